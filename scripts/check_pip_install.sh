#!/usr/bin/env bash
# The pip install a researcher does, offline: a fresh venv that sees Debian's
# packages, `pip install --no-build-isolation --no-index .` (setuptools from
# Debian, a CMake build of the module), then `import nsmodal` from another
# directory, with the version CMakeLists.txt gives. CI runs it after the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
src=$PWD
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
expected=$(sed -n 's/^project(nsmodal VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
[ -n "$expected" ] || { echo "pip install: no project(nsmodal VERSION ...) in CMakeLists.txt" >&2; exit 1; }

/usr/bin/python3 -m venv --system-site-packages "$work/v"
start=$(date +%s)
timeout --kill-after=10 "${PIP_INSTALL_TIMEOUT:-900}" \
  "$work/v/bin/pip" install --quiet --no-build-isolation --no-index "$src" ||
  { echo "pip install: failed or timed out (exit $?)" >&2; exit 1; }
(cd "$work" && "$work/v/bin/python" -c "
import nsmodal
assert nsmodal.__file__.startswith('$work/v/'), nsmodal.__file__
assert nsmodal.__version__ == '$expected', (nsmodal.__version__, '$expected')
import os
package = os.path.dirname(nsmodal.__file__)
assert all(os.path.isfile(os.path.join(package, f)) for f in ('__init__.pyi', 'py.typed')), os.listdir(package)
m = nsmodal.Model(masses=[1, 1], springs=[0.85, 2], gap=1.0, restitution=1.0)
print('pip install: nsmodal', nsmodal.__version__, 'from', nsmodal.__file__, m.linear_periods)
")
echo "pip install: 1 passed, 0 failed ($(( $(date +%s) - start )) s)"
