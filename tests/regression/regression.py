#!/usr/bin/env python3
"""Regression test: today's outputs of nsmodal on configs/*.toml, pinned.

Usage: regression.py NSMODAL_BINARY SOURCE_DIR [--mode exact|tolerant|update]
                     [--only CASE...] [--keep DIR]

Runs the commands of cases() below and compares every file they write (and
the JSON that `orbit --json` and `explore --json` print) with
tests/regression/expected/CASE/FILE. The mode (--mode, else the environment
variable NSMODAL_REGRESSION_MODE, else exact):

  exact     the Release GCC build (what ctest registers there): the analysis
            and the exact integrator number for number, as text; CVODE and
            Moreau-Jean within their own accuracy (integrator_rule);
  tolerant  the other builds (sanitizers, RelWithDebInfo, clang), where the
            last bits of a floating-point result may differ: the analysis and
            the exact integrator within ANALYSIS_RTOL (TOLERANT_ALLOWANCES
            say what else the last bits decide), CVODE and Moreau-Jean as in
            exact mode;
  update    rewrite expected/ from this binary (README.md: only for a change
            meant to change the outputs).

Standard library only (Debian's /usr/bin/python3 or any python3).
"""
import argparse
import csv
import io
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
EXPECTED = os.path.join(HERE, "expected")

# Fields that measure the machine, not the computation: they differ between
# two runs of the same binary, so they are left out by name (never by
# loosening a tolerance), in every mode. expected/ stores them blank (an
# empty CSV field, JSON null) so that a regeneration does not churn them.
# The outputs hold no host name, path or version string (checked when this
# test was written); a new one belongs here.
EXCLUDED_FIELDS = {
    "wall_time_s",  # simulate's summary.json, validate's validation.csv: elapsed time
    "cpu_s",  # bench's work_precision.csv (bench is not run here): CPU time
}

# Tolerant mode, analysis and exact integrator: 1e-9 relative, plus 1e-9
# times the field's scale (the median magnitude of its values in the
# expected file, or of the state they belong to: a value that cancels to ~0
# among O(1) values, v1 = -5.6e-17 at a turning point, has no relative
# accuracy to keep). Why 1e-9: a last-bit change
# (clang's FMA contraction in the AVX2 functions, another summation order at
# -O1, libmvec's sin for libm's) perturbs a result by ~1e-16 relative; the
# orbits are roots and eigenvectors of closed-form maps whose condition on
# these scenes keeps that below ~1e-12 (measured: every libm and libmvec
# result moved by one ulp, perturb_libm.c, moves no compared analysis value
# by more than 2e-12 of its field's scale), and the simulations are cut
# where the motion has not yet turned sensitive (paper-simulate.toml to
# t = 50: a 1e-12 change of x0 moves the final state 1.8e-11). 1e-9 keeps two
# decades of margin and still fails on any change of formula or algorithm.
ANALYSIS_RTOL = 1e-9

# Tolerant mode, response (forced orbits): 1e-4 relative. The continuation
# places its nodes between the grid's values by step control, and locates
# peaks (maxima of the energy: to ~sqrt(eps) relative in w) and folds
# (where the branch's slope is unbounded) by searches whose results move
# with the last bits; the multipliers of strongly unstable points (|mu| up
# to 5.5e3) amplify that. Measured with perturb_libm.c: up to 8.4e-7
# relative (max_multiplier 5531.35), 3.5e-9 on a peak's w.
RESPONSE_RTOL = 1e-4

# Round-off measures: quantities whose true value is 0 (residuals, drifts,
# penetrations, the deviation of a stable orbit from itself) and whose
# computed value is round-off, or round-off grown over the periods of a
# simulation: their digits are the last bits. Under every comparison but
# exact text they also pass within ROUNDOFF_ATOL absolute (they are relative
# or scaled quantities, and a broken closed form or periodicity makes them
# >= 1e-6; measured with perturb_libm.c: up to 2.1e-10, the nc2_residual of
# an explore finding, a root found numerically).
ROUNDOFF_FIELDS = {
    "periodicity_residual", "nc2_residual", "residual", "best_phi_new",  # the analysis' residuals
    "energy_drift",  # a simulation's |E(t_end) - E(0)| / E(0)
    "impact_time_error", "max_penetration",  # validate: the first period's timing, the largest x_c - d
    "deviation_1", "deviation_10", "deviation_100", "deviation_final", "deviation_end",  # |z(kT) - z0| / |z0|
}
ROUNDOFF_ATOL = 1e-8

