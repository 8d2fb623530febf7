"""Studies that outgrow one call (issue 27): basins of attraction, split into
chunks run by an executor the user chooses, gathered into one HDF5 dataset.

``basin(model, grid, periods=500, out=DIR)`` simulates (exact integrator) a
grid of initial states over ``periods`` forcing periods and classifies each by
the attractor it settles on (``nsmodal._settle``: the smallest stroboscopic
period n <= window / 2 whose samples repeat to ``tol``; -1 where none does).
Two points share an attractor when their periods, impact sequences and
canonical stroboscopic states agree (to 1e-4 of the motion's scale). The
attractors are numbered in a canonical order (period, impacts, sequence,
state), so the dataset does not depend on how the work was split or run.

Executors: ``processes`` (a process pool on this machine; 1 worker runs in
this process), ``dask`` (distributed: a LocalCluster of ``workers``
processes, or the scheduler at ``scheduler``), ``mpi`` (mpi4py's
MPIPoolExecutor: run under ``mpiexec -n K python3 -m mpi4py.futures -m
nsmodal.study ...``). Each finished chunk is saved in ``DIR/chunks``; a study
run again with the same request resumes where it stopped. A chunk that
raises is reported with its grid points and the rest completes; the dataset
``DIR/study.h5`` is written only when every chunk has.

``grid(model, {"amplitude": (from, to, count), "gap": ...}, analysis="response",
frequency=(from, to, step))`` runs an analysis (the frequency response's
summary, or any picklable function of the model) at every point of a grid of
two scene parameters, the same way.

Command line: ``python3 -m nsmodal.study basin SCENE --grid NAME=FROM:TO:COUNT
--grid NAME=FROM:TO:COUNT --periods P --out DIR [--workers N] [--executor
processes|dask|mpi] [--scheduler ADDR]``; ``python3 -m nsmodal.study grid SCENE
--grid NAME=FROM:TO:COUNT --grid NAME=FROM:TO:COUNT --frequency FROM:TO:STEP
--out DIR [--impacts M] [--periods N] [--workers N] [--executor ...]``.
"""
import argparse
import concurrent.futures
import hashlib
import json
import multiprocessing
import os
import pickle
import sys

import numpy as np

from . import _nsmodal

__all__ = ["basin", "grid", "response_summary", "basin_summary", "StudyError", "EXECUTORS", "ANALYSES"]

EXECUTORS = ("processes", "dask", "mpi")
MATCH_TOL = 1e-4  # states of one attractor: the same to this fraction of the motion's scale
CHUNK_POINTS = 400  # points per chunk (fixed: a resumed study finds its chunks whatever the workers)
GRID_CHUNK_POINTS = 10  # parameter-grid points per chunk (an analysis each: a response curve takes ~0.5 s)


class StudyError(ValueError):
    """A study that could not be run or completed (bad input, failed chunks)."""


def _state_names(dofs):
    return [f"x{i + 1}" for i in range(dofs)] + [f"v{i + 1}" for i in range(dofs)]


# The impact section's coordinates: the forcing phase w t of the start (rad)
# and the velocity into the wall just before the impact there (m/s).
SECTION = ("phase", "impact_velocity")


def _parse_grid(grid, dofs):
    """Two state coordinates (x1, v2, ...), or the impact section's two
    (phase, impact_velocity), with their ranges and counts."""
    names = _state_names(dofs)

    def check(name):
        if name not in names and name not in SECTION:
            raise ValueError(f"{name!r} is not a coordinate of the state ({', '.join(names)}) or of the impact "
                             f"section ({', '.join(SECTION)})")

    axes = _parse_axes(grid, check)
    section = [name in SECTION for name, *_ in axes]
    if any(section) and not all(section):
        raise StudyError(f"grid: a basin is over two state coordinates or over the impact section's "
                         f"{' and '.join(SECTION)}, not both, got {axes[0][0]} and {axes[1][0]}")
    for name, lo, _, _ in axes:
        if name == "impact_velocity" and not lo > 0:
            raise StudyError(f"grid: impact_velocity: must be > 0 (the velocity into the wall before the impact), "
                             f"got FROM = {lo:g}")
    return axes


def _impacts(count):
    return f"{count} impact" + ("" if count == 1 else "s")


def _coordinate_unit(name):
    return "rad" if name == "phase" else "m" if name.startswith("x") else "m/s"


def _floats(text):
    """The numbers of a chunk's comma-joined field ("" for none)."""
    return [float(x) for x in text.split(",")] if text else []


def _load(model):
    """(the Model, the scene file's text or None) from a Model or a scene path."""
    if isinstance(model, (str, os.PathLike)):
        path = os.fspath(model)
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise StudyError(f"scene: cannot read {path!r}: {e.strerror}") from None
        return _nsmodal.load_scene(path), text
    if not isinstance(model, _nsmodal.Model):
        raise StudyError(f"model: must be an nsmodal.Model or a scene path, got {type(model).__name__}")
    return model, None


