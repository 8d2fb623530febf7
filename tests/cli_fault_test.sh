#!/usr/bin/env bash
# Issue 29, items 2 and 3: a run that fails or is stopped leaves no result
# file of its own (output.h: every result is committed under a temporary name,
# and a failed run removes what it had committed), charts included.
# Usage: cli_fault_test.sh NSMODAL_BINARY SOURCE_DIR
. "$(dirname "$0")/cli_harness.sh" "$@"
paper=$src/configs/paper.toml
forced=$src/configs/forced.toml

# no_results DIR WHAT: DIR holds no file at all (the results removed, the
# temporaries too; an empty gnuplot log is not kept either).
no_results() {
  local left
  left=$(ls -A "$1" 2>/dev/null)
  [ -z "$left" ] && ok || bad "$2 left: $left"
}

# 1. A full disk. A small tmpfs where this test may mount one (root, as in
#    CI), else a file-size limit: SIGXFSZ ignored (inherited by gnuplot), so
#    every write past 8 KiB fails with EFBIG as one on a full disk fails with
#    ENOSPC. The tables (2-5 KiB) fit; the images (40 KiB and more) do not,
#    and gnuplot exits 0 leaving a truncated image: only the image's end
#    marker tells (gnuplot.cc).
full=$tmp/full
mkdir -p "$full"
if [ "$(id -u)" -eq 0 ] && mount -t tmpfs -o size=64k nsmodal-test "$full" 2>/dev/null; then
  trap 'umount "$full" 2>/dev/null; rm -rf "$tmp"' EXIT
  limit() { "$@"; }
  how="a 64 KiB tmpfs"
else
  limit() { (trap '' XFSZ; ulimit -f 16; exec "$@"); }
  how="a file-size limit of 8 KiB"
fi
for cmd in "figures $paper --period 0.05:12:0.05" "bench $paper --quick" \
  "response $forced --frequency 0.3:3.0:0.05 --amplitude 0.1,0.3"; do
  name=${cmd%% *}
  # shellcheck disable=SC2086
  limit "$bin" $cmd --out "$full/$name" >/dev/null 2>"$tmp/$name.err"
  rc=$?
  [ "$rc" -eq 5 ] && ok || bad "$name on $how: exit $rc, expected 5 ($(tail -2 "$tmp/$name.err"))"
  grep -q "unknown error" "$tmp/$name.err" && bad "$name on $how: 'unknown error' instead of the system's reason" || ok
  no_results "$full/$name" "$name on $how"
done

# 2. SIGTERM and SIGINT in the middle of `figures` (22 s on the default grid
#    on two cores; stopped after 2 s, while it sweeps or draws): exit 143 or
#    130, a message, and no figure left, though some were finished.
for sig in TERM INT; do
  out=$tmp/sig$sig
  "$bin" figures "$paper" --out "$out" >/dev/null 2>"$tmp/sig.err" &
  pid=$!
  sleep 2
  kill -"$sig" "$pid"
  wait "$pid"
  rc=$?
  want=$([ "$sig" = TERM ] && echo 143 || echo 130)
  [ "$rc" -eq "$want" ] && ok || bad "figures stopped by SIG$sig: exit $rc, expected $want"
  grep -q "interrupted by SIG$sig" "$tmp/sig.err" && ok || bad "SIG$sig: no message: $(cat "$tmp/sig.err")"
  no_results "$out" "figures stopped by SIG$sig"
done
# A stopped simulation is not a finished one: exit 143, no trajectory.
"$bin" simulate "$src/configs/paper-simulate.toml" --t-end 1e7 --sample-dt 0 --out "$tmp/simterm" >/dev/null 2>&1 &
pid=$!
sleep 1
kill -TERM "$pid"
wait "$pid"
rc=$?
[ "$rc" -eq 143 ] && ok || bad "simulate stopped by SIGTERM: exit $rc, expected 143"
no_results "$tmp/simterm" "simulate stopped by SIGTERM"

finish
