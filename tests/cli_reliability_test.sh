#!/usr/bin/env bash
# Issue 14's reliability cases, each pinned: no shell between user input and a
# process, every write checked (a failed write is a failed run, exit 5), and
# output directories that never mix runs or hold a result that looks complete
# but is not.
# Usage: cli_reliability_test.sh NSMODAL_BINARY SOURCE_DIR
. "$(dirname "$0")/cli_harness.sh" "$@"
paper=$src/configs/paper.toml
sim=$src/configs/paper-simulate.toml

# 1. Shell injection through --out: the path reaches gnuplot as an argument
#    vector and a working directory, never a command line.
cd "$tmp" || exit 1
evil="$tmp/x';touch PWNED;'"
"$bin" bench "$paper" --quick --out "$evil" >/dev/null 2>&1
rc=$?
[ ! -e "$tmp/PWNED" ] && [ ! -e "$evil/PWNED" ] && ok || bad "bench --out with a quote ran a shell command"
[ "$rc" -eq 0 ] && ok || bad "bench --out with a quote: exit $rc"
if command -v gnuplot >/dev/null; then
  [ -s "$evil/work_precision_smooth.png" ] && ok || bad "bench --out with a quote: chart not drawn"
fi
# A relative --out (the quick start's): charts drawn there too.
"$bin" bench "$paper" --quick --out rel/bench >/dev/null 2>"$tmp/rel.err"
rc=$?
[ "$rc" -eq 0 ] && ok || bad "bench with a relative --out: exit $rc: $(cat "$tmp/rel.err")"
if command -v gnuplot >/dev/null; then
  [ -s "$tmp/rel/bench/work_precision_smooth.png" ] && ok || bad "bench with a relative --out: chart not drawn"
fi
cd - >/dev/null || exit 1

# 2. Write failures: a file size limit stands in for a full disk (SIGXFSZ
#    ignored, so write() fails with EFBIG as it would with ENOSPC).
(trap '' XFSZ; ulimit -f 16; exec "$bin" orbits "$paper" --impacts 1 --period 0.05:40:0.01 --out "$tmp/full") \
  >/dev/null 2>"$tmp/full.err"
rc=$?
[ "$rc" -eq 5 ] && ok || bad "orbits on a full disk: exit $rc, expected 5 ($(cat "$tmp/full.err"))"
grep -q "orbits.csv" "$tmp/full.err" && ok || bad "full disk message does not name the file: $(cat "$tmp/full.err")"
[ -z "$(ls -A "$tmp/full" 2>/dev/null)" ] && ok || bad "full disk left files: $(ls -A "$tmp/full")"
(trap '' XFSZ; ulimit -f 16; exec "$bin" simulate "$sim" --t-end 200 --out "$tmp/fullsim") >/dev/null 2>&1
rc=$?
[ "$rc" -eq 5 ] && ok || bad "simulate on a full disk: exit $rc"
[ ! -e "$tmp/fullsim/summary.json" ] && [ ! -e "$tmp/fullsim/trajectory.csv" ] && ok || bad "simulate on a full disk left results"
"$bin" orbit "$paper" --period 7.5 --json >/dev/full 2>"$tmp/devfull.err"
rc=$?
[ "$rc" -eq 5 ] && ok || bad "orbit --json > /dev/full: exit $rc"
# An unwritable --out is refused before any work.
touch "$tmp/afile"
"$bin" orbits "$paper" --impacts 2 --period 0.05:40:0.01 --out "$tmp/afile/sub" >/dev/null 2>"$tmp/nodir.err"
rc=$?
[ "$rc" -eq 2 ] && grep -q -- "--out" "$tmp/nodir.err" && ok || bad "unwritable --out: exit $rc, $(cat "$tmp/nodir.err")"