def _settle_chunk(model, states, periods, window, tol, phases=None):
    # (Top level: the executors pickle it by name.)
    return _nsmodal._settle(model, states, periods, window, tol, phases)


def _basin_chunk(model, states, periods, window, tol, phases=None):
    r = _settle_chunk(model, states, periods, window, tol, phases)

    def joined(rows):
        return np.array([",".join(repr(float(t)) for t in ts) for ts in rows], dtype="U")

    return {"period": np.asarray(r["period"], dtype=np.int64), "state": np.asarray(r["state"]),
            "repetition": np.asarray(r["repetition"]), "rough": np.asarray(r["zeno_or_sticking"], dtype=bool),
            "contacts": np.array([",".join(map(str, c)) for c in r["impact_contacts"]], dtype="U"),
            "times": joined(r["impact_times"]), "velocities": joined(r["impact_velocities"])}


def _run_chunks(out, request, tasks, describe, workers, executor, scheduler, progress=True):
    """Runs tasks [(fn, args)] (one a chunk; each returns a dict of arrays)
    over the executor; with `out`, each finished chunk is kept in
    out/chunks and a run of the same request resumes from them. Returns the
    chunks' results in order; raises StudyError naming the failed chunks
    (describe(i): its points) once the others have completed."""
    key = hashlib.sha256(json.dumps(request, sort_keys=True).encode()).hexdigest()
    chunk_dir = None
    results = {}
    if out is not None:
        chunk_dir = os.path.join(out, "chunks")
        os.makedirs(chunk_dir, exist_ok=True)
        for stale in os.listdir(out):
            if stale.startswith(("study.h5", "basin.", "grid.")):
                os.remove(os.path.join(out, stale))
        key_path = os.path.join(chunk_dir, "study.json")
        if os.path.exists(key_path):
            with open(key_path, encoding="utf-8") as f:
                if json.load(f).get("key") != key:
                    raise StudyError(f"out: {chunk_dir} holds the chunks of another study; give another directory "
                                     "or remove it")
        else:
            with open(key_path, "w", encoding="utf-8") as f:
                json.dump({"key": key, "request": {k: v for k, v in request.items() if k != "model"}}, f)
        for i in range(len(tasks)):
            p = os.path.join(chunk_dir, f"chunk_{i:06d}.npz")
            if os.path.exists(p):
                with np.load(p, allow_pickle=False) as d:
                    results[i] = {k: d[k] for k in d.files}
        if results:
            print(f"study: resuming: {len(results)} of {len(tasks)} chunks already done in {chunk_dir}",
                  file=sys.stderr)
    failures = []
    ex = _Executor(executor, workers, scheduler)
    try:
        futures = {ex.submit(fn, *args): i for i, (fn, args) in enumerate(tasks) if i not in results}
        if progress:
            _progress(len(results), len(tasks))
        for f in ex.as_completed(list(futures)):
            i = futures[f]
            try:
                r = f.result()
            except Exception as e:  # noqa: BLE001  (reported with its chunk; the rest completes)
                failures.append(f"chunk {i}: {describe(i)}: {type(e).__name__}: {e}")
                continue
            results[i] = r
            if chunk_dir is not None:
                _atomic_save(os.path.join(chunk_dir, f"chunk_{i:06d}.npz"), **r)
            if progress:
                _progress(len(results), len(tasks))
    except KeyboardInterrupt:
        raise StudyError(f"interrupted: {len(results)} of {len(tasks)} chunks done"
                         + (f" and kept in {chunk_dir}: run the same study again to resume" if chunk_dir else ""))
    finally:
        ex.close()
    if failures:
        raise StudyError(f"{len(failures)} chunk(s) failed (the others are kept"
                         + (f" in {chunk_dir}" if chunk_dir else "") + "):\n  " + "\n  ".join(sorted(failures)))
    return [results[i] for i in range(len(tasks))]


class _Executor:
    """submit(fn, *args) -> future, as concurrent.futures; close()."""

    def __init__(self, kind, workers, scheduler):
        self.kind, self.client, self.pool = kind, None, None
        if kind == "processes":
            if workers > 1:
                self.pool = concurrent.futures.ProcessPoolExecutor(
                    max_workers=workers, mp_context=multiprocessing.get_context("spawn"))
        elif kind == "dask":
            try:
                from distributed import Client, LocalCluster
            except ImportError:
                raise StudyError("executor: 'dask' needs Dask distributed (Debian: python3-distributed; "
                                 "bash scripts/setup.sh installs it)") from None
            if scheduler:
                self.client = Client(scheduler)
            else:
                self.cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                            dashboard_address=None)
                self.client = Client(self.cluster)
        elif kind == "mpi":
            try:
                from mpi4py.futures import MPIPoolExecutor
            except ImportError:
                raise StudyError("executor: 'mpi' needs mpi4py (Debian: python3-mpi4py; bash scripts/setup.sh "
                                 "installs it)") from None
            self.pool = MPIPoolExecutor(max_workers=workers)
        else:
            raise StudyError(f"executor: must be one of {', '.join(EXECUTORS)}, got {kind!r}")

    def submit(self, fn, *args):
        if self.client is not None:
            return self.client.submit(fn, *args, pure=False)
        if self.pool is not None:
            return self.pool.submit(fn, *args)
        f = concurrent.futures.Future()
        try:
            f.set_result(fn(*args))
        except Exception as e:  # noqa: BLE001  (reported with its chunk)
            f.set_exception(e)
        return f

    def as_completed(self, futures):
        if self.client is not None:
            from distributed import as_completed
            return as_completed(futures)
        return concurrent.futures.as_completed(futures)

    def close(self):
        if self.client is not None:
            self.client.close()
            if hasattr(self, "cluster"):
                self.cluster.close()
        if self.pool is not None:
            self.pool.shutdown(cancel_futures=True)


