#!/usr/bin/env bash
# The documentation's figure gallery regenerates from a build with its
# documented command (scripts/figures.sh): every chart the docs show and
# every name issue 28 asks for, in PNG, SVG, page and column PDF, passing
# the chart check, within the size targets (SVG < 1.5 MB, PDF < 1 MB).
# Usage: figures_gallery_test.sh NSMODAL_BINARY SOURCE_DIR (exit 77: no gnuplot)
set -uo pipefail
bin=$1 src=$2
command -v gnuplot >/dev/null || { echo "no gnuplot: skipped"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
bad() { echo "FAIL: $*"; fail=1; }
bash "$src/scripts/figures.sh" "$bin" "$tmp/gallery" >"$tmp/log" 2>&1 || bad "scripts/figures.sh: $(tail -3 "$tmp/log")"
names="fig01_model multipliers_one_impact time_history validation_orbits fep_all_families bar_spacetime response_amplitude"
# Every gnuplot chart the docs show (docs/figures holds their PNGs).
for png in "$src"/docs/figures/*.png; do
  name=$(basename "$png" .png)
  grep -rq "figures/$name.png" "$src/docs/source" || continue
  case " bar_convergence dropped_bar modal_truncation " in *" $name "*) continue ;; esac  # the examples' (matplotlib)
  names="$names $name"
done
for name in $names; do
  for ext in png svg pdf column.pdf; do
    [ -s "$tmp/gallery/$name.$ext" ] || bad "$name.$ext not drawn"
  done
done
heavy=$(find "$tmp/gallery" \( -name '*.svg' -size +1536k \) -o \( -name '*.pdf' -size +1024k \))
[ -z "$heavy" ] || bad "too heavy: $heavy"
[ $fail = 0 ] && echo "gallery: $(echo $names | wc -w) charts regenerated, each in 4 formats"
exit $fail
