#!/usr/bin/env bash
# Builds the documentation site (docs/source, Sphinx + MyST) into build/docs/html,
# with warnings as errors, bounded in time.
#
# Usage: bash scripts/docs.sh [MODULE_DIR]
#   MODULE_DIR: the directory holding the built Python module (nsmodal*.so), whose
#   docstrings give the Python reference. Default: build/python. When it is given
#   explicitly it must import; when the default does not exist or does not
#   import, the site is built without the Python reference (its page says so).
# Environment: DOCS_TIMEOUT (seconds, default 300), DOCS_OUT (default build/docs),
# NSMODAL_BIN (default build/cli/nsmodal: its `settings --json` makes the
# settings reference page; required when MODULE_DIR is given).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

module_dir=${1:-build/python}
explicit=$(( $# > 0 ))
timeout_s=${DOCS_TIMEOUT:-300}
out=${DOCS_OUT:-build/docs}
python=/usr/bin/python3   # Debian's: where apt put Sphinx (and NumPy, for the module)

fail() { echo "docs: $*" >&2; exit 1; }

"$python" -c "import sphinx, myst_parser, sphinx_rtd_theme" 2>/dev/null ||
  fail "Sphinx, MyST or the RTD theme is missing: run bash scripts/setup.sh (python3-sphinx, python3-myst-parser, python3-sphinx-rtd-theme)"

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
[ -n "$pythonpath" ] || echo "docs: no importable module in $module_dir: building without the Python reference"

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

rm -rf "$out/html" "$out/doctrees"
mkdir -p "$out"
start=$(date +%s)
status=0
# -W: a warning fails the build; --keep-going: report all of them first.
# -E: read every page again (nothing stale from an earlier build).
PYTHONPATH="$pythonpath" timeout --kill-after=10 "$timeout_s" \
  "$python" -m sphinx -W --keep-going -E -q -b html -d "$out/doctrees" docs/source "$out/html" || status=$?
elapsed=$(( $(date +%s) - start ))
case $status in
  0) echo "docs: built $root/$out/html/index.html in ${elapsed} s" ;;
  124|137) fail "sphinx-build did not finish within ${timeout_s} s (DOCS_TIMEOUT)" ;;
  *) fail "sphinx-build failed (exit $status, ${elapsed} s): every warning above is an error" ;;
esac