def _progress(done, count, stream=sys.stderr):
    if stream.isatty():
        stream.write(f"\rstudy: {done}/{count} chunks")
        if done == count:
            stream.write("\n")
        stream.flush()


def _atomic_save(path, **arrays):
    tmp = path + ".partial.npz"
    np.savez(tmp, **arrays)
    os.replace(tmp, path)


def _classify(period, state, contacts, rough, dofs):
    """Attractor numbers per point (canonical order) and the attractors' table
    (each with its first point's index, `first`)."""
    reps = []  # (key, state, scale, points) in grid order
    label = np.full(len(period), -1, dtype=np.int64)
    for k in np.flatnonzero(period > 0):
        key = (int(period[k]), tuple(contacts[k]))
        z = state[k]
        scale = max(1.0, float(np.max(np.abs(z))))
        for r, rep in enumerate(reps):
            if rep[0] == key and np.max(np.abs(rep[1] - z)) <= MATCH_TOL * max(scale, rep[2]):
                label[k] = r
                rep[3].append(k)
                break
        else:
            label[k] = len(reps)
            reps.append((key, z, scale, [k]))
    order = sorted(range(len(reps)), key=lambda r: (reps[r][0][0], len(reps[r][0][1]), reps[r][0][1],
                                                    tuple(np.round(reps[r][1], 9))))
    new = np.empty(len(reps), dtype=np.int64)
    new[order] = np.arange(len(reps))
    # Not a settled attractor: -1, or -3 when the run had Zeno or sticking
    # phases; -2 a start beyond a wall.
    unsettled = np.where(period < 0, -2, np.where(rough, -3, -1))
    ids = np.where(label >= 0, new[np.maximum(label, 0)] if len(reps) else -1, unsettled)
    table = [{"id": int(new[r]), "period": reps[r][0][0], "impacts": len(reps[r][0][1]),
              "sequence": ",".join(str(c) for c in reps[r][0][1]), "state": reps[r][1],
              "points": len(reps[r][3]), "first": reps[r][3][0],
              "zeno_or_sticking": bool(np.any(rough[reps[r][3]]))} for r in order]
    return ids, table


def _identify(model, table, times):
    """Each attractor's analytic orbit (nsmodal._identify): the orbit
    `response` locates, solved from the simulated impact times of the
    attractor's first point; its admissibility, stability and how far its
    impact times are from the simulated ones."""
    for t in table:
        ts = _floats(times[t["first"]])
        contacts = [int(c) for c in t["sequence"].split(",")] if t["sequence"] else []
        r = _nsmodal._identify(model, contacts, t["period"], ts)
        t["orbit_found"] = bool(r["found"])
        t["orbit_stable"] = bool(r.get("stable", False))
        t["orbit_admissible"] = bool(r.get("admissible", False))
        t["orbit_max_multiplier"] = float(r.get("max_multiplier", np.nan))
        t["orbit_time_error"] = float(r.get("time_error", 0.0 if r["found"] else np.nan))


