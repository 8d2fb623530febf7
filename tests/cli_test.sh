#!/usr/bin/env bash
# End-to-end checks of the nsmodal CLI: outputs and their contracts, and bad
# input refused with a message naming the field and a non-zero exit.
# Usage: cli_test.sh NSMODAL_BINARY SOURCE_DIR
. "$(dirname "$0")/cli_harness.sh" "$@"

paper=$src/configs/paper.toml
expect_error "system.masses" "$bin" orbit "$(scene negmass '[system]\ngap=1\nrestitution=1\nmasses=[1,-1]\nsprings=[1,1]\n')" --period 3
expect_error "system.mass_matrix" "$bin" orbit "$(scene nonspd '[system]\ngap=1\nrestitution=1\nmass_matrix=[[1,2],[2,1]]\nstiffness_matrix=[[1,0],[0,1]]\n')" --period 3
expect_error "system.contact_dof" "$bin" orbit "$(scene dof '[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\ncontact_dof=5\n')" --period 3
expect_error "system.gap" "$bin" orbit "$(scene gap '[system]\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\ngap=0\n')" --period 3
expect_error "system.restitution" "$bin" orbit "$(scene e15 '[system]\ngap=1\nmasses=[1,1]\nsprings=[1,1]\nrestitution=1.5\n')" --period 3
expect_error "only for e = 1" "$bin" orbits "$(scene e05 '[system]\ngap=1\nmasses=[1,1]\nsprings=[1,1]\nrestitution=0.5\n')" --period 1:2:0.5 --out "$tmp/o"
expect_error "scene" "$bin" orbit "$(scene malformed '[system\nmasses=[1,1]\n')" --period 3
# Several contacts (issue 24): each refusal names the contact's index and field.
two='[system]\nmasses=[1,1]\nsprings=[0.85,2]\n[[contact]]\ndof=2\ngap=1\nrestitution=1\n'
expect_error "contact\\[2\\].normal: is zero" "$bin" orbit "$(scene zeronormal "$two"'[[contact]]\nnormal=[0,0]\ngap=1\nrestitution=1\n')" --period 3
expect_error "contact\\[2\\].gap" "$bin" orbit "$(scene gap2 "$two"'[[contact]]\ndof=1\ngap=-1\nrestitution=1\n')" --period 3
expect_error "contact\\[2\\].normal: duplicates contact 1" "$bin" orbit "$(scene dup "$two"'[[contact]]\ndof=2\ngap=2\nrestitution=1\n')" --period 3
expect_error "contact\\[2\\].restitution" "$bin" orbits "$(scene lossy2 "$two"'[[contact]]\ndof=2\nside="lower"\ngap=1\nrestitution=0.5\n')" --period 1:2:0.5 --out "$tmp/o"
clear2=$(scene clear2 "$two"'[[contact]]\ndof=2\nside="lower"\ngap=1.2\nrestitution=1\n')
expect_error "\\-\\-sequence: names contact 3" "$bin" orbits "$clear2" --sequence 1,3 --period 2:3:0.5 --out "$tmp/o"
expect_error "\\-\\-sequence: must list" "$bin" orbit "$clear2" --sequence 1,2,1 --period 3
expect_error "\\-\\-impacts: 2 disagrees" "$bin" orbit "$clear2" --impacts 2 --sequence 2 --period 3
expect_error "contact 2 (x2 >= -1.2)" "$bin" simulate "$clear2" --x0 0 -1.3 --v0 0 0 --out "$tmp/o"
# response --sequence: contacts checked, up to 8 impacts, agreeing with --impacts; the
# impact damper's (1, 2) response written with the backbone of its conservative twin.
damper=$src/configs/impact-damper.toml
expect_error "\\-\\-sequence: names contact 3" "$bin" response "$damper" --sequence 1,3 --frequency 1:1.2:0.1 --out "$tmp/o"
expect_error "\\-\\-sequence: must list the contact of each impact (1 to 8" "$bin" response "$damper" --sequence 1,2,1,2,1,2,1,2,1 --frequency 1:1.2:0.1 --out "$tmp/o"
expect_error "\\-\\-impacts: 3 disagrees" "$bin" response "$damper" --impacts 3 --sequence 1,2 --frequency 1:1.2:0.1 --out "$tmp/o"
expect_error "sequence: strikes no contact that moves the rigid-body mode" "$bin" response "$(scene damperstop '[system]\nmasses=[1,0.1]\nsprings=[1,0]\ndamping_ratios=[0,0.02]\n[[contact]]\nbetween=[2,1]\ngap=0.5\nrestitution=0.6\n[[contact]]\ndof=1\ngap=2\nrestitution=0.6\n[forcing]\namplitude=[0.3,0]\nfrequency=1.2\n')" --sequence 2 --frequency 1:1.2:0.1 --out "$tmp/o"
expect_error "system.damping_matrix: damps a rigid-body motion" "$bin" simulate "$(scene dampedfree '[system]\nmass_matrix=[[1,0],[0,0.1]]\nstiffness_matrix=[[1,0],[0,0]]\ndamping_matrix=[[0.1,0],[0,0.1]]\n[[contact]]\nbetween=[2,1]\ngap=0.5\nrestitution=0.6\n')" --x0 0 0 --v0 0 1 --out "$tmp/o"
if "$bin" response "$damper" --sequence 1,2 --frequency 1.3:1.5:0.1 --out "$tmp/damper" >"$tmp/damper.log" 2>&1; then
  ! grep -q "no backbone" "$tmp/damper.log" && ok || bad "response --sequence: no backbone"
  [ "$(wc -l <"$tmp/damper/backbone.csv")" -gt 100 ] && ok || bad "response --sequence wrote no backbone"
  python3 -c "
