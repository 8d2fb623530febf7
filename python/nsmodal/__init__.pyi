# Type stubs of nsmodal (PEP 561; the package carries py.typed). The
# parameters' names, kinds and defaults are those of the compiled module:
# python/tests/test_stubs.py compares them with inspect.signature of each.
# Tables are dicts of 1-D NumPy arrays keyed as the CLI's CSV columns.
from os import PathLike
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
Table = dict[str, Any]
# A period grid: (from, to, step), "FROM:TO:STEP", one value, or an evenly
# spaced array.
Grid = Union[tuple[float, float, float], str, float, npt.NDArray[np.float64]]
Progress = Optional[Callable[[int, int], Any]]
ContactSpec = Mapping[str, Any]  # dof/side, between or normal; gap; restitution

class Model:
    """A linear system of masses and springs with rigid stops (see help(nsmodal.Model))."""

    def __init__(
        self,
        masses: Optional[ArrayLike] = None,
        springs: Optional[ArrayLike] = None,
        mass_matrix: Optional[ArrayLike] = None,
        stiffness_matrix: Optional[ArrayLike] = None,
        *,
        gap: Optional[float] = None,
        restitution: Optional[float] = None,
        contact_dof: Optional[int] = None,
        contacts: Optional[Sequence[ContactSpec]] = None,
        rayleigh_damping: Optional[tuple[float, float]] = None,
        damping_ratios: Optional[ArrayLike] = None,
        damping_matrix: Optional[ArrayLike] = None,
        forcing_amplitude: Optional[ArrayLike] = None,
        forcing_frequency: Optional[float] = None,
        forcing_constant: Optional[ArrayLike] = None,
    ) -> None: ...
    def replace(self, **changes: Any) -> Model: ...
    def __getstate__(self) -> tuple[Any, ...]: ...
    def __setstate__(self, state: tuple[Any, ...]) -> None: ...
    @property
    def dofs(self) -> int: ...
    @property
    def mass_matrix(self) -> npt.NDArray[np.float64]: ...
    @property
    def stiffness_matrix(self) -> npt.NDArray[np.float64]: ...
    @property
    def damping_matrix(self) -> npt.NDArray[np.float64]: ...
    @property
    def contact_dof(self) -> int: ...
    @property
    def gap(self) -> float: ...
    @property
    def restitution(self) -> float: ...
    @property
    def contacts(self) -> list[dict[str, Any]]: ...
    @property
    def forcing_amplitude(self) -> npt.NDArray[np.float64]: ...
    @property
    def forcing_constant(self) -> npt.NDArray[np.float64]: ...
    @property
    def forcing_frequency(self) -> float: ...
    @property
    def linear_periods(self) -> npt.NDArray[np.float64]: ...

class ModalTruncation:
    """A model on its first linear modes, with the maps to and from the full model's dofs."""

    def contact_bound(self, energy: float) -> float: ...
    @property
    def model(self) -> Model: ...
    @property
    def dofs(self) -> int: ...
    @property
    def kept(self) -> int: ...
    @property
    def to_physical(self) -> npt.NDArray[np.float64]: ...
    @property
    def from_physical(self) -> npt.NDArray[np.float64]: ...
    @property
    def residual_flexibility(self) -> float: ...
    @property
    def highest_kept_frequency(self) -> float: ...
    @property
    def lowest_neglected_frequency(self) -> float: ...

def bar(
    *,
    length: float,
    youngs_modulus: float,
    density: float,
    area: float,
    elements: int,
    boundary: str = "fixed-free",
    mass: str = "consistent",
    contact_dof: Optional[int] = None,
    gap: Optional[float] = None,
    restitution: Optional[float] = None,
    contacts: Optional[Sequence[ContactSpec]] = None,
) -> Model: ...
def load_scene(path: Union[str, PathLike[str]]) -> Model: ...
def load_settings(path: Union[str, PathLike[str]]) -> dict[str, dict[str, Any]]: ...
def scenes() -> list[str]: ...
def settings() -> list[dict[str, Any]]: ...
def stack(table: Mapping[str, Any], name: str) -> npt.NDArray[Any]: ...
def orbits(
    model: Model,
    impacts: int = 1,
    *,
    period: Grid,
    stability: str = "potential",
    threads: int = 0,
    all_multipliers: bool = True,
    progress: Progress = None,
    sequence: Optional[Sequence[int]] = None,
) -> Table: ...
def orbit(
    model: Model, period: float, impacts: int = 1, sequence: Optional[Sequence[int]] = None
) -> list[dict[str, Any]]: ...
def multipliers(
    model: Model, period: float, impacts: int = 1, t2: Optional[float] = None
) -> npt.NDArray[np.complex128]: ...
def transitions(model: Model, period: Grid) -> Table: ...
def atlas(model: Model, period: Grid, threads: int = 0, progress: Progress = None) -> dict[str, Any]: ...
def truncate(
    model: Model,
    *,
    modes: Optional[int] = None,
    contact_tolerance: Optional[float] = None,
    energy: Optional[float] = None,
) -> ModalTruncation: ...
def simulate(
    model: Model,
    x0: Optional[ArrayLike] = None,
    v0: Optional[ArrayLike] = None,
    *,
    on_impact: Optional[Callable[[float, npt.NDArray[np.float64], npt.NDArray[np.float64]], Any]] = None,
    progress: Optional[Callable[[float, float], Any]] = None,
    t_span: Optional[tuple[float, float]] = None,
    t_eval: Optional[ArrayLike] = None,
    integrator: str = "exact",
    t_end: float = 100.0,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    method: str = "adams",
    step: float = 0.001,
    theta: float = 0.5,
    root_tol: float = 1e-14,
    sample_dt: float = 0.01,
    modes: Optional[int] = None,
    contact_tolerance: Optional[float] = None,
) -> dict[str, Any]: ...
def validate(
    model: Model,
    period: Optional[Grid] = None,
    *,
    progress: Progress = None,
    impacts: Sequence[int] = [1, 2],
    sequence: str = "",
    periods: int = 1000,
    integrators: Sequence[str] = ["exact"],
    rtol: float = 1e-10,
    atol: float = 1e-12,
    step: float = 0.0001,
    root_tol: float = 1e-14,
    threads: int = 0,
) -> dict[str, Any]: ...
def response(
    model: Model,
    impacts: int = 1,
    periods: int = 1,
    frequency: Optional[Grid] = None,
    amplitude: Optional[Grid] = None,
    backbone: bool = True,
    validate: int = 0,
    integrators: Sequence[str] = ["exact"],
    threads: int = 0,
    sequence: Optional[Sequence[int]] = None,
) -> dict[str, Any]: ...
def continue_parameter(
    model: Model,
    parameter: str,
    range: Union[tuple[float, float], tuple[float, float, float], str],
    impacts: int = 1,
    periods: int = 1,
    sequence: Optional[Sequence[int]] = None,
    period: Optional[Union[tuple[float, float, float], str]] = None,
) -> dict[str, Any]: ...
def with_parameter(model: Model, parameter: str, value: float) -> Model: ...
def follow_curve(
    model: Model,
    parameter: str,
    range: Union[tuple[float, float], tuple[float, float, float], str],
    second: str,
    second_range: Union[tuple[float, float], tuple[float, float, float], str],
    follow: str,
    impacts: int = 1,
    periods: int = 1,
    sequence: Optional[Sequence[int]] = None,
) -> dict[str, Any]: ...