def basin(model, grid, periods=500, out=None, workers=1, executor="processes", scheduler=None, window=32,
          tol=1e-6, base=None, contact=1, progress=True):
    """The basins of attraction of a forced model over a grid of two state
    coordinates (``{"x1": (from, to, count), "v1": (from, to, count)}``; the
    others from ``base``, an (x, v) of 2N values, zero by default), or over
    the impact section of contact ``contact`` (``{"phase": (from, to,
    count), "impact_velocity": (from, to, count)}``: each motion starts at
    t = phase / w on the wall, n . x = d, moving into it at n . v =
    impact_velocity > 0, the rest of the state from ``base`` (its component
    along n replaced); the Newton law strikes at once). ``progress``: the
    chunks' progress on a terminal's standard error.

    Returns {"attractor": (count_1, count_2) int array (-1: not settled, -2: a
    start beyond a wall, -3: not settled, with Zeno or sticking phases),
    coordinate arrays under their names, "attractors": list of dicts (id,
    period, impacts, sequence, state, points, share), "period": the
    stroboscopic period per point}; with ``out``, also writes out/study.h5
    and out/basin.png.
    """
    model, scene_text = _load(model)
    dofs = model.dofs
    axes = _parse_grid(grid, dofs)
    if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= 4096:
        raise StudyError(f"workers: must be a whole number from 1 to 4096, got {workers!r}")
    if executor not in EXECUTORS:
        raise StudyError(f"executor: must be one of {', '.join(EXECUTORS)}, got {executor!r}")
    if scheduler is not None and executor != "dask":
        raise StudyError(f"scheduler: is for the dask executor, got executor {executor!r}")
    z0 = np.zeros(2 * dofs) if base is None else np.asarray(base, dtype=float)
    if z0.shape != (2 * dofs,) or not np.all(np.isfinite(z0)):
        raise StudyError(f"base: must be 2N = {2 * dofs} finite values (x, v), got {base!r}")
    names = _state_names(dofs)
    coords = [np.linspace(lo, hi, count) for (_, lo, hi, count) in axes]
    n1, n2 = len(coords[0]), len(coords[1])
    first = np.repeat(coords[0], n2)
    second = np.tile(coords[1], n1)
    states = np.tile(z0, (n1 * n2, 1))
    section = axes[0][0] in SECTION
    phases = None
    if section:
        try:
            n, d = _nsmodal._contact_normal(model, contact)
        except (ValueError, TypeError) as e:
            raise StudyError(str(e)) from None
        by = dict(zip((axes[0][0], axes[1][0]), (first, second)))
        phases = np.mod(by["phase"], 2 * np.pi)
        unit = n / (n @ n)
        x, v = z0[:dofs], z0[dofs:]
        states[:, :dofs] = x + (d - n @ x) * unit
        states[:, dofs:] = v + np.outer(by["impact_velocity"] - n @ v, unit)
    else:
        states[:, names.index(axes[0][0])] = first
        states[:, names.index(axes[1][0])] = second
    # periods, window, tol and the model (a force to be stroboscopic in)
    # checked on one point before any work or file.
    try:
        _nsmodal._settle(model, states[:1], periods, window, tol, None if phases is None else phases[:1])
    except ValueError as e:
        raise StudyError(str(e)) from None
    request = {"study": "basin", "grid": [list(g) for g in axes], "periods": periods, "window": window,
               "tol": tol, "base": z0.tolist(), "chunk_points": CHUNK_POINTS, "model": pickle.dumps(model).hex()}
    if section:
        request["contact"] = contact
    chunks = [(s, min(s + CHUNK_POINTS, len(states))) for s in range(0, len(states), CHUNK_POINTS)]
    results = _run_chunks(out, request, [(_basin_chunk, (model, states[s:e], periods, window, tol,
                                                         None if phases is None else phases[s:e]))
                                         for s, e in chunks],
                          lambda i: f"points {chunks[i][0]} to {chunks[i][1] - 1} ({axes[0][0]} = "
                                    f"{first[chunks[i][0]]:g} .. {first[chunks[i][1] - 1]:g})",
                          workers, executor, scheduler, progress)
    period = np.concatenate([r["period"] for r in results])
    state = np.concatenate([r["state"] for r in results])
    contacts = [tuple(int(c) for c in s.split(",")) if s else () for r in results for s in r["contacts"]]
    rough = np.concatenate([r["rough"] for r in results])
    times = [s for r in results for s in r["times"]]
    velocities = [s for r in results for s in r["velocities"]]
    ids, table = _classify(period, state, contacts, rough, dofs)
    _identify(model, table, times)
    w = model.forcing_frequency
    for t in table:
        t["share"] = t["points"] / len(ids)
        # Its impacts over one period: forcing phase w t (mod 2 pi), velocity into the wall, contact.
        t["impact_phases"] = np.mod(w * np.asarray(_floats(times[t["first"]])), 2 * np.pi)
        t["impact_velocities"] = np.asarray(_floats(velocities[t["first"]]))
    result = {"attractor": ids.reshape(n1, n2), axes[0][0]: coords[0], axes[1][0]: coords[1],
              "attractors": table, "period": period.reshape(n1, n2)}
    if section:
        result["contact"] = contact
    if out is not None:
        _write_h5(os.path.join(out, "study.h5"), result, axes, model, scene_text, request, dofs)
        _draw(os.path.join(out, "basin"), result, axes, names)
    return result


# The analyses a parameter grid runs at each point: name -> (function of the
# model and the analysis's options returning named scalars, their units).
def response_summary(model, frequency, impacts=1, periods=1):
    """The frequency response's summary (nsmodal.response over the frequency
    grid `frequency`, no backbone): the peak of the admissible responses
    (largest energy, its frequency; NaN when no point is admissible), the
    folds and period doublings, the largest impact velocity of an admissible
    stable orbit (NaN: none), the share of admissible stable points."""
    r = _nsmodal.response(model, impacts=impacts, periods=periods, frequency=frequency, backbone=False)
    rows, pts = r["rows"], r["points"]
    ok = rows["admissible"].astype(bool)
    stable = ok & rows["stable"].astype(bool)
    kinds = np.asarray(pts["kind"], dtype=str)
    k = int(np.argmax(np.where(ok, rows["energy"], -np.inf))) if ok.any() else -1
    return {"peak_energy": float(rows["energy"][k]) if k >= 0 else np.nan,
            "peak_frequency": float(rows["w"][k]) if k >= 0 else np.nan,
            "folds": int(np.sum(kinds == "fold")),
            "period_doublings": int(np.sum(kinds == "period-doubling")),
            "max_impact_velocity": float(np.max(rows["impact_velocity"][stable])) if stable.any() else np.nan,
            "stable_share": float(np.mean(stable)) if len(stable) else 0.0}