import csv
rows = list(csv.DictReader(open('$tmp/damper/response.csv')))
assert any(r['admissible'] == '1' and r['stable'] == '1' for r in rows)
assert all(r['impacts'] == '2' for r in rows)
" && ok || bad "response --sequence rows"
else
  bad "response --sequence on the impact damper failed: $(tail -3 "$tmp/damper.log")"
fi
expect_error "\\-\\-sequence: names contact 3" "$bin" explore "$clear2" --sequence 1,3,1 --period 4:5:1
expect_error "\\-\\-sequence: explore takes 3 to 6 impacts" "$bin" explore "$clear2" --sequence 1,2 --period 4:5:1
expect_error "\\-\\-impacts: 4 disagrees" "$bin" explore "$clear2" --impacts 4 --sequence 1,1,2 --period 4:5:1
# Decoupled contacts (no common mode): the (1, 2) sequence is a continuum, refused naming the sequence.
expect_error "sequence: contacts 1 and 2 move no common mode" "$bin" orbit "$(scene decoupled '[system]\nmass_matrix=[[1,0],[0,1]]\nstiffness_matrix=[[1,0],[0,2]]\n[[contact]]\ndof=1\ngap=1\nrestitution=1\n[[contact]]\ndof=2\ngap=1\nrestitution=1\n')" --sequence 1,2 --period 4
# A free mass in a cavity (a rigid-body mode): figures draws Fig. 18 alone,
# its (1, 2) family; 1-impact orbits are refused naming the stiffness.
free=$src/configs/impact-damper-free.toml
if "$bin" figures "$free" --period 2:20:0.05 --out "$tmp/free" >"$tmp/free.txt" 2>&1; then
  [ "$(ls "$tmp/free" | grep -c '\.csv$')" = 1 ] && [ "$(grep -c '^1-2,' "$tmp/free/fig18_sequences_fep.csv")" -gt 300 ] \
    && ok || bad "figures of a free mass: not Fig. 18 alone with its (1, 2) family"
else
  bad "figures of a free mass failed: $(tail -2 "$tmp/free.txt")"
fi
expect_error "system.stiffness_matrix: has 1 rigid-body mode" "$bin" orbits "$free" --impacts 1 --period 2:3:0.5 --out "$tmp/o"
expect_error "sequence: contacts 1 and 1" "$bin" orbits "$free" --sequence 1,1 --period 2:3:0.5 --out "$tmp/o"
# An --impacts given must agree with --sequence, its default value too.
expect_error "\\-\\-impacts: 1 disagrees with the sequence 1,2" "$bin" orbits "$free" --impacts 1 --sequence 1,2 --period 2:3:0.5 --out "$tmp/o"
expect_error "\\-\\-impacts: 3 disagrees with the sequence 1,2,1,2" "$bin" explore "$clear2" --impacts 3 --sequence 1,2,1,2 --period 4:5:1
# The paper's figures need contact 1 as an upper stop on a dof.
expect_error "figures draw contact 1" "$bin" figures "$(scene lowerfirst '[system]\nmasses=[1,1]\nsprings=[0.85,2]\n[[contact]]\ndof=2\nside="lower"\ngap=1\nrestitution=1\n')" --out "$tmp/f"
# A forced response against a lower wall (the forced scene mirrored: wall and
# force flipped) is validated as the upper one is: the same orbits, each consistent.
up=$(scene fup '[system]\nmasses=[1,1]\nsprings=[0.85,2]\ngap=1\nrestitution=0.8\ndamping_ratios=[0.02,0.02]\n[forcing]\namplitude=[0.3,0]\nfrequency=0.5\n')
down=$(scene fdown '[system]\nmasses=[1,1]\nsprings=[0.85,2]\ndamping_ratios=[0.02,0.02]\n[[contact]]\ndof=2\nside="lower"\ngap=1\nrestitution=0.8\n[forcing]\namplitude=[-0.3,0]\nfrequency=0.5\n')
if "$bin" response "$up" --frequency 0.8:1.0:0.1 --validate 3 --integrators exact --out "$tmp/rup" >/dev/null 2>&1 &&
   "$bin" response "$down" --frequency 0.8:1.0:0.1 --validate 3 --integrators exact --out "$tmp/rdown" >/dev/null 2>&1; then
  ok
else
  bad "a forced response against a lower wall is not validated as against the upper one"