# 3. Reused output directories.
"$bin" orbits "$paper" --impacts 1 --period 5:6:0.5 --out "$tmp/reuse" >/dev/null 2>&1
"$bin" orbits "$paper" --impacts 2 --period 5:6:0.5 --out "$tmp/reuse" >/dev/null 2>&1
[ ! -e "$tmp/reuse/transitions.csv" ] && ok || bad "orbits --impacts 2 left the 1-ipp transitions.csv"
"$bin" simulate "$sim" --t-end 5 --out "$tmp/sim" >/dev/null 2>&1
before=$(cat "$tmp/sim/summary.json" "$tmp/sim/trajectory.csv" | md5sum)
"$bin" simulate "$sim" --t-end -1 --out "$tmp/sim" >/dev/null 2>&1
rc=$?
after=$(cat "$tmp/sim/summary.json" "$tmp/sim/trajectory.csv" 2>/dev/null | md5sum)
[ "$rc" -eq 2 ] && [ "$before" = "$after" ] && ok || bad "refused simulate (exit $rc) changed the previous results"
"$bin" simulate "$sim" --x0 0 1.5 --out "$tmp/refused" >/dev/null 2>&1
[ -z "$(ls -A "$tmp/refused" 2>/dev/null)" ] && ok || bad "refused simulate wrote $(ls -A "$tmp/refused")"
# Interrupted: nothing named like a result.
# (No samples: 1e7 time units with samples would be refused, not run.)
timeout --preserve-status -s INT 1 "$bin" simulate "$sim" --t-end 1e7 --sample-dt 0 --out "$tmp/int" >/dev/null 2>&1
rc=$?
[ "$rc" -eq 130 ] && ok || bad "simulate interrupted by SIGINT: exit $rc, expected 130"
[ ! -e "$tmp/int/trajectory.csv" ] && [ ! -e "$tmp/int/summary.json" ] && ok || bad "interrupted simulate left results"
# figures: another run removes the figures it does not draw this time.
mkdir -p "$tmp/fig" && echo stale >"$tmp/fig/fig09_two_grazes.csv"
"$bin" figures "$paper" --period 0.05:5:0.05 --out "$tmp/fig" >/dev/null 2>&1
[ ! -e "$tmp/fig/fig09_two_grazes.csv" ] && ok || bad "figures left a stale fig09 from another run"

# 4. Crashes, hangs and silent non-finite results on legal-looking input: each
#    now a refusal naming the field, exit 2, within 10 s (expect_error treats a
#    timeout, 124, as a failure too: it is not the refusal asked for).
t() { timeout 10 "$@"; }
sys='[system]\ngap=1\nrestitution=1\nsprings=[1,1]\n'
expect_error "system.mass_matrix" t "$bin" orbit "$(scene subnormal "${sys}masses=[5e-324,1.0]\n")" --period 7.5
expect_error "system.mass_matrix" t "$bin" orbit "$(scene light "${sys}masses=[1,1e-16]\n")" --period 7.5
expect_error "system.gap" t "$bin" orbit "$(scene hugegap '[system]\ngap=1e308\nrestitution=1\nsprings=[1,1]\nmasses=[1,1]\n')" --period 7.5
expect_error "\-\-threads" t "$bin" orbits "$paper" --period 1:2:0.5 --out "$tmp/thr" --threads 2147483647
expect_error "\-\-period" t "$bin" orbit "$paper" --period 1e15
expect_error "\-\-period" t "$bin" orbit "$paper" --period 1e-320
expect_error "period" t "$bin" orbits "$paper" --period 1e-300:1e-299:1e-300 --out "$tmp/tiny"
expect_error "initial_velocity" t "$bin" simulate "$(scene fastv "${sys}masses=[1,1]\n[simulate]\ninitial_position=[0,0]\ninitial_velocity=[0,1e308]\n")" --out "$tmp/fast"
expect_error "\\-\\-sample-dt" t "$bin" simulate "$sim" --t-end 1e6 --sample-dt 0.01 --out "$tmp/many"
expect_error "\-\-period" t "$bin" orbits "$paper" --period 1:1e8:1 --out "$tmp/grid"
x0=$(seq 1 1500 | tr '\n' ' ')
# shellcheck disable=SC2086
expect_error "^error: --x0" t "$bin" simulate "$sim" --x0 $x0 --out "$tmp/x0"