def basin_summary(model, states, periods=500, window=32, tol=1e-6, base=None, contact=1):
    """A basin's summary (``basin(model, states, periods, ...)`` in this
    process, ``states`` its grid of two state or section coordinates): the
    number of attractors, the largest basin's share, the share of the
    starts that settle on an impacting attractor, the share that does not
    settle (-1 and -3), and the longest attractor period (forcing periods;
    0 when none settles)."""
    r = basin(model, states, periods=periods, window=window, tol=tol, base=base, contact=contact, progress=False)
    ids, table = r["attractor"], r["attractors"]
    impacting = [t["id"] for t in table if t["impacts"] > 0]
    return {"attractors": len(table),
            "largest_share": max((t["share"] for t in table), default=0.0),
            "impacting_share": float(np.mean(np.isin(ids, impacting))),
            "unsettled_share": float(np.mean((ids == -1) | (ids == -3))),
            "max_period": max((t["period"] for t in table), default=0)}


# Units of a grid's coordinates, by the parameter's key (before any index).
PARAMETER_UNITS = {"frequency": "rad/s", "amplitude": "N", "gap": "m", "restitution": "", "masses": "kg",
                   "springs": "N/m", "damping_ratios": "", "rayleigh_damping": "", "contact": ""}


ANALYSES = {"response": (response_summary, {"peak_energy": "J", "peak_frequency": "rad/s", "folds": "",
                                            "period_doublings": "", "max_impact_velocity": "m/s",
                                            "stable_share": ""}),
            "basin": (basin_summary, {"attractors": "", "largest_share": "", "impacting_share": "",
                                      "unsettled_share": "", "max_period": "forcing periods"})}


def _grid_chunk(model, names, values, analysis, options):
    """One chunk of a parameter grid: the analysis at each (value_1, value_2)."""
    fn = ANALYSES[analysis][0] if isinstance(analysis, str) else analysis
    out = {}
    for k, (v1, v2) in enumerate(values):
        m = _nsmodal.with_parameter(_nsmodal.with_parameter(model, names[0], float(v1)), names[1], float(v2))
        for key, value in fn(m, **options).items():
            if not np.isscalar(value) and np.ndim(value) != 0:
                raise StudyError(f"analysis: must return scalars, got {key!r} of shape {np.shape(value)}")
            out.setdefault(key, []).append(value)
        if any(len(v) != k + 1 for v in out.values()):
            raise StudyError(f"analysis: returned other keys at {names[0]} = {v1:g}, {names[1]} = {v2:g}")
    return {key: np.asarray(v) for key, v in out.items()}