fi
expect_error "cannot open" "$bin" orbit "$tmp/missing.toml" --period 3
# A built-in scene by name (compiled in from configs/), from a directory that has no such file.
if env -C "$tmp" "$bin" orbit paper --period 7.5 | grep -q "admissible"; then ok; else bad "orbit paper: no built-in scene"; fi
expect_error "no built-in scene of that name (bar, clearance, forced, impact-damper-free, impact-damper, oscillator, paper-simulate, paper)" env -C "$tmp" "$bin" orbit papr --period 3
expect_error "\-\-period" "$bin" orbits "$paper" --period 1:2 --out "$tmp/o"
expect_error "\-\-period" "$bin" orbits "$paper" --period 5:1:0.1 --out "$tmp/o"
expect_error "\-\-period" "$bin" orbits "$paper" --period 1:2:0 --out "$tmp/o"
expect_error "\-\-period" "$bin" orbits "$paper" --period a:2:0.1 --out "$tmp/o"
expect_error "\-\-period" "$bin" orbit "$paper" --period -1
expect_error "\-\-impacts" "$bin" orbits "$paper" --impacts 3 --period 1:2:0.5 --out "$tmp/o"
expect_error "impacts" "$bin" explore "$paper" --impacts 2 --period 1:2:0.5
expect_error "--follow" "$bin" explore "$paper" --impacts 4 --period 27:27:1 --follow 26:30:0.01
expect_error "--follow" "$bin" explore "$paper" --impacts 3 --period 27:27:1 --follow 26:x:0.01
# --follow: the paper's admissible 3-ipp family, from the orbit found at T = 27.5, to its ends.
if out=$("$bin" explore "$paper" --impacts 3 --period 27.5:27.5:1 --follow 26:30:0.01 2>/dev/null); then
  echo "$out" | grep -q "admissible for T in \[26.5714" && echo "$out" | grep -q ", 29.30716875" && ok ||
    bad "explore --follow: the 3-ipp family's ends"
else
  bad "explore --follow exit status"
fi

# orbits.csv and transitions.csv contracts.
if "$bin" orbits "$paper" --impacts 1 --period 2:12:0.01 --out "$tmp/one" >/dev/null 2>&1; then
  head -1 "$tmp/one/orbits.csv" |
    grep -q '^T,t2,energy,potential,admissible,periodicity_residual,.*,x1,x2,v1,v2,stable,max_multiplier,mu1_re,mu1_im,.*,mu4_im$' &&
    ok || bad "orbits.csv header"
  # Stability columns: T = 5 is stable (|lambda| = 1), T = 6.5 unstable (|lambda| = 2.40), see validate_test.
  python3 -c "
import csv; r={round(float(x['T']),2): x for x in csv.DictReader(open('$tmp/one/orbits.csv'))}
assert r[5.0]['stable'] == '1' and abs(float(r[5.0]['max_multiplier']) - 1) < 1e-6
assert r[6.5]['stable'] == '0' and abs(float(r[6.5]['max_multiplier']) - 2.398) < 1e-3
" && ok || bad "orbits.csv stability columns"
  [ "$(wc -l <"$tmp/one/orbits.csv")" -eq 1002 ] && ok || bad "orbits.csv rows: $(wc -l <"$tmp/one/orbits.csv")"
  head -1 "$tmp/one/transitions.csv" | grep -qx 'T,kind,energy,contact' && ok || bad "transitions.csv header"
  grep -q ',singular,' "$tmp/one/transitions.csv" && grep -q ',modal,' "$tmp/one/transitions.csv" &&
    grep -q ',grazing,' "$tmp/one/transitions.csv" && ok || bad "transitions.csv kinds"
else
  bad "orbits --impacts 1 failed"
fi
if "$bin" orbits "$paper" --impacts 2 --period 3:4:0.5 --out "$tmp/two" >/dev/null 2>&1; then
  # Every 2-ipp row has t2; T = 3 has roots t2 != T/2 (Fig. 6).
  awk -F, 'NR > 1 && $2 == "" { exit 1 }' "$tmp/two/orbits.csv" && ok || bad "2-ipp rows without t2"
  [ "$(awk -F, 'NR > 1 && $1 == 3' "$tmp/two/orbits.csv" | wc -l)" -ge 3 ] && ok || bad "T = 3 has < 3 roots"
else
  bad "orbits --impacts 2 failed"
fi
if "$bin" orbit "$paper" --impacts 2 --period 6 --json >"$tmp/j.json" 2>/dev/null; then
  python3 -c "import json,sys; d=json.load(open('$tmp/j.json')); o=d['orbits']; assert len(o) >= 3; assert all(k in o[0] for k in ('T','t2','energy','admissible','periodicity_residual','x','v','stable','multipliers'))" && ok || bad "orbit --json"
else
  bad "orbit --json failed"
fi
# simulate: outputs, flags over the [simulate] table, bad input.
sim=$src/configs/paper-simulate.toml
if "$bin" simulate "$sim" --out "$tmp/sim" --t-end 20 >/dev/null 2>&1; then
  head -1 "$tmp/sim/trajectory.csv" | grep -qx 't,x1,x2,v1,v2,energy' && ok || bad "trajectory.csv header"
  head -1 "$tmp/sim/impacts.csv" | grep -qx 't,contact,x1_before,x2_before,v1_before,v2_before,x1_after,x2_after,v1_after,v2_after' && ok || bad "impacts.csv header"
  python3 -c "
import json; d=json.load(open('$tmp/sim/summary.json'))
for k in ('final_time','final_state','impacts','sticking_time','energy_drift','wall_time_s','steps'): assert k in d, k
assert d['final_time'] == 20 and len(d['final_state']) == 4 and d['impacts'] > 0 and d['energy_drift'] < 1e-12
" && ok || bad "summary.json"
  [ "$(wc -l <"$tmp/sim/trajectory.csv")" -eq 402 ] && ok || bad "trajectory rows: $(wc -l <"$tmp/sim/trajectory.csv")"
else
  bad "simulate failed"
fi
for integ in cvode moreau-jean; do
  "$bin" simulate "$sim" --out "$tmp/sim-$integ" --t-end 20 --integrator $integ --step 1e-4 >/dev/null 2>&1 && ok || bad "simulate --integrator $integ"
