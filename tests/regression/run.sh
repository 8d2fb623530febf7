#!/usr/bin/env bash
# The regression test (regression.py, README.md): today's outputs of nsmodal
# on configs/*.toml, pinned in expected/.
# Usage: run.sh NSMODAL_BINARY SOURCE_DIR [--mode exact|tolerant|update] [--only CASE...] [--keep DIR]
# Standard library only: Debian's python3 when there, else the first on PATH.
py=/usr/bin/python3
[ -x "$py" ] || py=python3
exec "$py" "$(dirname "$0")/regression.py" "$@"