def grid(model, grid, analysis="response", out=None, workers=1, executor="processes", scheduler=None, **options):
    """An analysis at every point of a grid of two scene parameters
    (``{"amplitude": (from, to, count), "gap": (from, to, count)}``, named as
    in continue_parameter), collected into one dataset: each named scalar
    the analysis returns, as a (count_1, count_2) array, with the grid's
    coordinates. ``analysis``: "response" (response_summary; options
    frequency=(from, to, step), impacts, periods), "basin" (basin_summary;
    options states={"x1": (from, to, count), "v1": ...} or the section's,
    periods, window, tol, base, contact) or a picklable function model ->
    {name: scalar} run with ``options``. Returns {name: array, the
    coordinates under their names}; with ``out``, writes out/study.h5 and
    out/grid.png (the first quantity's map)."""
    model, scene_text = _load(model)
    if isinstance(analysis, str) and analysis not in ANALYSES:
        raise StudyError(f"analysis: must be one of {', '.join(ANALYSES)} or a function, got {analysis!r}")
    if analysis == "response" and (model.forcing_amplitude is None or not np.any(model.forcing_amplitude)):
        raise StudyError("model: the response analysis needs a forced model (a [forcing] table)")
    axes = _parse_axes(grid, lambda name: _nsmodal._parameter_value(model, name))
    if analysis == "response" and any(name == "frequency" for name, *_ in axes):
        raise StudyError("grid: frequency cannot be a grid axis of the response analysis (it sweeps the "
                         "frequency itself: --frequency)")
    coords = [np.linspace(lo, hi, count) for (_, lo, hi, count) in axes]
    names = [axes[0][0], axes[1][0]]
    # The grid's corners checked before any work or file (a value that
    # leaves the valid model: its field), and the analysis run at the first
    # (its options).
    for v1 in (coords[0][0], coords[0][-1]):
        for v2 in (coords[1][0], coords[1][-1]):
            try:
                _nsmodal.with_parameter(_nsmodal.with_parameter(model, names[0], v1), names[1], v2)
            except ValueError as e:
                raise StudyError(f"grid: at {names[0]} = {v1:g}, {names[1]} = {v2:g}: {e}") from None
    try:
        _grid_chunk(model, names, [(coords[0][0], coords[1][0])], analysis, options)
    except (ValueError, TypeError) as e:
        raise StudyError(f"analysis: {e}") from None
    values = np.array([(a, b) for a in coords[0] for b in coords[1]])
    per = GRID_CHUNK_POINTS
    chunks = [(s, min(s + per, len(values))) for s in range(0, len(values), per)]
    request = {"study": "grid", "grid": [list(g) for g in axes], "analysis": analysis if isinstance(analysis, str)
               else f"{analysis.__module__}.{analysis.__qualname__}", "options": repr(sorted(options.items())),
               "chunk_points": per, "model": pickle.dumps(model).hex()}
    results = _run_chunks(out, request, [(_grid_chunk, (model, names, values[s:e], analysis, options))
                                         for s, e in chunks],
                          lambda i: f"points {chunks[i][0]} to {chunks[i][1] - 1} ({names[0]} = "
                                    f"{values[chunks[i][0], 0]:g} .. {values[chunks[i][1] - 1, 0]:g})",
                          workers, executor, scheduler)
    n1, n2 = len(coords[0]), len(coords[1])
    result = {key: np.concatenate([r[key] for r in results]).reshape(n1, n2) for key in results[0]}
    result[names[0]], result[names[1]] = coords[0], coords[1]
    if out is not None:
        import h5py
        units = ANALYSES[analysis][1] if isinstance(analysis, str) else {}
        tmp = os.path.join(out, "study.h5.partial")
        with h5py.File(tmp, "w", track_order=True) as f:
            for key in results[0]:
                d = f.create_dataset(key, data=result[key], track_times=False)
                d.attrs["units"] = units.get(key, "")
                d.attrs["dims"] = json.dumps(names)
            for name, c in zip(names, coords):
                f.create_dataset(name, data=c, track_times=False).attrs["units"] = PARAMETER_UNITS.get(
                    name.split("[")[0], "")
            _provenance(f, model, scene_text, request)
        os.replace(tmp, os.path.join(out, "study.h5"))
        first = next(iter(results[0]))
        _draw_grid(os.path.join(out, "grid"), result, names, first, units.get(first, ""))
    return result


def _parse_axes(grid, check):
    items = list(grid.items()) if isinstance(grid, dict) else list(grid)
    out = []
    for item in items:
        if isinstance(item, str):
            name, sep, spec = item.partition("=")
            parts = spec.split(":")
            if not sep or len(parts) != 3:
                raise StudyError(f"grid: must be NAME=FROM:TO:COUNT, got {item!r}")
        else:
            name, parts = item
        try:
            lo, hi, count = (float(v) for v in parts)
        except (TypeError, ValueError):
            raise StudyError(f"grid: {name}: must be FROM:TO:COUNT (numbers), got {parts!r}") from None
        try:
            check(name)
        except ValueError as e:
            raise StudyError(f"grid: {e}") from None
        if not (np.isfinite(lo) and np.isfinite(hi) and hi > lo):
            raise StudyError(f"grid: {name}: must have finite FROM < TO, got {lo}:{hi}")
        if count != int(count) or not 2 <= count <= 100000:
            raise StudyError(f"grid: {name}: COUNT must be a whole number from 2 to 100000, got {count:g}")
        out.append((name, lo, hi, int(count)))
    if len(out) != 2 or out[0][0] == out[1][0]:
        raise StudyError(f"grid: a study needs two different coordinates, got {[g[0] for g in out]}")
    return out


def _provenance(f, model, scene_text, request):
    f.attrs["nsmodal_version"] = _nsmodal.__version__
    f.attrs["settings"] = json.dumps({k: v for k, v in request.items() if k != "model"})
    f.attrs["model"] = repr(model)
    if scene_text is not None:
        f.attrs["scene"] = scene_text


def _draw_grid(stem, result, names, key, unit):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from . import style
    style.use("png")
    fig, ax = plt.subplots(figsize=style.figsize("png"))
    ax.grid(False)
    values = np.asarray(result[key])
    norm = None
    finite = values[np.isfinite(values)] if values.dtype.kind == "f" else values
    if values.dtype.kind in "iu" and finite.size and finite.max() - finite.min() <= 12:
        # Counts: one colour per value, the colour bar's ticks on them.
        from matplotlib.colors import BoundaryNorm
        lo, hi = int(finite.min()), int(finite.max())
        norm = BoundaryNorm(np.arange(lo - 0.5, hi + 1.5), style.colormap("level").N)
    mesh = ax.pcolormesh(result[names[1]], result[names[0]], values, cmap=style.colormap("level"), norm=norm,
                         shading="nearest")
    def label(name, u):
        return f"{name.replace('_', ' ')} ({u})" if u else name.replace("_", " ")

    bar = fig.colorbar(mesh, ax=ax, label=label(key, unit))
    if norm is not None:
        bar.set_ticks(np.arange(int(finite.min()), int(finite.max()) + 1))
    ax.set_xlabel(label(names[1], PARAMETER_UNITS.get(names[1].split("[")[0], "")))
    ax.set_ylabel(label(names[0], PARAMETER_UNITS.get(names[0].split("[")[0], "")))
    fig.tight_layout()
    style.save(fig, stem, ["png"])
    plt.close(fig)