done
expect_error "simulate.initial_position" "$bin" simulate "$sim" --out "$tmp/s" --x0 0 1.5
expect_error "^error: --x0" "$bin" simulate "$sim" --out "$tmp/s" --x0 0 0 0
expect_error "\-\-integrator" "$bin" simulate "$sim" --out "$tmp/s" --integrator euler
# Modal truncation: keeping both of the paper's modes is the full run (same
# impacts, final state within the round-off the impacts amplify); the output
# is physical (N columns); bad requests name the flag or key.
if "$bin" simulate "$sim" --out "$tmp/sim-k2" --t-end 20 --modes 2 >"$tmp/k2.txt" 2>&1; then
  grep -q "modal truncation: 2 of 2 modes kept" "$tmp/k2.txt" && ok || bad "simulate --modes: no truncation line"
  python3 -c "
import json; a=json.load(open('$tmp/sim/summary.json')); b=json.load(open('$tmp/sim-k2/summary.json'))
assert a['impacts'] == b['impacts'] and len(b['final_state']) == 4, (a['impacts'], b['impacts'])
assert max(abs(p - q) for p, q in zip(a['final_state'], b['final_state'])) < 1e-9
assert b['truncation']['kept'] == 2 and b['truncation']['contact_bound'] == 0
" && ok || bad "simulate --modes 2 differs from the full run"
else
  bad "simulate --modes 2 failed: $(cat "$tmp/k2.txt")"
fi
expect_error "^error: --modes" "$bin" simulate "$sim" --out "$tmp/s" --modes 0
expect_error "^error: --modes" "$bin" simulate "$sim" --out "$tmp/s" --modes 1.5
expect_error "^error: --modes" "$bin" simulate "$sim" --out "$tmp/s" --modes 1 --contact-tolerance 1e-3
expect_error "^error: --contact-tolerance" "$bin" simulate "$sim" --out "$tmp/s" --contact-tolerance -1
expect_error "^error: simulate.modes" "$bin" simulate "$(scene badmodes '[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\n[simulate]\ninitial_position=[0,0]\nmodes=3\n')" --out "$tmp/s"
# orbits --modes: a 6-mass chain analysed on all its modes is the full
# analysis (same orbits, the state mapped back to 6 dofs, bound 0: 1e-9
# relative is far above the round-off of the two bases, far below any
# difference a wrong mapping makes); on 3 modes the bound column is positive.
chain6="$(scene chain6 '[system]\ngap=1\nrestitution=1\nmasses=[1,1,1,1,1,1]\nsprings=[1,1,1,1,1,1]\n')"
if "$bin" orbits "$chain6" --period 5:9:0.5 --out "$tmp/o6" >/dev/null 2>&1 &&
   "$bin" orbits "$chain6" --period 5:9:0.5 --out "$tmp/o6k6" --modes 6 >"$tmp/o6k6.txt" 2>&1 &&
   "$bin" orbits "$chain6" --period 5:9:0.5 --out "$tmp/o6k3" --modes 3 >/dev/null 2>&1; then
  grep -q "modal truncation: 6 of 6 modes kept" "$tmp/o6k6.txt" && ok || bad "orbits --modes: no truncation line"
  python3 -c "
import csv
full = list(csv.DictReader(open('$tmp/o6/orbits.csv')))
all6 = list(csv.DictReader(open('$tmp/o6k6/orbits.csv')))
k3 = list(csv.DictReader(open('$tmp/o6k3/orbits.csv')))
assert len(full) == len(all6) == len(k3) > 0
for a, b in zip(full, all6):
    assert a['admissible'] == b['admissible'] and float(b['neglected_xc_bound']) == 0.0
    for key in ['energy', 'x1', 'x6', 'v1', 'v6']:
        assert abs(float(a[key]) - float(b[key])) <= 1e-9 * max(1.0, abs(float(a[key]))), (key, a[key], b[key])
assert all(float(r['neglected_xc_bound']) > 0 for r in k3 if r['energy'])
" && ok || bad "orbits --modes 6 differs from the full analysis"
else
  bad "orbits --modes failed: $(cat "$tmp/o6k6.txt")"
fi
expect_error "^error: --modes" "$bin" orbits "$chain6" --period 5:9:0.5 --out "$tmp/o" --modes 0
expect_error "^error: --modes" "$bin" orbits "$chain6" --period 5:9:0.5 --out "$tmp/o" --modes 2.5
expect_error "^error: --modes" "$bin" orbits "$chain6" --period 5:9:0.5 --out "$tmp/o" --modes 7
# Errors name what the user wrote: the flag when given, else the scene key.
expect_error "^error: --rtol" "$bin" simulate "$sim" --out "$tmp/s" --rtol -1
expect_error "^error: simulate.rtol" "$bin" simulate "$(scene badrtol '[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\n[simulate]\ninitial_position=[0,0]\nrtol=-1\n')" --out "$tmp/s"
expect_error "^error: --theta" "$bin" simulate "$sim" --out "$tmp/s" --theta 2
expect_error "^error: --t-end" "$bin" simulate "$sim" --out "$tmp/s" --t-end 0
expect_error "simulate.initial_position" "$bin" simulate "$paper" --out "$tmp/s"
expect_error "simulate.t_end" "$bin" simulate "$(scene badsim '[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\n[simulate]\ninitial_position=[0,0]\nt_end=[1]\n')" --out "$tmp/s"
expect_error "simulate.foo" "$bin" simulate "$(scene badkey '[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[1,1]\n[simulate]\nfoo=1\n')" --out "$tmp/s"

