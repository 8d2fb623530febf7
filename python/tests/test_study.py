"""nsmodal.study (issue 27): basins of attraction over an executor, into one
HDF5 dataset; answers known in closed form or confirmed by longer runs."""
import importlib.util
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import nsmodal
import nsmodal.study as study
from nsmodal import _nsmodal


def oscillator(gap, w=1.2, a=0.3, zeta=0.05):
    # m x'' + c x' + k x = a cos(w t), m = k = 1, a wall at x = gap.
    return nsmodal.Model(masses=[1], springs=[1], gap=gap, restitution=0.8, damping_ratios=[zeta],
                         forcing_amplitude=[a], forcing_frequency=w)


GRID = {"x1": (-3, 3, 16), "v1": (-3, 3, 16)}


def test_a_linear_oscillator_has_one_attractor_its_steady_state():
    w, a, zeta = 1.2, 0.3, 0.05
    r = study.basin(oscillator(100.0, w, a, zeta), GRID, periods=300)
    assert np.all(r["attractor"] == 0) and len(r["attractors"]) == 1
    t = r["attractors"][0]
    assert t["period"] == 1 and t["impacts"] == 0 and t["share"] == 1.0
    X = a / (1 - w**2 + 2j * zeta * w)  # x = Re(X e^{i w t}): the state at the stroboscopic t = 0 (mod 2 pi / w)
    # (1e-9: the transient after 300 periods is e^{-zeta * 300 * 2 pi / w} ~ 1e-34 of its start;
    # what remains is the exact integrator's round-off.)
    assert np.allclose(t["state"], [X.real, (1j * w * X).real], rtol=0, atol=1e-9)


def test_an_impact_oscillator_has_two_coexisting_responses_confirmed_by_longer_runs():
    m = oscillator(1.0)
    r = study.basin(m, GRID, periods=300)
    kinds = sorted((t["period"], t["impacts"]) for t in r["attractors"])
    assert kinds == [(1, 0), (1, 1)], r["attractors"]
    assert all(t["share"] > 0.05 for t in r["attractors"])
    # Each is the stable, admissible orbit `response` locates, solved from its
    # simulated impact times (1e-6: the settled motion repeats to 1e-6 of its
    # scale; its impact times follow).
    for t in r["attractors"]:
        assert t["orbit_found"] and t["orbit_admissible"] and t["orbit_stable"], t
        assert t["orbit_time_error"] < 1e-6, t
    # Starts beyond the wall (x1 > d = 1) are no motion: -2.
    assert np.all((r["attractor"] == -2) == (r["x1"][:, None] > 1.0) * np.ones((1, 16), bool))
    # Ten points of each basin settle on the same attractor over 2,000 periods.
    states = []
    labels = []
    for t in r["attractors"]:
        i, j = np.nonzero(r["attractor"] == t["id"])
        for k in np.linspace(0, len(i) - 1, 10).astype(int):
            states.append([r["x1"][i[k]], r["v1"][j[k]]])
            labels.append(t)
    long = _nsmodal._settle(m, np.array(states), 2000)
    for k, t in enumerate(labels):
        assert long["period"][k] == t["period"] and len(long["impact_contacts"][k]) == t["impacts"]
        # (1e-6: the classification's own repetition tolerance.)
        assert np.max(np.abs(long["state"][k] - t["state"])) < 1e-6


def read(path):
    import h5py
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: out.__setitem__(name, obj[()]) if hasattr(obj, "shape") else None)
        out["attrs"] = {k: f.attrs[k] for k in f.attrs}
    return out


def same(a, b):
    assert a.keys() == b.keys()
    for k in a:
        if k == "attrs":
            assert a[k].keys() == b[k].keys() and all(str(a[k][x]) == str(b[k][x]) for x in a[k])
        elif a[k].dtype == object:  # one array per attractor (its impacts)
            assert len(a[k]) == len(b[k]) and all(np.array_equal(x, y) for x, y in zip(a[k], b[k])), k
        else:
            assert np.array_equal(a[k], b[k]), k