def _write_h5(path, result, axes, model, scene_text, request, dofs):
    import h5py
    tmp = path + ".partial"
    with h5py.File(tmp, "w", track_order=True) as f:
        d = f.create_dataset("attractor", data=result["attractor"].astype(np.int32), track_times=False)
        d.attrs["meaning"] = ("the attractor of each grid point (the table attractors); -1: no settled attractor; "
                              "-2: a start beyond a wall; -3: not settled, with Zeno or sticking phases")
        d.attrs["dims"] = json.dumps([axes[0][0], axes[1][0]])
        for name, _, _, _ in axes:
            c = f.create_dataset(name, data=result[name], track_times=False)
            c.attrs["units"] = _coordinate_unit(name)
            if name in SECTION:
                c.attrs["meaning"] = ("the forcing phase w t of the start, on the wall of contact "
                                      f"{result['contact']}" if name == "phase" else
                                      "the velocity into the wall just before the start's impact")
        f.create_dataset("period", data=result["period"].astype(np.int32), track_times=False).attrs["meaning"] = (
            "stroboscopic period n of the settled motion, in forcing periods; 0: not settled")
        g = f.create_group("attractors")
        t = result["attractors"]
        g.create_dataset("id", data=np.array([r["id"] for r in t], dtype=np.int32), track_times=False)
        g.create_dataset("period", data=np.array([r["period"] for r in t], dtype=np.int32), track_times=False)
        g.create_dataset("impacts", data=np.array([r["impacts"] for r in t], dtype=np.int32), track_times=False)
        g.create_dataset("sequence", data=np.array([r["sequence"] for r in t], dtype=h5py.string_dtype()),
                         track_times=False)
        g.create_dataset("share", data=np.array([r["share"] for r in t]), track_times=False)
        g.create_dataset("zeno_or_sticking", data=np.array([r["zeno_or_sticking"] for r in t], dtype=bool),
                         track_times=False)
        for key in ("orbit_found", "orbit_admissible", "orbit_stable"):
            g.create_dataset(key, data=np.array([r[key] for r in t], dtype=bool), track_times=False)
        for key in ("orbit_max_multiplier", "orbit_time_error"):
            g.create_dataset(key, data=np.array([r[key] for r in t], dtype=float), track_times=False)
        for key in ("impact_phases", "impact_velocities"):
            d = g.create_dataset(key, (len(t),), dtype=h5py.vlen_dtype(np.float64), track_times=False)
            for k, r in enumerate(t):
                d[k] = r[key]
        g["impact_phases"].attrs["units"] = "rad"
        g["impact_velocities"].attrs["units"] = "m/s"
        g.create_dataset("state", data=np.array([r["state"] for r in t]).reshape(len(t), 2 * dofs),
                         track_times=False).attrs["columns"] = json.dumps(_state_names(dofs))
        _provenance(f, model, scene_text, request)
    os.replace(tmp, path)