# 6. Issue 29 item 4: analyses within the documented limits that never ended.
#    Each now answers within `timeout 20`: a result (exit 0, the result file)
#    or a refusal (exit 2) naming the option, with the work estimate.
#    answers PATTERN FILE CMD...: exit 0 with FILE written, or exit 2 with
#    PATTERN and the estimate on stderr; a timeout (124) fails.
answers() {
  local pattern=$1 file=$2
  shift 2
  timeout -k 5 20 "$@" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  if [ "$rc" -eq 0 ] && [ -s "$file" ]; then
    ok
  elif [ "$rc" -eq 2 ] && grep -q -- "$pattern" "$tmp/err" && grep -q "mode-root evaluations; the limit is" "$tmp/err"; then
    ok
  else
    bad "no answer within 20 s (exit $rc) for: $* -> $(cat "$tmp/err")"
  fi
}
# The 2-ipp sweep is quadratic in w_max T (each of its ~w_max T / pi orbits is
# checked over the whole period): T = 10,000 on the paper's system, refused.
answers "\-\-period" "$tmp/w1/orbits.csv" "$bin" orbits "$paper" --impacts 2 --period 10000:10000:1 --out "$tmp/w1"
# A 20-element bar, one mode kept: 6.6e3 oscillations per period, refused.
bar20=$(sed 's/elements = 100/elements = 20/' "$src/configs/bar.toml" >"$tmp/bar20.toml"; echo "$tmp/bar20.toml")
answers "\-\-period" "$tmp/w2/orbits.csv" "$bin" orbits "$bar20" --modes 1 --impacts 2 --period 5:5.1:0.1 --out "$tmp/w2"
# A chain with a stiff spring (w_max = 6.6e4): validate ends (its manifold
# check built a whole orbit, NC3 search included, 320 times an impact), and
# the 2-ipp sweep is refused.
stiff=$(scene stiff '[system]\nmasses=[1.0,1.0]\nsprings=[0.85,2147483647]\ncontact_dof=2\ngap=1.0\nrestitution=1.0\n')
answers "\-\-period" "$tmp/w3/validation.csv" "$bin" validate "$stiff" --period 2:2:1 --impacts 1 --out "$tmp/w3"
answers "\-\-period" "$tmp/w4/orbits.csv" "$bin" orbits "$stiff" --impacts 2 --period 2:6:0.5 --out "$tmp/w4"
# Its 1-ipp sweep is cheap, but the transitions search probes 8e4 modal and
# singular periods: refused with that estimate.
answers "transitions search" "$tmp/w5/orbits.csv" "$bin" orbits "$stiff" --impacts 1 --period 2:6:0.5 --out "$tmp/w5"
# Below the limits the same commands answer: the paper's T = 1,000 (0.14 s).
answers "\-\-period" "$tmp/w6/orbits.csv" "$bin" orbits "$paper" --impacts 2 --period 1000:1000:1 --out "$tmp/w6"
# Simulations bounded too: 420 orbits over 1e8 periods (about 3e4 s with the
# exact integrator, months with CVODE) refused at once, naming --periods;
# response --validate the same, naming --validate.
expect_error "\-\-periods: 420 orbits over 100000000 periods" t "$bin" validate "$paper" --period 2:30:0.5 --periods 100000000 --out "$tmp/w7"
[ -z "$(ls -A "$tmp/w7" 2>/dev/null)" ] && ok || bad "refused validate wrote $(ls -A "$tmp/w7")"
# explore: m = 6 on a grid of 200 (2.5e9 samples a period) refused at once.
expect_error "grid: 2472258789 samples a period" t "$bin" explore "$paper" --impacts 6 --period 5:5:1 --grid 200
expect_error "\-\-validate: is 100000000: a validation samples every period, fewer than 1e+07 periods" t "$bin" response "$src/configs/forced.toml" --frequency 0.5:0.55:0.05 --validate 100000000 --out "$tmp/w8"
[ -s "$tmp/w6/orbits.csv" ] && ok || bad "2-ipp orbits at T = 1000 were refused: $(cat "$tmp/err")"