def test_the_dataset_is_the_same_from_one_worker_two_processes_and_a_resumed_run(tmp_path):
    m = oscillator(1.0)
    grid = {"x1": (-3, 3, 30), "v1": (-3, 3, 30)}  # 900 points: 3 chunks
    study.basin(m, grid, periods=200, out=str(tmp_path / "one"))
    study.basin(m, grid, periods=200, out=str(tmp_path / "two"), workers=2)
    one = read(tmp_path / "one" / "study.h5")
    same(one, read(tmp_path / "two" / "study.h5"))
    # Interrupted: the second chunk raises; the others are kept, no dataset.
    real = study._settle_chunk

    def failing(model, states, *args):
        if states[0, 0] == study.np.linspace(-3, 3, 30)[400 // 30]:
            raise RuntimeError("injected")
        return real(model, states, *args)

    study._settle_chunk = failing
    try:
        with pytest.raises(study.StudyError, match=r"1 chunk\(s\) failed[\s\S]*chunk 1: points 400 to 799"):
            study.basin(m, grid, periods=200, out=str(tmp_path / "resumed"))
    finally:
        study._settle_chunk = real
    assert not (tmp_path / "resumed" / "study.h5").exists()
    assert sorted(os.listdir(tmp_path / "resumed" / "chunks")) == ["chunk_000000.npz", "chunk_000002.npz",
                                                                   "study.json"]
    study.basin(m, grid, periods=200, out=str(tmp_path / "resumed"))
    same(one, read(tmp_path / "resumed" / "study.h5"))
    # Another request into the same directory is refused, naming it.
    with pytest.raises(study.StudyError, match="out: .* holds the chunks of another study"):
        study.basin(m, grid, periods=300, out=str(tmp_path / "resumed"))


@pytest.mark.skipif(importlib.util.find_spec("distributed") is None, reason="Dask distributed is not installed")
def test_the_dataset_is_the_same_from_a_dask_local_cluster(tmp_path):
    m = oscillator(1.0)
    grid = {"x1": (-3, 3, 30), "v1": (-3, 3, 30)}
    study.basin(m, grid, periods=200, out=str(tmp_path / "one"))
    study.basin(m, grid, periods=200, out=str(tmp_path / "dask"), workers=2, executor="dask")
    same(read(tmp_path / "one" / "study.h5"), read(tmp_path / "dask" / "study.h5"))


@pytest.mark.skipif(importlib.util.find_spec("mpi4py") is None or shutil.which("mpiexec") is None,
                    reason="mpi4py or mpiexec is not installed")
def test_the_dataset_is_the_same_under_mpiexec(tmp_path):
    scene = tmp_path / "one.toml"
    scene.write_text("[system]\nmasses = [1.0]\nsprings = [1.0]\ngap = 1.0\nrestitution = 0.8\n"
                     "damping_ratios = [0.05]\n[forcing]\namplitude = [0.3]\nfrequency = 1.2\n")
    args = ["basin", str(scene), "--grid", "x1=-3:3:30", "--grid", "v1=-3:3:30", "--periods", "200"]
    env = dict(os.environ)
    subprocess.run([sys.executable, "-m", "nsmodal.study", *args, "--out", str(tmp_path / "one")], check=True, env=env)
    subprocess.run(["mpiexec", "--oversubscribe", "--allow-run-as-root", "-n", "3", sys.executable, "-m",
                    "mpi4py.futures", "-m", "nsmodal.study", *args, "--out", str(tmp_path / "mpi"),
                    "--executor", "mpi", "--workers", "2"], check=True, env=env, timeout=300)
    same(read(tmp_path / "one" / "study.h5"), read(tmp_path / "mpi" / "study.h5"))


def test_bad_requests_name_their_argument(tmp_path):
    m = oscillator(1.0)
    with pytest.raises(study.StudyError, match="grid: 'y1' is not a coordinate"):
        study.basin(m, {"y1": (0, 1, 5), "v1": (0, 1, 5)})
    with pytest.raises(study.StudyError, match="grid: v1: COUNT"):
        study.basin(m, {"x1": (0, 1, 5), "v1": (0, 1, 1.5)})
    with pytest.raises(study.StudyError, match="grid: a study needs two different coordinates"):
        study.basin(m, {"x1": (0, 1, 5)})
    with pytest.raises(study.StudyError, match="executor: must be one of"):
        study.basin(m, GRID, executor="threads")
    with pytest.raises(study.StudyError, match="scheduler: is for the dask executor"):
        study.basin(m, GRID, scheduler="tcp://localhost:8786")
    with pytest.raises(study.StudyError, match="periods: must exceed the window"):
        study.basin(m, GRID, periods=10)
    free = nsmodal.Model(masses=[1], springs=[1], gap=1, restitution=0.8, damping_ratios=[0.05])
    with pytest.raises(study.StudyError, match="forcing.amplitude: is needed"):
        study.basin(free, GRID, out=str(tmp_path / "free"))
    assert not (tmp_path / "free").exists()
    # The command line: exit 2 and the message.
    r = subprocess.run([sys.executable, "-m", "nsmodal.study", "basin", "nosuch.toml", "--grid", "x1=0:1:4",
                        "--grid", "v1=0:1:4", "--out", str(tmp_path / "cli")], capture_output=True, text=True)
    assert r.returncode == 2 and "error: scene: cannot read 'nosuch.toml'" in r.stderr, r.stderr


def test_a_parameter_grid_of_responses_holds_the_gap_scaling_law(tmp_path):
    # The response at force a and gap d is the one at a / d and gap 1 scaled
    # by d: the same peak frequency, its energy times d^2. The grid's
    # (amplitude, gap) = (0.4, 2) is then its (0.2, 1), each a grid point of
    # its own (the coordinates' order checked with it).
    m = nsmodal.load_scene(os.path.join(os.environ["NSMODAL_SOURCE_DIR"], "configs", "forced.toml"))
    grid = {"amplitude": (0.2, 0.4, 2), "gap": (1, 2, 2)}
    r = study.grid(m, grid, frequency=(0.4, 1.0, 0.01), out=str(tmp_path / "one"))
    assert r["peak_energy"].shape == (2, 2) and list(r["amplitude"]) == [0.2, 0.4] and list(r["gap"]) == [1, 2]
    # (1e-9: both responses solved to 1e-13 of the gap; the energies follow.)
    assert abs(r["peak_energy"][1, 1] - 4 * r["peak_energy"][0, 0]) < 1e-9 * r["peak_energy"][1, 1]
    assert abs(r["peak_frequency"][1, 1] - r["peak_frequency"][0, 0]) < 1e-9
    assert r["folds"][1, 1] == r["folds"][0, 0]
    # The same dataset from two processes.
    study.grid(m, grid, frequency=(0.4, 1.0, 0.01), out=str(tmp_path / "two"), workers=2)
    same(read(tmp_path / "one" / "study.h5"), read(tmp_path / "two" / "study.h5"))


def test_a_parameter_grid_refuses_what_leaves_the_model():
    m = nsmodal.load_scene(os.path.join(os.environ["NSMODAL_SOURCE_DIR"], "configs", "forced.toml"))
    with pytest.raises(study.StudyError, match="grid: parameter: 'stiffness' is not a parameter"):
        study.grid(m, {"stiffness": (1, 2, 2), "gap": (1, 2, 2)}, frequency=(0.4, 1.0, 0.01))
    with pytest.raises(study.StudyError, match="grid: at amplitude = 0.2, gap = -1: "):
        study.grid(m, {"amplitude": (0.2, 0.4, 2), "gap": (-1, 2, 2)}, frequency=(0.4, 1.0, 0.01))
    with pytest.raises(study.StudyError, match="grid: frequency cannot be a grid axis"):
        study.grid(m, {"amplitude": (0.2, 0.4, 2), "frequency": (0.5, 1, 2)}, frequency=(0.4, 1.0, 0.01))
    free = nsmodal.load_scene(os.path.join(os.environ["NSMODAL_SOURCE_DIR"], "configs", "paper.toml"))
    with pytest.raises(study.StudyError, match="model: the response analysis needs a forced model"):
        study.grid(free, {"gap": (1, 2, 2), "springs[2]": (1, 2, 2)}, frequency=(0.4, 1.0, 0.01))
    with pytest.raises(study.StudyError, match="analysis: must be one of"):
        study.grid(m, {"amplitude": (0.2, 0.4, 2), "gap": (1, 2, 2)}, analysis="atlas")
    with pytest.raises(study.StudyError, match="analysis: .*frequency"):
        study.grid(m, {"amplitude": (0.2, 0.4, 2), "gap": (1, 2, 2)}, frequency=(1.0, 0.4, 0.01))


def test_a_subharmonic_attractor_is_the_analytic_orbit_of_its_sequence():
    # configs/forced.toml at w = 0.5: every start settles on a motion of two
    # forcing periods with one impact, the (1, 2) response.
    m = nsmodal.load_scene(os.path.join(os.environ["NSMODAL_SOURCE_DIR"], "configs", "forced.toml"))
    r = study.basin(m, {"x1": (-1, 0.5, 6), "v1": (-1, 1, 6)}, periods=400)
    assert [(t["period"], t["impacts"]) for t in r["attractors"]] == [(2, 1)]
    t = r["attractors"][0]
    assert t["orbit_found"] and t["orbit_admissible"] and t["orbit_stable"] and t["orbit_time_error"] < 1e-6, t


def test_a_basin_on_the_impact_section_finds_the_coexisting_responses_and_each_impact_is_its_own_attractor():
    # The 1-dof oscillator's two responses (a non-impacting one, a one-impact
    # one) from starts on the wall: phase w t0 in [0, 2 pi), velocity into the
    # wall v in (0, 2.5].
    m = oscillator(1.0)
    w = m.forcing_frequency
    r = study.basin(m, {"phase": (0, 2 * np.pi * 15 / 16, 16), "impact_velocity": (0.1, 2.5, 12)}, periods=300)
    assert r["attractor"].shape == (16, 12) and r["contact"] == 1
    on_states = study.basin(m, GRID, periods=300)["attractors"]
    kinds = sorted((t["period"], t["impacts"]) for t in r["attractors"])
    assert kinds == [(1, 0), (1, 1)], r["attractors"]
    # The same attractors as from the state plane (1e-6: the repetition tolerance).
    for t in r["attractors"]:
        twin = [u for u in on_states if (u["period"], u["impacts"]) == (t["period"], t["impacts"])][0]
        assert np.max(np.abs(t["state"] - twin["state"])) < 1e-6
    # The one-impact attractor's own impact, as a start, is on the attractor
    # from the first period: after 10 periods it has settled to 1e-6 (from
    # anywhere else the transient decays as e^(-zeta t): 0.05 over 10
    # periods, not settled), with the same impact (its phase to 1e-6 rad and
    # velocity to 1e-6 of it: the settled motion's repetition).
    hit = [t for t in r["attractors"] if t["impacts"] == 1][0]
    phase, v = float(hit["impact_phases"][0]), float(hit["impact_velocities"][0])
    assert v > 0
    own = study.basin(m, {"phase": (phase, phase + 1e-9, 2), "impact_velocity": (v, v + 1e-9, 2)}, periods=10,
                      window=8)
    assert np.all(own["attractor"] == 0) and own["attractors"][0]["impacts"] == 1
    assert abs(own["attractors"][0]["impact_phases"][0] - phase) < 1e-6
    assert abs(own["attractors"][0]["impact_velocities"][0] - v) < 1e-6 * v
    # Its stroboscopic state is where a simulation started on that impact at
    # t0 = phase / w reaches at the next multiple of 2 pi / w (1e-9: the exact
    # flight's round-off over one period).
    tf = 2 * np.pi / w
    s = nsmodal.simulate(m, [1.0], [v], t_span=(phase / w, 3 * tf), t_eval=[2 * tf, 3 * tf])["trajectory"]
    assert abs(s["x1"][1] - s["x1"][0]) < 1e-6 and abs(s["x1"][1] - hit["state"][0]) < 1e-6
    # Points of each basin confirmed by 2,000-period runs from the same starts.
    starts, phases, labels = [], [], []
    for t in r["attractors"]:
        i, j = np.nonzero(r["attractor"] == t["id"])
        for k in np.linspace(0, len(i) - 1, 6).astype(int):
            starts.append([1.0, r["impact_velocity"][j[k]]])
            phases.append(np.mod(r["phase"][i[k]], 2 * np.pi))
            labels.append(t)
    long = _nsmodal._settle(m, np.array(starts), 2000, phases=np.array(phases))
    for k, t in enumerate(labels):
        assert long["period"][k] == t["period"] and len(long["impact_contacts"][k]) == t["impacts"]
        assert np.max(np.abs(long["state"][k] - t["state"])) < 1e-6


def test_a_section_basin_refuses_a_mixed_grid_a_bad_contact_and_a_velocity_away_from_the_wall():
    m = oscillator(1.0)
    with pytest.raises(study.StudyError, match="not both, got phase and x1"):
        study.basin(m, {"phase": (0, 1, 2), "x1": (0, 1, 2)}, periods=100)
    with pytest.raises(study.StudyError, match="impact_velocity: must be > 0 .* got FROM = -1"):
        study.basin(m, {"phase": (0, 1, 2), "impact_velocity": (-1, 1, 2)}, periods=100)
    with pytest.raises(study.StudyError, match="contact: must be a contact of the model, 1 to 1, got 2"):
        study.basin(m, {"phase": (0, 1, 2), "impact_velocity": (0.5, 1, 2)}, periods=100, contact=2)
    with pytest.raises(study.StudyError, match="'y1' is not a coordinate of the state .* impact section"):
        study.basin(m, {"y1": (0, 1, 2), "impact_velocity": (0.5, 1, 2)}, periods=100)


def test_a_parameter_grid_of_basins_is_each_points_basin(tmp_path):
    # The one-mass oscillator with its wall at d = 1 (two coexisting
    # responses) and far away (d = 100: the linear steady state alone), at two
    # forcing levels: each grid point's summary is the basin computed there
    # on its own.
    m = oscillator(1.0)
    states = {"x1": (-3, 1, 8), "v1": (-3, 3, 8)}
    r = study.grid(m, {"gap": (1, 100, 2), "amplitude": (0.3, 0.35, 2)}, analysis="basin", states=states,
                   periods=200, out=str(tmp_path / "g"))
    assert r["attractors"].shape == (2, 2)
    assert np.all(r["attractors"][1] == 1) and np.all(r["impacting_share"][1] == 0)
    assert np.all(r["largest_share"][1] == 1.0)
    for j, a in enumerate(r["amplitude"]):
        alone = study.basin_summary(nsmodal.with_parameter(m, "amplitude", float(a)), states, periods=200)
        assert {k: r[k][0, j] for k in alone} == alone
    assert r["attractors"][0, 0] == 2 and 0 < r["impacting_share"][0, 0] < 1
    cli = subprocess.run([sys.executable, "-m", "nsmodal.study", "grid", os.path.join(
        os.environ.get("NSMODAL_SOURCE_DIR", "."), "configs", "oscillator.toml"), "--grid", "gap=1:100:2",
        "--grid", "amplitude=0.3:0.35:2", "--analysis", "basin", "--states", "x1=-3:1:8", "--states", "v1=-3:3:8",
        "--periods", "200", "--out", str(tmp_path / "c")], capture_output=True, text=True)
    assert cli.returncode == 0, cli.stderr
    got = read(tmp_path / "c" / "study.h5")
    assert np.array_equal(got["impacting_share"], r["impacting_share"])
    bad = subprocess.run([sys.executable, "-m", "nsmodal.study", "grid", "x.toml", "--grid", "gap=1:2:2", "--grid",
                          "amplitude=0.3:0.4:2", "--analysis", "basin", "--out", str(tmp_path / "b")],
                         capture_output=True, text=True)
    assert bad.returncode == 2 and "--analysis basin needs --states" in bad.stderr
