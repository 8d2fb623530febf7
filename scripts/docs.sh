#!/usr/bin/env bash
# Builds the documentation site (docs/source: Sphinx + MyST, the tutorials as
# Jupyter notebooks by nbsphinx, the C++ reference by Doxygen + Breathe) into
# build/docs/html, with warnings as errors, bounded in time, and checks it.
#
# Usage: bash scripts/docs.sh [MODULE_DIR]
#   MODULE_DIR: the directory holding the built Python package (nsmodal/), whose
#   docstrings give the Python reference and which executes the tutorials. Default:
#   build/python. When it is given explicitly it must import; when the default does
#   not exist or does not import, the site is built without the Python reference and
#   with the tutorials not executed (their pages say so).
# Environment: DOCS_TIMEOUT (seconds, default 300: Doxygen and Sphinx together),
# DOCS_CELL_TIMEOUT (seconds a notebook cell may run, default 60), DOCS_OUT
# (default build/docs), NSMODAL_BIN (default build/cli/nsmodal: its `settings
# --json` makes the settings reference page; required when MODULE_DIR is given).
#
# Steps, each failing the script: the notebooks are stored without outputs;
# Doxygen (XML only,
# docs/doxygen/Doxyfile, warnings fail it) into build/docs/doxygen; Sphinx with
# -W (the notebooks executed when the module imports: a cell that raises or runs
# past DOCS_CELL_TIMEOUT fails the build); then each executed notebook's page
# must show the figure of every cell that draws one (docs/check_notebooks.py).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

module_dir=${1:-build/python}
explicit=$(( $# > 0 ))
timeout_s=${DOCS_TIMEOUT:-300}
cell_timeout_s=${DOCS_CELL_TIMEOUT:-60}
out=${DOCS_OUT:-build/docs}
python=/usr/bin/python3   # Debian's: where apt put Sphinx (and NumPy, for the module)

fail() { echo "docs: $*" >&2; exit 1; }

"$python" -c "import sphinx, myst_parser, sphinx_rtd_theme, nbsphinx, breathe, ipykernel" 2>/dev/null ||
  fail "a documentation package is missing: run bash scripts/setup.sh (python3-sphinx, python3-myst-parser, python3-sphinx-rtd-theme, python3-nbsphinx, python3-breathe, python3-ipykernel)"
for tool in doxygen pandoc; do
  command -v "$tool" >/dev/null || fail "$tool is missing: run bash scripts/setup.sh (Debian package $tool)"
done

# The tutorials are stored without outputs (the build executes them).
"$python" docs/check_notebooks.py stored || fail "store the notebooks without outputs (see above)"

pythonpath=""
if [ -d "$module_dir" ]; then
  module_dir=$(cd "$module_dir" && pwd)
  if PYTHONPATH="$module_dir" "$python" -c "import nsmodal" 2>/dev/null; then
    pythonpath=$module_dir
    echo "docs: Python reference from $(PYTHONPATH="$module_dir" "$python" -c 'import nsmodal; print(nsmodal.__file__)')"
  elif [ "$explicit" -eq 1 ]; then
    PYTHONPATH="$module_dir" "$python" -c "import nsmodal" || true
    fail "the module in $module_dir does not import (see above)"
  fi
elif [ "$explicit" -eq 1 ]; then
  fail "$module_dir: no such directory (the built module's directory, e.g. build/python)"
fi
if [ -n "$pythonpath" ]; then
  execute=always
else
  execute=never
  echo "docs: no importable module in $module_dir: building without the Python reference, tutorials not executed"
fi

# The settings reference page is made from `nsmodal settings --json` (the one
# settings table): the built command, as the module is the built one.
nsmodal_bin=${NSMODAL_BIN:-$root/build/cli/nsmodal}
if [ -x "$nsmodal_bin" ]; then
  export NSMODAL_BIN=$nsmodal_bin
elif [ "$explicit" -eq 1 ]; then
  fail "$nsmodal_bin: no built nsmodal command (build the project first, or set NSMODAL_BIN)"
else
  echo "docs: no built nsmodal command: building without the settings reference"
  export NSMODAL_BIN=""
fi

rm -rf "$out/html" "$out/doctrees" "$out/doxygen"
mkdir -p "$out/doxygen"
out_abs=$(cd "$out" && pwd)
start=$(date +%s)
deadline=$(( start + timeout_s ))

# The C++ reference's XML (read by Breathe), from the public headers.
status=0
NSMODAL_DOXYGEN_OUT="$out_abs/doxygen" timeout --kill-after=10 "$timeout_s" doxygen docs/doxygen/Doxyfile || status=$?
case $status in
  0) ;;
  124|137) fail "doxygen did not finish within ${timeout_s} s (DOCS_TIMEOUT)" ;;
  *) fail "doxygen failed (exit $status): every warning above is an error" ;;
esac
doxygen_s=$(( $(date +%s) - start ))

# -W: a warning fails the build; --keep-going: report all of them first.
# -E: read every page again (nothing stale from an earlier build).
# The notebooks run in a python3 kernel of this environment (PYTHONPATH: the
# module); MPLBACKEND is unset so that the kernel's inline backend shows figures.
# Jupyter's and IPython's directories are fresh ones under $out, and the user
# site (~/.local) is off (PYTHONNOUSERSITE): a kernel spec or a startup file in
# the user's home (say a "python3" kernel of another Python, without NumPy)
# cannot change what runs.
left=$(( deadline - $(date +%s) ))
[ "$left" -gt 0 ] || fail "no time left for Sphinx within ${timeout_s} s (DOCS_TIMEOUT)"
jupyter_home="$out_abs/jupyter"
rm -rf "$jupyter_home" && mkdir -p "$jupyter_home"/{config,data,runtime,ipython}
status=0
env -u MPLBACKEND -u JUPYTER_PATH PYTHONNOUSERSITE=1 PYDEVD_DISABLE_FILE_VALIDATION=1 \
  JUPYTER_CONFIG_DIR="$jupyter_home/config" JUPYTER_DATA_DIR="$jupyter_home/data" \
  JUPYTER_RUNTIME_DIR="$jupyter_home/runtime" IPYTHONDIR="$jupyter_home/ipython" \
  PYTHONPATH="$pythonpath" NSMODAL_DOXYGEN_XML="$out_abs/doxygen/xml" \
  NSMODAL_DOCS_EXECUTE="$execute" NSMODAL_DOCS_CELL_TIMEOUT="$cell_timeout_s" \
  timeout --kill-after=10 "$left" \
  "$python" -m sphinx -W --keep-going -E -q -b html -d "$out/doctrees" docs/source "$out/html" || status=$?
elapsed=$(( $(date +%s) - start ))
case $status in
  0) ;;
  124|137) fail "sphinx-build did not finish within ${timeout_s} s with Doxygen (DOCS_TIMEOUT)" ;;
  *) fail "sphinx-build failed (exit $status, ${elapsed} s): every warning above is an error" ;;
esac

# Each executed notebook's page shows the figure of every cell that draws one.
if [ "$execute" = always ]; then
  "$python" docs/check_notebooks.py figures "$out/html" || fail "a tutorial's figure is missing (see above)"
  tutorials="tutorials executed"
else
  tutorials="tutorials NOT executed (no module)"
fi
echo "docs: built $root/$out/html/index.html in ${elapsed} s (Doxygen ${doxygen_s} s; $tutorials)"