# validate: outputs, exit status, bad input.
if "$bin" validate "$paper" --out "$tmp/val" --period 5:8:1 --periods 50 --integrators exact cvode >/dev/null 2>&1; then
  head -1 "$tmp/val/validation.csv" | grep -q '^T,t2,impacts_per_period,integrator,admissible,stable,' && ok || bad "validation.csv header"
  python3 -c "
import json; d=json.load(open('$tmp/val/summary.json'))
assert d['integrators']['exact']['inconsistent'] == 0 and d['integrators']['exact']['checked'] > 4
" && ok || bad "validate summary.json"
else
  bad "validate failed"
fi
expect_error "\-\-period" "$bin" validate "$paper" --out "$tmp/v"
expect_error "\-\-integrators" "$bin" validate "$paper" --out "$tmp/v" --period 5:6:1 --integrators rk4
expect_error "^error: --periods" "$bin" validate "$paper" --out "$tmp/v" --period 5:6:1 --periods 0
# Issue 10: validate's --step was reported as simulate.step, a table it never reads.
expect_error "^error: --step" "$bin" validate "$paper" --out "$tmp/v" --period 5:6:1 --step -1
expect_error "^error: --root-tol" "$bin" validate "$paper" --out "$tmp/v" --period 5:6:1 --root-tol 1

# figures of a bar: its contact in space and time (bar_spacetime), every
# node's displacement at every sample, the impacts at its end.
if "$bin" figures "$src/configs/bar.toml" --out "$tmp/figbar" >"$tmp/figbar.txt" 2>&1; then
  python3 -c "
import csv
rows = list(csv.DictReader(open('$tmp/figbar/bar_spacetime.csv')))
hits = list(csv.DictReader(open('$tmp/figbar/bar_spacetime_impacts.csv')))
times = sorted({r['t_ms'] for r in rows})
assert len(rows) == 101 * len(times) and len(times) > 400, (len(rows), len(times))
assert hits and all(float(h['x']) == 1.0 for h in hits), hits[:3]
# The end never passes the wall (u / d <= 1 up to the root tolerance).
assert max(float(r['u_over_d']) for r in rows if float(r['x']) == 1.0) <= 1 + 1e-9
" && ok || bad "figures of a bar: bar_spacetime.csv"
  if command -v gnuplot >/dev/null; then
    grep -q "^1 figures drawn" "$tmp/figbar.txt" && [ -s "$tmp/figbar/bar_spacetime.column.pdf" ] && ok || bad "figures of a bar: chart"
    python3 "$src/scripts/check_figure_colours.py" "$tmp/figbar" >/dev/null && ok || bad "figures of a bar: chart check"
  fi
else
  bad "figures of a bar failed: $(tail -3 "$tmp/figbar.txt")"
fi
expect_error "\\-\\-period: the figures of a bar" "$bin" figures "$src/configs/bar.toml" --period 1:2:0.5 --out "$tmp/o"

# bench: the work-precision contract (quick mode), charts, and its scene check.
if "$bin" bench "$paper" --out "$tmp/bench" --quick >"$tmp/bench.txt" 2>/dev/null; then
  [ "$(head -1 "$tmp/bench/work_precision.csv")" = "case,integrator,setting,error,cpu_s,impacts,steps,expected_impacts" ] && ok ||
    bad "work_precision.csv header"
  for c in smooth near-grazing high-energy long-100 zeno; do
    grep -q "^$c,exact," "$tmp/bench/work_precision.csv" && grep -q "^$c,moreau-jean," "$tmp/bench/work_precision.csv" &&
      grep -q "^$c,cvode-adams," "$tmp/bench/work_precision.csv" && ok || bad "work_precision.csv lacks case $c"
    if command -v gnuplot >/dev/null; then
      [ -s "$tmp/bench/work_precision_$c.png" ] && [ -s "$tmp/bench/work_precision_$c.svg" ] &&
        [ -s "$tmp/bench/work_precision_$c.pdf" ] && ok || bad "chart $c"
    fi
  done
  grep -q "^moreau-jean  step=1e-02" "$tmp/bench.txt" && ok || bad "bench grazing table"
  if command -v gnuplot >/dev/null; then
    python3 "$src/scripts/check_figure_colours.py" "$tmp/bench" >"$tmp/bench_colours.txt" && ok \
      || bad "bench: chart check: $(grep FAIL "$tmp/bench_colours.txt" | head -3)"
  fi
else
  bad "bench --quick failed"
fi
expect_error "scene" "$bin" bench "$(scene other '[system]\ngap=1\nrestitution=1\nmasses=[1,2]\nsprings=[1,1]\n')" --out "$tmp/b"

