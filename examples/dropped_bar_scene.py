"""The dropped bar of issue 12, shared by dropped_bar.py and
modal_truncation.py: a free-free steel bar (L = 1 m, E = 210 GPa,
rho = 7800 kg/m^3, A = 3.14e-4 m^2, consistent mass) falling at V0 = 0.1 m/s
from GAP = 5e-5 m onto the ground at its end node, e = 0 there. The
continuous bar stays in contact CONTACT = 2 L / c and leaves at -V0."""
import numpy as np

import nsmodal

L, E, RHO, A = 1.0, 210e9, 7800.0, 3.14e-4
V0, GAP = 0.1, 5e-5
C = np.sqrt(E / RHO)
CONTACT = 2.0 * L / C
T_END = GAP / V0 + 2.0 * CONTACT  # the fall, the contact, as long again in flight


def model(elements):
    """The bar's model with `elements` linear elements (elements + 1 dofs)."""
    return nsmodal.bar(length=L, youngs_modulus=E, density=RHO, area=A, elements=elements, boundary="free-free",
                       gap=GAP, restitution=0.0)


def rebound_over_v0(bar, velocity):
    """The bar's momentum over its mass, relative to V0, for nodal velocities."""
    mass = bar.mass_matrix
    return float(mass.sum(axis=0) @ np.asarray(velocity) / mass.sum()) / V0