# validate's perturbed runs: a start moved by 1e-6 |y| in the Floquet
# subspace, its growth and amplification, and the distances to the 1-ipp
# family. The round-off of the states (1e-16, up to 1e-13 after 20 periods)
# is up to 1e-7 of such a 1e-6 quantity (measured: 2e-7 relative): 1e-5
# relative under every comparison but exact text.
PERTURBATION_FIELDS = {
    "perturbed_amplification", "perturbed_growth", "stable_worst_amplification",
    "unstable_worst_relative_rate_error", "manifold_distance", "perturbed_manifold_distance",
}
PERTURBATION_RTOL = 1e-5

# Counters of an integrator's work, not of its result: under every
# comparison but exact text they may differ by COST_COUNTER_RTOL. CVODE's
# step-size controller answers a last-bit change of its error estimate with
# other step sizes from then on (measured with perturb_libm.c over 30
# seeds: paper-simulate.toml's 1838 steps became 1760 to 2026, up to 10 %;
# the exact integrator's 161 on forced.toml became 162).
COST_COUNTERS = {"steps", "sweep_steps"}
COST_COUNTER_RTOL = 0.25

# What the last bits decide, under every comparison but exact text (each
# measured with perturb_libm.c, README.md):
#  - Floquet multipliers are sorted by modulus, "the first two of equal
#    modulus in no set order" (README), and all of a stable orbit's are of
#    modulus 1 up to round-off: compared as a set (each expected one to the
#    nearest one got), per row or orbit.
#  - validate's worst_stable ranks stable orbits by deviations that are
#    round-off (exact) or integrator error (cvode): compared as a set keyed
#    by (T, t2). (The grid has 4 stable admissible orbits, fewer than the 5
#    listed, so the set itself is not decided by the ranking.)
#  - An admissible orbit the multipliers call unstable grows its round-off
#    by |lambda| a period: its validation row's UNSTABLE_ROW_FIELDS are that
#    round-off made visible (deviations, the measured growth and the verdict
#    text built on them, the impacts counted after it has left the orbit):
#    not compared; its verdict `consistent` is.
#  - explore merges the cyclic shifts (and time reversals) of an orbit and
#    reports one of them, chosen by round-off: findings are matched by
#    (kind, T, energy) and their SHIFT_FIELDS are not compared.
#  - response's special points at CROSSING_KINDS are where a multiplier
#    crosses the unit circle (stable there is a coin toss), where
#    admissibility changes (grazing) or where an impact velocity vanishes
#    (the multiplier is unbounded): their CROSSING_FIELDS are not compared.
#  - Numbers inside verdict texts (REASON_FIELDS) are printed to 3-6 digits
#    from fields compared on their own, or locate a maximum of x_c that a
#    symmetric orbit has twice at equal height: only their words are compared.
UNSTABLE_ROW_FIELDS = {"deviation_1", "deviation_10", "deviation_100", "deviation_final", "deviation_end",
                       "measured_growth", "reason", "impacts", "manifold_distance", "perturbed_manifold_distance"}
SHIFT_FIELDS = {"t2", "impact_times", "x", "v", "reason"}
CROSSING_KINDS = {"period-doubling", "fold", "grazing", "zero-velocity", "torus"}
CROSSING_FIELDS = {"admissible", "stable", "max_multiplier"}
REASON_FIELDS = {"reason", "message"}
MULTIPLIER_COLUMN = re.compile(r"mu(\d+)_(re|im)")

NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
INTEGER = re.compile(r"-?\d+")