# figures: every figure's data (and charts when gnuplot is there), on a
# shorter sweep that still holds two grazing transitions (9.127, 19.242).
if "$bin" figures "$paper" --out "$tmp/fig" --period 0.05:20:0.05 >"$tmp/fig.txt" 2>"$tmp/fig.err"; then
  for f in fig02_not_admissible fig03_one_impact fig03_transitions fig04_modal_transition fig05_grazing_transition \
    fig06_det_a2 fig06_roots fig07_two_impact fig08_fep fig08_bridges fig09_two_grazes fig10_one_impact_mode \
    fig11_two_impact_mode fig12_two_impact_mode fig13_bridge_orbits fig14_bridge_section fig15_bridge_fep fig15_bridge \
    fig17_bridges_fep fig17_bridges fig01_model multipliers_one_impact time_history time_history_impacts \
    validation_orbits validation_deviation fep_all_families; do
    [ -s "$tmp/fig/$f.csv" ] && ok || bad "figures: $f.csv missing"
  done
  if command -v gnuplot >/dev/null; then
    grep -q "^21 figures drawn" "$tmp/fig.txt" && ok || bad "figures: not all drawn: $(tail -1 "$tmp/fig.txt")"
    for f in fig01_model fig02_not_admissible fig03_one_impact_energy fig06_det_a2 fig08_fep fig12_two_impact_mode \
      fig15_bridge_fep fig17_bridges multipliers_one_impact time_history validation_orbits fep_all_families; do
      [ -s "$tmp/fig/$f.png" ] && [ -s "$tmp/fig/$f.svg" ] && [ -s "$tmp/fig/$f.pdf" ] && [ -s "$tmp/fig/$f.column.pdf" ] \
        && ok || bad "figures: $f chart"
    done
    # Every colour from the style; series told apart by colour alone stay
    # apart in greyscale and for a deuteranope; every key names what is drawn.
    python3 "$src/scripts/check_figure_colours.py" "$tmp/fig" >"$tmp/colours.txt" && ok \
      || bad "figures: chart check: $(grep FAIL "$tmp/colours.txt" | head -3)"
    # Every SVG under 1.5 MB and every PDF under 1 MB (issue 28's targets).
    heavy=$(find "$tmp/fig" \( -name '*.svg' -size +1536k \) -o \( -name '*.pdf' -size +1024k \))
    [ -z "$heavy" ] && ok || bad "figures: too heavy: $heavy"
  fi
  # Paper Fig. 6: roots t2 != T/2 exactly for T in {3, 4, 5, 6, 9}.
  away=$(awk -F, 'NR > 1 && $3 == 0 { print $1 }' "$tmp/fig/fig06_roots.csv" | sort -nu | tr '\n' ' ')
  [ "$away" = "3 4 5 6 9 " ] && ok || bad "figures: Fig. 6 periods with roots off T/2: '$away'"
  # The paper's bridge (graze at T/2): its lowest energy is the 1-ipp orbit of
  # period T_G/2, computed here by another command; both print 17 digits of
  # quantities exact to ~1e-15, so 1e-12 relative.
  read -r tg emin < <(awk -F, '$1 > 19 && $1 < 20 { print $1, $3 }' "$tmp/fig/fig08_bridges.csv")
  if [ -n "${tg:-}" ]; then
    half=$(awk -v t="$tg" 'BEGIN { printf "%.17g", t / 2 }')
    e=$("$bin" orbit "$paper" --period "$half" --json | awk -F': ' '/"energy"/ { gsub(",", "", $2); print $2; exit }')
    awk -v a="$emin" -v b="$e" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-12 * b) }' && ok ||
      bad "figures: bridge bottom $emin vs 1-ipp energy at T_G/2 $e"
  else
    bad "figures: no bridge near T = 19.24 in fig08_bridges.csv"
  fi
else
  bad "figures failed: $(cat "$tmp/fig.err")"
fi
expect_error "--period" "$bin" figures "$paper" --out "$tmp/f2" --period 1:x:0.1
expect_error "system.restitution" "$bin" figures "$(scene e05 '[system]\ngap=1\nmasses=[1,1]\nsprings=[1,1]\nrestitution=0.5\n')" --out "$tmp/f3"

# response: the forced, damped families, their contract and bad input.
forced=$src/configs/forced.toml
if "$bin" response "$forced" --frequency 0.4:1.0:0.01 --out "$tmp/resp" >"$tmp/resp.log" 2>&1; then
  head -1 "$tmp/resp/response.csv" |
    grep -qx 'w,amplitude,period,impacts,energy,max_xc,impact_velocity,admissible,stable,max_multiplier,t_impact,x1,x2,v1,v2,branch,periods,residual' &&
    ok || bad "response.csv header"
  head -1 "$tmp/resp/response_points.csv" | grep -q '^w,amplitude,kind,energy,' && ok || bad "response_points.csv header"
  for k in fold period-doubling grazing zero-velocity peak; do
    grep -q ",$k," "$tmp/resp/response_points.csv" && ok || bad "response_points.csv has no $k"
  done
  # Every admissible impacting point meets the wall: residual at round-off.
  python3 -c "
import csv
rows = list(csv.DictReader(open('$tmp/resp/response.csv')))
assert len(rows) > 60
assert all(float(r['residual']) < 1e-12 for r in rows), max(float(r['residual']) for r in rows)
assert any(r['admissible'] == '1' and r['stable'] == '1' for r in rows)
" && ok || bad "response.csv rows"
  head -1 "$tmp/resp/backbone.csv" | grep -qx 'w,T,energy,admissible,stable,max_multiplier,impact_velocity' && ok ||
    bad "backbone.csv header"
  if command -v gnuplot >/dev/null; then
    for f in response_energy response_amplitude; do
      [ -s "$tmp/resp/$f.png" ] && [ -s "$tmp/resp/$f.svg" ] && [ -s "$tmp/resp/$f.pdf" ] && [ -s "$tmp/resp/$f.column.pdf" ] &&
        ok || bad "response: $f chart"
    done
    python3 "$src/scripts/check_figure_colours.py" "$tmp/resp" >"$tmp/resp_colours.txt" && ok \
      || bad "response: chart check: $(grep FAIL "$tmp/resp_colours.txt" | head -3)"
  fi
  grep -q "the nonsmooth mode at that energy" "$tmp/resp.log" && ok || bad "response: no peak-to-mode distance printed"
