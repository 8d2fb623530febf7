#!/usr/bin/env bash
# Installs build/ into a temporary prefix, then builds and runs a consumer
# project against it (find_package(nsmodal COMPONENTS ...)) and imports the
# Python module from the install. CI runs it after the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
src=$PWD
prefix=$(mktemp -d)
work=$(mktemp -d)
trap 'rm -rf "$prefix" "$work"' EXIT
cmake --install build --prefix "$prefix" >/dev/null
# The exported targets carry no warning flags into a consumer's build.
if grep -rq -- '-Werror\|-Wpedantic' "$prefix"/lib/cmake/nsmodal/; then
  echo "the installed package exports warning flags" >&2
  exit 1
fi
cmake -S tests/consumer -B "$work" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work" -j"$(nproc)" >/dev/null
"$work/consumer"
package=$(find "$prefix" -name '_nsmodal.cpython-*.so' -printf '%h\n' | head -1)
[ -n "$package" ] || { echo "the Python module was not installed" >&2; exit 1; }
for f in __init__.py __init__.pyi py.typed; do
  [ -f "$package/$f" ] || { echo "the Python package lacks $f" >&2; exit 1; }
done
site=$(dirname "$package")
(cd "$work" && PYTHONPATH="$site" /usr/bin/python3 -c "
import nsmodal
m = nsmodal.load_scene('$src/configs/paper.toml')
print('python module from the install:', nsmodal.__file__, m.linear_periods)
")
echo "install: 1 passed, 0 failed"