def cases(src):
    """Every command of the test: its name, the arguments after the binary,
    the files it writes (or its stdout, saved under the name given) and its
    rule: 'analysis' (the analysis and the exact integrator), 'response'
    (analysis too, tolerant as RESPONSE_RTOL says), 'cvode', 'moreau-jean'."""
    paper = os.path.join(src, "configs/paper.toml")
    sim = os.path.join(src, "configs/paper-simulate.toml")
    forced = os.path.join(src, "configs/forced.toml")
    bar = os.path.join(src, "configs/bar.toml")
    clearance = os.path.join(src, "configs/clearance.toml")
    # The bar at rest, its velocity rising linearly to 2 m/s at the free
    # end: x_c reaches the wall 0.1 mm away after 59 us.
    bar_start = ["--x0"] + ["0"] * 100 + ["--v0"] + [repr(2.0 * (i + 1) / 100) for i in range(100)]
    sweep_files = ["orbits.csv", "transitions.csv"]
    sim_files = ["trajectory.csv", "impacts.csv", "summary.json"]
    validate_files = ["validation.csv", "summary.json"]
    out = []

    def add(name, argv, files, rule="analysis", stdout=None):
        out.append({"name": name, "argv": argv, "files": files, "rule": rule, "stdout": stdout})

    # The analysis: 1-ipp (with its transitions) and 2-ipp sweeps of the
    # paper's system; a 1-ipp and a 2-ipp sweep of the bar on a few modes.
    add("orbits-paper-1", ["orbits", paper, "--impacts", "1", "--period", "0.5:30:0.25"], sweep_files)
    add("orbits-paper-2", ["orbits", paper, "--impacts", "2", "--period", "1:20:0.5"], ["orbits.csv"])
    add("orbits-bar-1-modes4", ["orbits", bar, "--impacts", "1", "--period", "0.0002:0.0016:0.0002", "--modes", "4"],
        sweep_files)
    add("orbits-bar-2-modes2", ["orbits", bar, "--impacts", "2", "--period", "0.0008:0.0016:0.0004", "--modes", "2"],
        ["orbits.csv"])
    # Several contacts (issue 24): the clearance's families of the sequences
    # (1, 2) and (1), the latter's transitions with the lower wall's grazings.
    add("orbits-clearance-12", ["orbits", clearance, "--sequence", "1,2", "--period", "2:20:0.5"], ["orbits.csv"])
    add("orbits-clearance-1", ["orbits", clearance, "--sequence", "1", "--period", "1:30:0.25"], sweep_files)
    # The conservative impact damper: a rigid-body mode, its (1, 2) family.
    add("orbits-damper-free-12", ["orbits", os.path.join(src, "configs/impact-damper-free.toml"), "--sequence", "1,2",
                                  "--period", "2:30:0.25"], ["orbits.csv"])
    # orbit --json: a stable 1-ipp orbit; the 2-ipp roots of T = 6 (Fig. 6).
    add("orbit-paper-1-T7.5", ["orbit", paper, "--impacts", "1", "--period", "7.5", "--json"], [], stdout="orbit.json")
    add("orbit-paper-2-T6", ["orbit", paper, "--impacts", "2", "--period", "6", "--json"], [], stdout="orbit.json")
    # explore --json: 3 impacts at T = 27 and 28 (admissible new orbits), 4
    # on a coarse grid. (At T = 27.5 one non-admissible finding comes and
    # goes with the last bits: not used.)
    add("explore-paper-3", ["explore", paper, "--impacts", "3", "--period", "27:28:1", "--json"], [],
        stdout="explore.json")
    add("explore-paper-4", ["explore", paper, "--impacts", "4", "--period", "8:9:0.5", "--grid", "12", "--json"], [],
        stdout="explore.json")
    # simulate: each integrator on the three scenes, to horizons where the
    # motion has not yet turned sensitive: paper-simulate.toml to t = 50 (8
    # impacts; a 1e-12 change of x0 moves the final state 1.8e-11 there,
    # 2e-7 at t = 200), forced.toml to t = 150 (damped: it forgets its start),
    # the bar on 8 modes to 2 ms (7 impacts; CVODE's dense Newton systems on
    # all 200 states would take seconds) and on all its modes to 80 us (its
    # first 14 impacts, a chatter of the free end).
    for integrator in ("exact", "cvode", "moreau-jean"):
        rule = "analysis" if integrator == "exact" else integrator
        flags = ["--integrator", integrator]
        add("simulate-paper-" + integrator, ["simulate", sim, "--t-end", "50", "--sample-dt", "0.5"] + flags,
            sim_files, rule)
        add("simulate-forced-" + integrator, ["simulate", forced, "--t-end", "150", "--sample-dt", "1"] + flags,
            sim_files, rule)
        add("simulate-clearance-" + integrator, ["simulate", clearance, "--t-end", "30", "--sample-dt", "0.5"] + flags,
            sim_files, rule)
        add("simulate-bar-modes8-" + integrator,
            ["simulate", bar, "--t-end", "0.002", "--sample-dt", "0.0002", "--modes", "8", "--step", "1e-7"]
            + bar_start + flags, sim_files, rule)
    add("simulate-bar-exact-full", ["simulate", bar, "--t-end", "8e-5", "--sample-dt", "2e-5"] + bar_start, sim_files)
    # validate on 1- and 2-ipp orbits: the exact integrator (a rule of the
    # analysis), CVODE and Moreau-Jean at validate's defaults, given here
    # explicitly because their rules read them from the command line.
    grid = ["--period", "2:12:1", "--impacts", "1", "2", "--periods", "20"]
    add("validate-paper-exact", ["validate", paper] + grid + ["--integrators", "exact"], validate_files)
    add("validate-paper-cvode", ["validate", paper] + grid + ["--integrators", "cvode", "--rtol", "1e-10",
                                                               "--atol", "1e-12"], validate_files, "cvode")
    add("validate-paper-moreau-jean", ["validate", paper] + grid + ["--integrators", "moreau-jean", "--step", "1e-4"],
        validate_files, "moreau-jean")
    # validate the clearance's (1, 2) family (issue 24): exact and CVODE.
    seq = ["--period", "3:12:1", "--sequence", "1,2", "--periods", "20"]
    add("validate-clearance-exact", ["validate", clearance] + seq + ["--integrators", "exact"], validate_files)
    add("validate-clearance-cvode", ["validate", clearance] + seq + ["--integrators", "cvode", "--rtol", "1e-10",
                                                                      "--atol", "1e-12"], validate_files, "cvode")
    # response: a frequency sweep with its backbone and every point
    # validated by the exact integrator; an amplitude sweep at w = 0.5.
    add("response-forced-frequency",
        ["response", forced, "--frequency", "0.4:1.0:0.05", "--validate", "5", "--integrators", "exact"],
        ["response.csv", "response_points.csv", "backbone.csv", "response_validation.csv"], "response")
    add("response-forced-amplitude", ["response", forced, "--amplitude", "0.1:0.5:0.05", "--frequency", "0.5"],
        ["response.csv", "response_points.csv"], "response")
    # The impact damper's (1, 2) response (issue 24: a free mass, two
    # relative contacts), every point validated by the exact integrator.
    damper = os.path.join(src, "configs/impact-damper.toml")
    add("response-damper-12",
        ["response", damper, "--sequence", "1,2", "--frequency", "0.6:1.6:0.05", "--validate", "20",
         "--integrators", "exact"],
        ["response.csv", "response_points.csv", "response_validation.csv", "backbone.csv"], "response")
    return out