else
  bad "response failed: $(cat "$tmp/resp.log")"
fi
# continue (issue 26): the response followed in a scene parameter; the
# CSVs' first column is named as the parameter; a bad name, a range that
# leaves the valid scene and a scene without a force are refused, naming them.
if "$bin" continue "$forced" --parameter 'springs[2]' --range 1.5:2.5:0.01 --out "$tmp/cont" >"$tmp/cont.log" 2>&1; then
  head -1 "$tmp/cont/continuation.csv" | grep -q '^springs\[2\],w,amplitude,period,impacts,energy,' && ok ||
    bad "continuation.csv header: $(head -1 "$tmp/cont/continuation.csv")"
  head -1 "$tmp/cont/continuation_points.csv" | grep -q '^springs\[2\],w,amplitude,kind,energy,' && ok ||
    bad "continuation_points.csv header"
  python3 -c "
import csv
rows = list(csv.DictReader(open('$tmp/cont/continuation.csv')))
k = [float(r['springs[2]']) for r in rows]
assert len(rows) > 100 and min(k) >= 1.5 - 1e-12 and max(k) <= 2.5 + 1e-12, (len(rows), min(k), max(k))
assert all(float(r['residual']) < 1e-12 for r in rows)
" && ok || bad "continuation.csv rows"
else
  bad "continue failed: $(cat "$tmp/cont.log")"
fi
# continue --second (issue 26): the grazing curves in (frequency, amplitude),
# every point on its defining condition, the flags without --second refused.
if "$bin" continue "$forced" --parameter frequency --range 0.5:0.8 --second amplitude --second-range 0.05:1 \
    --follow grazing --out "$tmp/curve" >"$tmp/curve.log" 2>&1; then
  head -1 "$tmp/curve/curve.csv" | grep -q '^frequency,amplitude,kind,w,amplitude,period,' && ok ||
    bad "curve.csv header: $(head -1 "$tmp/curve/curve.csv")"
  python3 -c "
import csv
rows = [r for r in csv.DictReader(open('$tmp/curve/curve.csv')) if r['kind'] == 'grazing']
assert len(rows) > 100 and all(abs(float(r['condition'])) < 1e-12 for r in rows), len(rows)
" && ok || bad "curve.csv rows"
else
  bad "continue --second failed: $(cat "$tmp/curve.log")"
fi
expect_error "\-\-follow: must be fold, period-doubling or grazing" "$bin" continue "$forced" --parameter frequency --range 0.5:0.8 --second amplitude --second-range 0.05:1 --follow cusp --out "$tmp/c2"
expect_error "\-\-second-range: is needed" "$bin" continue "$forced" --parameter frequency --range 0.5:0.8 --second amplitude --follow fold --out "$tmp/c2"
expect_error "\-\-follow: is given without \-\-second" "$bin" continue "$forced" --parameter frequency --range 0.5:0.8 --follow fold --out "$tmp/c2"
expect_error "\-\-second-range" "$bin" continue "$forced" --parameter frequency --range 0.5:0.8 --second amplitude --second-range 1:0.1 --follow fold --out "$tmp/c2"
expect_error "\-\-parameter: 'stiffness' is not a parameter" "$bin" continue "$forced" --parameter stiffness --range 1:2 --out "$tmp/c2"
expect_error "\-\-parameter: 'masses\[3\]': the model has 2 masses" "$bin" continue "$forced" --parameter 'masses[3]' --range 1:2 --out "$tmp/c2"
expect_error "system.restitution" "$bin" continue "$forced" --parameter restitution --range 0.5:1.5 --out "$tmp/c2"
expect_error "system.masses" "$bin" continue "$forced" --parameter 'masses[1]' --range -1:2 --out "$tmp/c2"
# A spring at 0 frees a rigid-body mode; an undamped scene at e = 1 has no
# isolated response: refused naming --range and the value, before any file.
expect_error "\-\-range: at springs\[1\] = 0: the model has 1 rigid-body modes" "$bin" continue "$forced" --parameter 'springs[1]' --range 0:1 --out "$tmp/c2"
expect_error "\-\-range: at restitution = 1: " "$bin" continue "$(scene undamped '[system]\nmasses=[1,1]\nsprings=[0.85,2]\ngap=1\nrestitution=0.8\n[forcing]\namplitude=[0.3,0]\nfrequency=0.5\n')" --parameter restitution --range 0.5:1 --out "$tmp/c2"
expect_error "\-\-range" "$bin" continue "$forced" --parameter gap --range ' 1:2' --out "$tmp/c2"
expect_error "\-\-range" "$bin" continue "$forced" --parameter gap --range 2:1 --out "$tmp/c2"
expect_error "\-\-range" "$bin" continue "$forced" --parameter gap --range 1:x --out "$tmp/c2"
expect_error "\-\-period: is needed for a scene with no \[forcing\]" "$bin" continue "$src/configs/paper.toml" --parameter gap --range 1:2 --out "$tmp/c2"
expect_error "\-\-parameter: 'restitution' does not change the free" "$bin" continue "$src/configs/paper.toml" --parameter restitution --range 0.5:1 --period 2:10:0.1 --out "$tmp/c2"
expect_error "\-\-period" "$bin" continue "$forced" --parameter gap --range 1:2 --period 2:10:0.1 --out "$tmp/c2"
# A free scene: its 1-impact transitions followed in a spring.
if "$bin" continue "$src/configs/paper.toml" --parameter 'springs[2]' --range 1.5:2.5:0.1 --period 2:30:0.01 \
    --out "$tmp/fam" >"$tmp/fam.log" 2>&1; then
  head -1 "$tmp/fam/transitions.csv" | grep -q '^springs\[2\],T,kind,energy,contact,track$' && ok ||
    bad "transitions.csv header: $(head -1 "$tmp/fam/transitions.csv")"