def _draw(stem, result, axes, names):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap
    from . import style
    style.use("png")
    fig, ax = plt.subplots(figsize=style.figsize("png"))
    ids = result["attractor"]
    n = len(result["attractors"])
    # Beyond a wall: white; not settled: light grey; the attractors in the
    # sequences' colours, in turn.
    seq = style.cycle("sequences")
    cmap = ListedColormap([style.colour("grey"), style.colour("white"), style.colour("grey_light")] +
                          [seq[k % len(seq)] for k in range(max(n, 1))])
    c1, c2 = result[axes[0][0]], result[axes[1][0]]
    ax.grid(False)
    ax.pcolormesh(c2, c1, ids + 3, cmap=cmap, vmin=-0.5, vmax=max(n, 1) + 2.5, shading="nearest")
    from matplotlib.patches import Patch
    section = axes[0][0] in SECTION
    handles = []
    for r in result["attractors"]:
        if section:
            # The attractor's impacts on the section's wall, at their phase and velocity.
            mine = [k for k, c in enumerate(r["sequence"].split(",") if r["sequence"] else [])
                    if int(c) == result["contact"]]
            at = {"phase": r["impact_phases"][mine], "impact_velocity": r["impact_velocities"][mine]}
            ax.plot(at[axes[1][0]], at[axes[0][0]], **style.series("mark"))
        else:
            # The attractor's canonical stroboscopic point.
            a, b = names.index(axes[0][0]), names.index(axes[1][0])
            ax.plot(r["state"][b], r["state"][a], **style.series("mark"))
        handles.append(Patch(facecolor=seq[r["id"] % len(seq)],
                             label=f"{r['id']}: n = {r['period']}, {_impacts(r['impacts'])}, {100 * r['share']:.1f} %"))
    if np.any(ids == -1):
        handles.append(Patch(facecolor=style.colour("grey_light"), label="not settled"))
    if np.any(ids == -3):
        handles.append(Patch(facecolor=style.colour("grey"), label="not settled: Zeno or sticking"))
    if np.any(ids == -2):
        handles.append(Patch(facecolor=style.colour("white"), edgecolor=style.colour("grey"),
                             label="start beyond a wall"))
    handles.append(ax.plot([], [], **style.series("mark"),
                           label=f"attractor (its impacts on contact {result['contact']})" if section else
                           "attractor (stroboscopic point)")[0])

    def label(name):
        if name == "phase":
            return "forcing phase $\\omega t$ at the start (rad)"
        if name == "impact_velocity":
            return "velocity into the wall before the impact (m/s)"
        return f"${name[0]}_{{{name[1:]}}}$ ({_coordinate_unit(name)})"

    ax.set_xlabel(label(axes[1][0]))
    ax.set_ylabel(label(axes[0][0]))
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, fontsize="small")
    fig.tight_layout()
    style.save(fig, stem, ["png"])
    plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(prog="python3 -m nsmodal.study", description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    b = sub.add_parser("basin", help="basins of attraction over a grid of two state coordinates or the impact "
                                     "section's phase and impact_velocity")
    b.add_argument("scene")
    b.add_argument("--grid", action="append", required=True,
                   help="NAME=FROM:TO:COUNT (twice: x1, v1, ...; or phase and impact_velocity)")
    b.add_argument("--contact", type=int, default=1, help="the impact section's contact (1-based; default 1)")
    b.add_argument("--periods", type=int, default=500)
    b.add_argument("--out", required=True)
    b.add_argument("--workers", type=int, default=1)
    b.add_argument("--executor", default="processes", choices=EXECUTORS)
    b.add_argument("--scheduler")
    g = sub.add_parser("grid", help="an analysis over a grid of two scene parameters")
    g.add_argument("scene")
    g.add_argument("--grid", action="append", required=True,
                   help="NAME=FROM:TO:COUNT (twice: amplitude, gap, springs[2], ...)")
    g.add_argument("--analysis", default="response", choices=sorted(ANALYSES))
    g.add_argument("--frequency", help="response: the frequency grid FROM:TO:STEP")
    g.add_argument("--impacts", type=int, default=1, help="response: impacts per period")
    g.add_argument("--periods", type=int, help="response: forcing periods per response period n (default 1); "
                                               "basin: forcing periods simulated (default 500)")
    g.add_argument("--states", action="append", help="basin: NAME=FROM:TO:COUNT (twice: x1, v1, ...; or phase "
                                                     "and impact_velocity)")
    g.add_argument("--contact", type=int, default=1, help="basin: the impact section's contact")
    g.add_argument("--out", required=True)
    g.add_argument("--workers", type=int, default=1)
    g.add_argument("--executor", default="processes", choices=EXECUTORS)
    g.add_argument("--scheduler")
    a = p.parse_args(argv)
    try:
        if a.command == "grid":
            if a.analysis == "response":
                if a.frequency is None or a.states:
                    raise StudyError("--analysis response needs --frequency FROM:TO:STEP and takes no --states")
                options = dict(frequency=a.frequency, impacts=a.impacts, periods=a.periods or 1)
            else:
                if not a.states or a.frequency is not None:
                    raise StudyError("--analysis basin needs --states NAME=FROM:TO:COUNT (twice) and takes no "
                                     "--frequency")
                options = dict(states=a.states, periods=a.periods or 500, contact=a.contact)
            r = grid(a.scene, a.grid, analysis=a.analysis, out=a.out, workers=a.workers, executor=a.executor,
                     scheduler=a.scheduler, **options)
            names = [k for k in r if np.ndim(r[k]) == 1]
            print(f"wrote {' x '.join(str(len(r[n])) for n in names)} points ({', '.join(names)}) to "
                  f"{a.out}/study.h5 and {a.out}/grid.png")
            return 0
        r = basin(a.scene, a.grid, periods=a.periods, out=a.out, workers=a.workers, executor=a.executor,
                  scheduler=a.scheduler, contact=a.contact)
    except (StudyError, ValueError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    for t in r["attractors"]:
        orbit = ("the analytic orbit: " + ("admissible" if t["orbit_admissible"] else "NOT admissible") + ", " +
                 ("stable" if t["orbit_stable"] else "unstable") + f", impact times within {t['orbit_time_error']:.1e}"
                 if t["orbit_found"] else "no analytic orbit found from its impact times")
        print(f"attractor {t['id']}: period {t['period']}, {_impacts(t['impacts'])} ({t['sequence'] or 'none'}), "
              f"{100 * t['share']:.2f} % of the grid; {orbit}"
              + ("; Zeno or sticking phases" if t["zeno_or_sticking"] else ""))
    unsettled, beyond = float(np.mean(r["attractor"] == -1)), float(np.mean(r["attractor"] == -2))
    print(f"not settled: {100 * unsettled:.2f} %; starts beyond a wall: {100 * beyond:.2f} %; wrote {a.out}/study.h5 "
          f"and {a.out}/basin.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
