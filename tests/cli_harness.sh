# Shared by the CLI test scripts: sourced as `. cli_harness.sh NSMODAL_BINARY SOURCE_DIR`.
# Sets bin, src and a temporary directory tmp (removed on exit), counts
# results with ok/bad, and ends with `finish`.
set -u
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*"; fail=$((fail + 1)); }

# expect_error PATTERN CMD...: non-zero exit and PATTERN on stderr, no crash (exit < 128).
expect_error() {
  local pattern=$1
  shift
  "$@" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  if [ "$rc" -eq 0 ] || [ "$rc" -ge 128 ]; then
    bad "exit $rc for: $*"
  elif ! grep -q -- "$pattern" "$tmp/err"; then
    bad "message lacks '$pattern' for: $* -> $(cat "$tmp/err")"
  else
    ok
  fi
}

# scene NAME TEXT: a scene file with TEXT (printf %b escapes), its path printed.
scene() { printf '%b' "$2" >"$tmp/$1.toml"; echo "$tmp/$1.toml"; }

# The closing line ctest's reader and a person look for; the exit status.
finish() {
  echo "$pass passed, $fail failed"
  [ "$fail" -eq 0 ]
}