else
  bad "continue on a free scene failed: $(cat "$tmp/fam.log")"
fi
[ ! -e "$tmp/c2" ] && ok || bad "a refused continue left $tmp/c2"
expect_error "\-\-frequency" "$bin" response "$forced" --frequency 0.4:1:0.1 --amplitude 0.1:0.2:0.1 --out "$tmp/r2"
expect_error "\-\-amplitude" "$bin" response "$forced" --amplitude 0.3 --out "$tmp/r2"
expect_error "\-\-amplitude" "$bin" response "$forced" --frequency 0.4:1:0.1 --amplitude -1 --out "$tmp/r2"
expect_error "\-\-frequency" "$bin" response "$forced" --frequency 1:0.4:0.1 --out "$tmp/r2"
expect_error "\-\-impacts" "$bin" response "$forced" --impacts 9 --frequency 0.4:1:0.1 --out "$tmp/r2"
expect_error "\-\-periods" "$bin" response "$forced" --impacts 0 --periods 2 --frequency 0.4:1:0.1 --out "$tmp/r2"
expect_error "forcing.amplitude" "$bin" response "$paper" --frequency 0.4:1:0.1 --out "$tmp/r2"
expect_error "e = 1" "$bin" response "$(scene undamped '[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[0.85,2]\n[forcing]\namplitude=[0.3,0]\nfrequency=0.5\n')" --frequency 0.4:1:0.1 --out "$tmp/r2"
expect_error "system.damping_matrix" "$bin" response "$(scene negdamp '[system]\ngap=1\nrestitution=1\nmasses=[1,1]\nsprings=[0.85,2]\ndamping_matrix=[[0.1,0],[0,-0.1]]\n[forcing]\namplitude=[0.3,0]\nfrequency=0.5\n')" --frequency 0.4:1:0.1 --out "$tmp/r2"
expect_error "forcing.amplitude" "$bin" simulate "$(scene badlen '[system]\ngap=1\nrestitution=0.5\nmasses=[1,1]\nsprings=[0.85,2]\n[forcing]\namplitude=[0.3]\nfrequency=0.5\n[simulate]\ninitial_position=[0,0]\ninitial_velocity=[0,0]\n')" --out "$tmp/r2"
expect_error "system" "$bin" orbits "$forced" --period 1:2:0.5 --out "$tmp/r2"
expect_error "\-\-integrators" "$bin" response "$forced" --frequency 0.4:1:0.1 --validate 10 --integrators euler --out "$tmp/r2"
[ ! -e "$tmp/r2/response.csv" ] && ok || bad "a refused response left response.csv"

# --format hdf5 (issue 25): the sweep's HDF5 file holds what its CSV holds, column by
# column (missing: NaN in a float dataset, an empty CSV field); the other format's file
# of an earlier run in the same directory is removed; a bad format names --format.
"$bin" orbits "$paper" --impacts 1 --period 2:12:0.05 --out "$tmp/fmt" >/dev/null && cp "$tmp/fmt/orbits.csv" "$tmp/orbits.csv"
"$bin" orbits "$paper" --impacts 1 --period 2:12:0.05 --out "$tmp/fmt" --format hdf5 >/dev/null
if [ -s "$tmp/fmt/orbits.h5" ] && [ -s "$tmp/fmt/transitions.h5" ] && [ ! -e "$tmp/fmt/orbits.csv" ] &&
  /usr/bin/python3 - "$tmp/orbits.csv" "$tmp/fmt/orbits.h5" <<'PY'
import csv, math, sys
import h5py
rows = list(csv.DictReader(open(sys.argv[1])))
with h5py.File(sys.argv[2], "r") as f:
    assert list(f.attrs["columns"]) == list(rows[0].keys()), "columns"
    for name in rows[0]:
        data = f[name][()]
        assert len(data) == len(rows), name
        for r, v in zip(rows, data):
            text = r[name]
            if text == "":
                assert (isinstance(v, float) and math.isnan(v)) or v in (False, b"", ""), (name, v)
            elif data.dtype.kind == "f":
                assert float(text) == v, (name, text, v)  # 17 digits read back exactly
            elif data.dtype.kind == "b":
                assert (text == "1") == bool(v), (name, text, v)
            else:
                assert int(text) == v, (name, text, v)
PY
then ok; else bad "orbits --format hdf5 does not hold what orbits.csv holds"; fi
expect_error "^error: --format: must be csv or hdf5" "$bin" orbits "$paper" --period 2:3:1 --out "$tmp/fmt" --format xlsx

finish
