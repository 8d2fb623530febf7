#!/usr/bin/env bash
# Quick start: install what is missing, build, and run the main job on the
# default scene (configs/paper.toml, the paper's 2-dof system).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# Install the libraries, headers, CMake package, CLI and Python module (/usr/local).
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
$sudo cmake --install build >/dev/null
scene=configs/paper.toml
echo
echo "== 1 impact per period, T in [0.05, 40] step 0.001 (orbits, transitions)"
build/cli/nsmodal orbits "$scene" --impacts 1 --period 0.05:40:0.001 --out out/paper/one-impact
echo
echo "== 2 impacts per period, T in [0.05, 40] step 0.01"
build/cli/nsmodal orbits "$scene" --impacts 2 --period 0.05:40:0.01 --out out/paper/two-impact
echo
echo "== transitions of the 1-ipp family"
cat out/paper/one-impact/transitions.csv
echo
echo "== the paper's figures 2-15 and two of our own (PNG, SVG, PDF, CSV), stability on every branch"
build/cli/nsmodal figures "$scene" --out out/paper/figures
echo
echo "== simulate a non-periodic start with the three integrators"
for integrator in exact cvode moreau-jean; do
  build/cli/nsmodal simulate configs/paper-simulate.toml --integrator "$integrator" --t-end 50 --step 1e-4 \
    --out "out/paper/simulate-$integrator"
done
echo
echo "== validate the 1- and 2-ipp orbits of T in [2, 30] by 1,000 periods of simulation (exact, CVODE)"
build/cli/nsmodal validate "$scene" --period 2:30:0.5 --impacts 1 2 --integrators exact cvode --out out/paper/validate
echo
echo "== speed against accuracy, quick version (the full one: nsmodal bench $scene --out DIR)"
build/cli/nsmodal bench "$scene" --quick --out out/paper/bench | tail -8
echo
echo "== from Python: the paper's linear periods, and Fig. 8 redrawn with matplotlib"
python3 -c "import nsmodal; print('T_i =', nsmodal.load_scene('$scene').linear_periods)"
python3 examples/fep_and_trajectory.py "$scene" out/paper/python
echo
echo "== 3 impacts per period: exploratory search (paper section 2.3)"
# (into a file first: head closing the pipe early would fail the script under pipefail)
build/cli/nsmodal explore "$scene" --impacts 3 --period 1:40:0.5 --grid 24 >out/paper/explore-3.txt
head -6 out/paper/explore-3.txt
echo "(all findings: out/paper/explore-3.txt)"
echo
echo "== forced, damped responses beside the nonsmooth mode (configs/forced.toml: 2 % damping, e = 0.8),"
echo "   two forcing levels, validated by 200 periods of simulation"
build/cli/nsmodal response configs/forced.toml --frequency 0.3:3.0:0.01 --amplitude 0.1,0.3 --validate 200 \
  --out out/forced | tail -6