# 7. Issue 29. (1) No inf or nan as a value in any table or document a run
#    writes: validate over a non-admissible orbit (T = 4.5, 1 impact: an extra
#    impact in its first period, whose time error was written as inf), and
#    response --validate (rows that break in their first period likewise).
#    Every CSV field and JSON number of the output directory is scanned.
no_nonfinite() {
  python3 - "$1" <<'PY'
import csv, json, math, os, sys
bad = []
for name in sorted(os.listdir(sys.argv[1])):
    path = os.path.join(sys.argv[1], name)
    if name.endswith(".csv"):
        for i, row in enumerate(csv.reader(open(path))):
            for field in row:
                if field.strip().lower().lstrip("+-") in ("inf", "infinity", "nan"):
                    bad.append("%s:%d: %s" % (name, i + 1, field))
    elif name.endswith(".json"):
        def refuse(token, name=name):
            bad.append("%s: %s" % (name, token))
        json.load(open(path), parse_constant=refuse)
print("\n".join(bad))
sys.exit(1 if bad else 0)
PY
}
t "$bin" validate "$paper" --period 4.5:4.5:1 --impacts 1 --periods 30 --out "$tmp/v45" >"$tmp/v45.log" 2>&1
rc=$?
[ "$rc" -eq 0 ] && ok || bad "validate T = 4.5: exit $rc: $(cat "$tmp/v45.log")"
out=$(no_nonfinite "$tmp/v45") && ok || bad "validate T = 4.5 wrote non-finite values: $out"
python3 -c "
import csv, sys
rows = list(csv.DictReader(open('$tmp/v45/validation.csv')))
assert len(rows) == 1 and rows[0]['admissible'] == '0' and rows[0]['first_period_impacts'] != '1', rows
assert rows[0]['impact_time_error'] == '', rows[0]['impact_time_error']
" && ok || bad "validate T = 4.5: impact_time_error not empty on the non-admissible row"
forced=$src/configs/forced.toml
# (A computation, not a refusal: bounded at 60 s, not t's 10. Under the
# sanitizers it takes 6.8 s alone, and past 10 s beside another test.)
timeout 60 "$bin" response "$forced" --frequency 0.4:1.0:0.05 --validate 3 --out "$tmp/rv" >"$tmp/rv.log" 2>&1
rc=$?
[ "$rc" -eq 0 ] && ok || bad "response --validate 3: exit $rc: $(cat "$tmp/rv.log")"
out=$(no_nonfinite "$tmp/rv") && ok || bad "response --validate 3 wrote non-finite values: $out"
python3 -c "
import csv
rows = list(csv.DictReader(open('$tmp/rv/response_validation.csv')))
assert any(r['impact_time_error'] == '' for r in rows)
" && ok || bad "response --validate 3: no row without an impact_time_error (the case is not exercised)"
# (5) Scene files: regular files only, at most 16 MiB, refused at once with
#     the path named (/dev/zero was read until memory ran out, /dev/urandom
#     for more than 20 s, a FIFO hung).
expect_error "scene: '/dev/zero' is a character device" t "$bin" orbit /dev/zero --period 7.5
expect_error "scene: '/dev/urandom' is a character device" t "$bin" validate /dev/urandom --period 5:6:1 --out "$tmp/urandom"
mkfifo "$tmp/scene.fifo"
expect_error "scene: '$tmp/scene.fifo' is a FIFO" t "$bin" orbit "$tmp/scene.fifo" --period 7.5
expect_error "is a directory" t "$bin" orbit "$tmp" --period 7.5
truncate -s 16777217 "$tmp/big.toml"
expect_error "is 16777217 bytes: a scene file holds at most 16777216" t "$bin" orbit "$tmp/big.toml" --period 7.5

# 8. Command-line errors exit 2 as documented; --version.
"$bin" orbits >/dev/null 2>&1
rc=$?
[ "$rc" -eq 2 ] && ok || bad "missing arguments: exit $rc, expected 2"
"$bin" orbit "$paper" --period 3 --no-such-flag >/dev/null 2>&1
rc=$?
[ "$rc" -eq 2 ] && ok || bad "unknown flag: exit $rc, expected 2"
"$bin" --version | grep -q '^nsmodal [0-9]' && ok || bad "--version"

finish