# ---------------------------------------------------------------- rules

class Rule:
    """How the numbers of one case are compared. exact: as text. Otherwise
    |a - b| <= rtol max(|a|, |b|) + rtol scale + atol, scale the field's
    typical magnitude in the expected file, or its state's largest
    component (scales_csv, row_scales, compare_json), widened for the
    fields above."""

    def __init__(self, exact, rtol=0.0, atol=0.0, why=""):
        self.exact, self.rtol, self.atol, self.why = exact, rtol, atol, why

    def tolerance(self, field, a, b, scale):
        rtol = max(self.rtol, PERTURBATION_RTOL) if field in PERTURBATION_FIELDS else self.rtol
        if field in ROUNDOFF_FIELDS:  # relative measures: their scale is 1, not the round-off they hold
            return max(rtol * (max(abs(a), abs(b)) + max(scale, 1.0)) + self.atol, ROUNDOFF_ATOL)
        return rtol * (max(abs(a), abs(b)) + scale) + self.atol


# How much the flow grows an error over the runs' horizons: a 1e-12 change
# of x0 moves paper-simulate.toml's state 1.8e-11 at t = 50 (the longest and
# most sensitive of these runs; forced.toml is damped, the bar's runs short).
CVODE_GROWTH = 20.0


def flag(case, name, default):
    """A setting given on the case's command line (--rtol 1e-10), else the default."""
    argv = case["argv"]
    return float(argv[argv.index(name) + 1]) if name in argv else default


def integrator_rule(case, expected_dir):
    """CVODE's and Moreau-Jean's tolerance, from the run's own settings.

    cvode: each step's local error is kept within rtol |y| + atol; two builds
    whose right-hand sides differ in the last bits take other steps, and
    their results differ by about the global error: the local errors of all
    steps added up, steps x (rtol |y| + atol), grown by the flow by up to
    CVODE_GROWTH. |y| is the field's scale, steps the run's own count
    (simulate's summary.json) or, for validate, 2e4 a run (20 periods of at
    most 12 time units; Adams at rtol 1e-10 takes ~70 steps a unit here).
    Measured with perturb_libm.c (CVODE's own pow() moved by one ulp: other
    steps from the first one on): up to 0.37 x steps x (rtol |y| + atol).

    moreau-jean: first order at impacts: a contact decision taken on the
    other side of round-off moves an impact by one step h, the state by
    ~h |v|: the step h relative to the field's scale, h the run's own."""
    summary = None
    path = os.path.join(expected_dir, "summary.json")
    if case["argv"][0] == "simulate" and os.path.exists(path):
        with open(path, encoding="utf-8") as f:
            summary = json.load(f)
    if case["rule"] == "cvode":
        rtol, atol, steps = flag(case, "--rtol", 1e-10), flag(case, "--atol", 1e-12), 2e4
        if summary:
            rtol, atol, steps = summary["settings"]["rtol"], summary["settings"]["atol"], max(summary["steps"], 1)
        return Rule(False, CVODE_GROWTH * steps * rtol, CVODE_GROWTH * steps * atol,
                    why="cvode: %g x steps x (rtol |y| + atol), steps %g, rtol %g, atol %g"
                    % (CVODE_GROWTH, steps, rtol, atol))
    h = summary["settings"]["step"] if summary else flag(case, "--step", 1e-3)
    return Rule(False, h, 0.0, why="moreau-jean: the step h = %g relative to the field's scale" % h)


def rule_for(case, mode, expected_dir):
    if case["rule"] in ("cvode", "moreau-jean"):
        return integrator_rule(case, expected_dir)
    if mode == "exact":
        return Rule(True, why="the same text")
    rtol = RESPONSE_RTOL if case["rule"] == "response" else ANALYSIS_RTOL
    return Rule(False, rtol, 0.0, why="tolerant: %g relative" % rtol)


# ---------------------------------------------------------------- files

class Num:
    """A JSON number as written (its text), so that exact mode compares text."""
    __slots__ = ("text", "is_int")

    def __init__(self, text, is_int):
        self.text, self.is_int = text, is_int

    def __float__(self):
        return float(self.text)


def load(path):
    with open(path, encoding="utf-8", newline="") as f:
        text = f.read()
    if path.endswith(".json"):
        return json.loads(text, parse_float=lambda t: Num(t, False), parse_int=lambda t: Num(t, True),
                          parse_constant=lambda t: Num(t, False))
    return list(csv.reader(io.StringIO(text)))


def blank_excluded(path):
    """expected/ stores the EXCLUDED_FIELDS blank: CSV cells empty, JSON values null."""
    with open(path, encoding="utf-8", newline="") as f:
        text = f.read()
    if path.endswith(".json"):
        for field in EXCLUDED_FIELDS:
            text = re.sub(r'("%s": )[^,\n\[{]+' % re.escape(field), r"\1null", text)
    else:
        def write(rows):
            buf = io.StringIO()
            csv.writer(buf, lineterminator="\n").writerows(rows)
            return buf.getvalue()
        rows = list(csv.reader(io.StringIO(text)))
        if write(rows) != text:  # the rewrite must change nothing but the blanked cells
            raise SystemExit("cannot rewrite %s without changing its text" % path)
        drop = [j for j, h in enumerate(rows[0]) if h in EXCLUDED_FIELDS] if rows else []
        for r in rows[1:]:
            for j in drop:
                r[j] = ""
        text = write(rows)
    with open(path, "w", encoding="utf-8", newline="") as f:
        f.write(text)


# ---------------------------------------------------------------- comparison

class Comparison:
    """The differences found in one case (the first few kept to print)."""

    def __init__(self, rule, limit=12):
        self.rule, self.items, self.count, self.limit = rule, [], 0, limit
        self.worst = (0.0, "")  # the largest difference / tolerance that passed, and where

    def margin(self, difference, tolerance, where):
        if tolerance > 0 and difference / tolerance > self.worst[0]:
            self.worst = (difference / tolerance, where)

    def bad(self, where, message):
        self.count += 1
        if len(self.items) < self.limit:
            self.items.append("%s: %s" % (where, message))

    def numbers(self, field, a, b, scale, where, counts=False):
        """Two numbers as written; counts: both written as integers."""
        if a == b:
            return
        if self.rule.exact:
            return self.bad(where, "expected %s, got %s" % (a, b))
        fa, fb = float(a), float(b)
        if counts:  # a count is equal, but for an integrator's work
            if field in COST_COUNTERS and abs(fa - fb) <= COST_COUNTER_RTOL * max(abs(fa), abs(fb)):
                return
            return self.bad(where, "expected %s, got %s (a count)" % (a, b))
        tol = self.rule.tolerance(field, fa, fb, scale)
        if not (math.isfinite(fa) and math.isfinite(fb)) or abs(fa - fb) > tol:
            self.bad(where, "expected %s, got %s (difference %.3g, tolerance %.3g)" % (a, b, abs(fa - fb), tol))
        else:
            self.margin(abs(fa - fb), tol, where)

    def text(self, field, a, b, where):
        """Two strings: equal; under tolerance a verdict's words only (REASON_FIELDS)."""
        if a == b or (not self.rule.exact and field in REASON_FIELDS
                      and NUMBER.sub("#", a) == NUMBER.sub("#", b)):
            return
        self.bad(where, "expected %r, got %r" % (a, b))

    def multiplier_set(self, exp, act, scale, where):
        """Two lists of complex multipliers (None: not computed), as sets."""
        if [m is None for m in exp] != [m is None for m in act]:
            return self.bad(where, "multipliers present differ")
        left = [m for m in act if m is not None]
        for m in exp:
            if m is None:
                continue
            best = min(left, key=lambda n: abs(n - m))
            tol = self.rule.tolerance("max_multiplier", abs(m), abs(best), scale)
            if abs(best - m) > tol:
                return self.bad(where, "multiplier %s has no counterpart within %.3g (nearest %s)" % (m, tol, best))
            self.margin(abs(best - m), tol, where)
            left.remove(best)


# The components of a state share its scale (the largest of them, in that
# row or list): v1 of a 1-ipp orbit is zero by symmetry (round-off of either
# sign), v2 is not; an integrator's error in one component is a share of
# the whole state's. CSV: the columns x1..xN, v1..vN (and _before, _after);
# JSON: the lists x, v, final_state.
STATE_GROUP = re.compile(r"([xv])\d+(_before|_after)?")
STATE_KEYS = {"x", "v", "final_state"}


def group(field):
    m = STATE_GROUP.fullmatch(field)
    return m.group(1) + (m.group(2) or "") if m else None


def typical(values):
    """The median magnitude of the nonzero values: a floor for the values
    that cancel to ~0, which a few huge values (energies near a singular
    period) do not inflate."""
    mags = sorted(abs(v) for v in values if v)
    return mags[len(mags) // 2] if mags else 0.0


def scales_csv(rows):
    """The typical magnitude of each column."""
    values = {}
    for r in rows[1:]:
        for h, v in zip(rows[0], r):
            if NUMBER.fullmatch(v):
                values.setdefault(h, []).append(float(v))
    return {h: typical(v) for h, v in values.items()}


def row_scales(header, row, scales):
    """A row's scale of each column: its state's largest component for a
    state column, else the column's typical magnitude."""
    state = {}
    for h, v in zip(header, row):
        g = group(h)
        if g and NUMBER.fullmatch(v):
            state[g] = max(state.get(g, 0.0), abs(float(v)))
    return {h: max(scales.get(h, 0.0), state.get(group(h), 0.0)) for h in header}


def scales_json(node):
    """The typical magnitude of the numbers under each key (a list takes its
    key's name)."""
    values = {}

    def walk(n, key):
        if isinstance(n, dict):
            for k, v in n.items():
                walk(v, k)
        elif isinstance(n, list):
            for v in n:
                walk(v, key)
        elif isinstance(n, Num):
            values.setdefault(key, []).append(float(n))
    walk(node, "")
    return {k: typical(v) for k, v in values.items()}


def compare_csv(exp, act, cmp, name):
    if not exp or not act or exp[0] != act[0]:
        return cmp.bad(name, "header: expected %s, got %s" % (exp[:1], act[:1]))
    if len(exp) != len(act):
        return cmp.bad(name, "expected %d rows, got %d" % (len(exp) - 1, len(act) - 1))
    header, scales = exp[0], scales_csv(exp)
    mu_columns = [j for j, h in enumerate(header) if MULTIPLIER_COLUMN.fullmatch(h)]
    mu_scale = max([scales.get(header[j], 0.0) for j in mu_columns] + [scales.get("max_multiplier", 0.0)])
    for line, (x, y) in enumerate(zip(exp[1:], act[1:]), start=2):
        if len(x) != len(y):
            cmp.bad("%s line %d" % (name, line), "expected %d fields, got %d" % (len(x), len(y)))
            continue
        skip, scale = set(EXCLUDED_FIELDS), row_scales(header, x, scales)
        if not cmp.rule.exact:
            d = dict(zip(header, x))
            if d.get("admissible") == "1" and d.get("stable") == "0" and "deviation_1" in d:
                skip |= UNSTABLE_ROW_FIELDS
            if d.get("kind") in CROSSING_KINDS:
                skip |= CROSSING_FIELDS
            if mu_columns:
                skip |= {header[j] for j in mu_columns}

                def multipliers(r):
                    v = {header[j]: r[j] for j in mu_columns}
                    return [complex(float(v["mu%d_re" % k]), float(v["mu%d_im" % k])) if v["mu%d_re" % k] else None
                            for k in range(1, len(mu_columns) // 2 + 1)]
                cmp.multiplier_set(multipliers(x), multipliers(y), mu_scale, "%s line %d multipliers" % (name, line))
        for h, a, b in zip(header, x, y):
            if a == b or h in skip:
                continue
            where = "%s line %d column %s" % (name, line, h)
            if NUMBER.fullmatch(a) and NUMBER.fullmatch(b):
                cmp.numbers(h, a, b, scale.get(h, 0.0), where, bool(INTEGER.fullmatch(a) and INTEGER.fullmatch(b)))
            else:
                cmp.text(h, a, b, where)


def match_sets(exp, act, key, cmp, name, path, compare):
    """Lists in no set order: each expected element is paired with the first
    unused element of the same key (a tuple of texts and numbers, numbers
    within the rule), then compare(expected, got, path of the element)."""
    def same(k1, k2):
        return all(a == b or (isinstance(a, float) and isinstance(b, float)
                              and abs(a - b) <= cmp.rule.tolerance("", a, b, 0.0)) for a, b in zip(k1, k2))
    if len(exp) != len(act):
        return cmp.bad("%s %s" % (name, path), "expected %d elements, got %d" % (len(exp), len(act)))
    left = list(act)
    for i, e in enumerate(exp):
        found = next((a for a in left if same(key(e), key(a))), None)
        if found is None:
            cmp.bad("%s %s[%d]" % (name, path, i), "nothing got matches %s" % (key(e),))
            continue
        left.remove(found)
        compare(e, found, "%s[%d]" % (path, i))


def plain(v):
    return float(v) if isinstance(v, Num) else v


def compare_json(exp, act, cmp, name, scales=None, key="", path=""):
    scales = scales_json(exp) if scales is None else scales
    where = "%s %s" % (name, path or "/")

    def child(e, a, k, p):
        compare_json(e, a, cmp, name, scales, k, p)

    if key in STATE_KEYS and isinstance(exp, list) and not path.endswith("]"):  # a state: its largest component
        scales = dict(scales)
        scales[key] = max([scales.get(key, 0.0)] + [abs(float(v)) for v in exp if isinstance(v, Num)])

    if key in EXCLUDED_FIELDS:
        return
    if isinstance(exp, dict) and isinstance(act, dict):
        if sorted(exp) != sorted(act):
            return cmp.bad(where, "keys: expected %s, got %s" % (sorted(exp), sorted(act)))
        skip = set()
        if not cmp.rule.exact:
            if exp.get("admissible") is True and exp.get("stable") is False and "deviation_final" in exp:
                skip |= UNSTABLE_ROW_FIELDS
            if "kernel_dimension" in exp:  # an explore finding
                skip |= SHIFT_FIELDS
        for k in exp:
            if k in skip:
                continue
            if not cmp.rule.exact and k == "worst_stable":
                for integrator in exp[k]:
                    if integrator not in act[k]:
                        cmp.bad(where, "worst_stable lacks %s" % integrator)
                        continue
                    match_sets(exp[k][integrator], act[k][integrator], lambda e: (plain(e["T"]), plain(e["t2"])), cmp,
                               name, "%s/worst_stable/%s" % (path, integrator), lambda e, a, p: child(e, a, "", p))
            elif not cmp.rule.exact and k == "findings":
                match_sets(exp[k], act[k], lambda e: (e["kind"], plain(e["T"]), plain(e["energy"])), cmp,
                           name, path + "/findings", lambda e, a, p: child(e, a, "", p))
            elif not cmp.rule.exact and k == "multipliers":
                def multipliers(v):
                    return [complex(float(m[0]), float(m[1])) for m in v]
                if len(exp[k]) != len(act[k]):
                    cmp.bad(where + "/multipliers", "expected %d, got %d" % (len(exp[k]), len(act[k])))
                else:
                    cmp.multiplier_set(multipliers(exp[k]), multipliers(act[k]),
                                       max(scales.get("multipliers", 0.0), scales.get("max_multiplier", 0.0)),
                                       where + "/multipliers")
            else:
                child(exp[k], act[k], k, path + "/" + k)
    elif isinstance(exp, list) and isinstance(act, list):
        if len(exp) != len(act):
            return cmp.bad(where, "expected %d elements, got %d" % (len(exp), len(act)))
        for i, (e, a) in enumerate(zip(exp, act)):
            child(e, a, key, "%s[%d]" % (path, i))
    elif isinstance(exp, Num) and isinstance(act, Num):
        cmp.numbers(key, exp.text, act.text, scales.get(key, 0.0), where, exp.is_int and act.is_int)
    elif isinstance(exp, str) and isinstance(act, str):
        cmp.text(key, exp, act, where)
    elif not ((exp is None and act is None) or (isinstance(exp, bool) and exp is act)):
        show = lambda v: v.text if isinstance(v, Num) else json.dumps(v)  # noqa: E731
        cmp.bad(where, "expected %s, got %s" % (show(exp), show(act)))


# ---------------------------------------------------------------- running

def outputs(case):
    return case["files"] + ([case["stdout"]] if case["stdout"] else [])


def run_case(binary, case, out_dir):
    """Runs one command; its files (and stdout) land in out_dir. None, or what went wrong."""
    os.makedirs(out_dir, exist_ok=True)
    argv = [binary] + case["argv"] + ([] if case["stdout"] else ["--out", out_dir])
    proc = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=900)
    if proc.returncode != 0:
        return "exit %d: %s" % (proc.returncode, (proc.stderr or proc.stdout).strip()[-2000:])
    if case["stdout"]:
        with open(os.path.join(out_dir, case["stdout"]), "w", encoding="utf-8") as f:
            f.write(proc.stdout)
    return None


def update(binary, selected, expected, everything):
    """Rewrites expected/ (all of it, or the selected cases) from this binary."""
    if everything and os.path.isdir(expected):
        shutil.rmtree(expected)
    for c in selected:
        target = os.path.join(expected, c["name"])
        shutil.rmtree(target, ignore_errors=True)
        error = run_case(binary, c, target)
        if error:
            raise SystemExit("%s: %s" % (c["name"], error))
        for f in os.listdir(target):  # only the compared files: not the charts and their scripts
            if f not in outputs(c):
                path = os.path.join(target, f)
                shutil.rmtree(path) if os.path.isdir(path) else os.remove(path)
        for f in outputs(c):
            blank_excluded(os.path.join(target, f))
        print("updated %s: %s" % (c["name"], ", ".join(outputs(c))))


def check(binary, case, mode, expected, work):
    """Runs one case and compares its outputs; the Comparison."""
    exp_dir, act_dir = os.path.join(expected, case["name"]), os.path.join(work, case["name"])
    cmp = Comparison(rule_for(case, mode, exp_dir))
    error = run_case(binary, case, act_dir)
    if error:
        cmp.bad(case["name"], error)
        return cmp
    for f in outputs(case):
        exp_path, act_path = os.path.join(exp_dir, f), os.path.join(act_dir, f)
        name = "%s/%s" % (case["name"], f)
        if not os.path.exists(exp_path):
            cmp.bad(name, "no expected file %s (a new case? --mode update, README.md)" % exp_path)
        elif not os.path.exists(act_path):
            cmp.bad(name, "not written")
        elif f.endswith(".json"):
            compare_json(load(exp_path), load(act_path), cmp, name)
        else:
            compare_csv(load(exp_path), load(act_path), cmp, name)
    return cmp


def exact_unavailable():
    """Why this machine cannot reproduce expected/ to the last bit, or None.
    expected/ was made on x86-64 with AVX2 and FMA, where flow.cc takes
    libmvec's sin and cos and stability.cc its AVX2 sums (simd.h decides at
    run time); elsewhere the plain loops give other last bits."""
    if os.uname().machine not in ("x86_64", "AMD64"):
        return "not x86-64"
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            flags = next((line.split(":", 1)[1].split() for line in f if line.startswith("flags")), [])
    except OSError:
        return "no /proc/cpuinfo"
    missing = [x for x in ("avx2", "fma") if x not in flags]
    return "no %s on this processor" % " or ".join(missing) if missing else None


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("binary")
    p.add_argument("source_dir")
    p.add_argument("--mode", choices=["exact", "tolerant", "update"],
                   default=os.environ.get("NSMODAL_REGRESSION_MODE") or "exact")
    p.add_argument("--only", nargs="+", metavar="CASE", help="these cases only")
    p.add_argument("--keep", metavar="DIR", help="keep this run's outputs in DIR")
    p.add_argument("--margins", action="store_true",
                   help="print each case's largest difference / tolerance among the numbers that passed")
    a = p.parse_args()
    binary, src = os.path.abspath(a.binary), os.path.abspath(a.source_dir)
    selected = [c for c in cases(src) if not a.only or c["name"] in a.only]
    if a.only and len(selected) != len(set(a.only)):
        raise SystemExit("unknown case in %s; the cases: %s" % (a.only, " ".join(c["name"] for c in cases(src))))
    start = time.monotonic()
    if a.mode == "update":
        update(binary, selected, EXPECTED, not a.only)
        print("expected/ rewritten in %.1f s; commit it saying which change moved the outputs, and why"
              % (time.monotonic() - start))
        return 0
    if a.mode == "exact" and exact_unavailable():
        print("exact comparison needs the processor expected/ was made on (%s): comparing as in tolerant mode"
              % exact_unavailable())
        a.mode = "tolerant"
    work = os.path.abspath(a.keep) if a.keep else tempfile.mkdtemp(prefix="nsmodal-regression-")
    failed = 0
    try:
        for c in selected:
            t0 = time.monotonic()
            cmp = check(binary, c, a.mode, EXPECTED, work)
            print("%-4s %-32s %5.2f s  %s" % ("ok" if cmp.count == 0 else "FAIL", c["name"], time.monotonic() - t0,
                                              cmp.rule.why))
            failed += cmp.count > 0
            if a.margins and cmp.worst[0] > 0:
                print("       largest difference: %.2g of its tolerance, at %s" % cmp.worst)
            for item in cmp.items:
                print("       " + item)
            if cmp.count > len(cmp.items):
                print("       ... and %d more differences" % (cmp.count - len(cmp.items)))
    finally:
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)
    print("%d cases, %d failed (mode %s, %.1f s)%s" % (len(selected), failed, a.mode, time.monotonic() - start,
                                                      "; outputs kept in " + work if a.keep else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
