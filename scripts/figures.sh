#!/usr/bin/env bash
# Draws the figure gallery of the documentation (docs/source/figures.md and
# forced.md) from a build, into OUT: the paper's figures and the pictures
# beside them (`figures configs/paper.toml`), Fig. 18 of two walls
# (`figures configs/clearance.toml`), the bar's (`figures
# configs/bar.toml`), the forced responses (`response configs/forced.toml`
# at two forcing levels), each chart as NAME.png, NAME.svg, NAME.pdf and
# NAME.column.pdf with its CSV and gnuplot scripts; then the chart check of
# every set (scripts/check_figure_colours.py) into OUT/colours.txt and the
# commands' printouts into OUT/figures.txt. Exits non-zero if a command or
# the check fails (OUT is then not written).
#
# Usage: scripts/figures.sh NSMODAL_BINARY OUT
#   docs/figures holds the PNGs and the two text files of a run:
#   scripts/figures.sh build/cli/nsmodal out/gallery && cp out/gallery/*.png out/gallery/*.txt docs/figures/
set -euo pipefail
[ $# -eq 2 ] || { sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
bin=$1 out=$2
src=$(cd "$(dirname "$0")/.." && pwd)
python=/usr/bin/python3
[ -x "$python" ] || python=python3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/gallery"
run() {  # NAME COMMAND...: runs it, its output to NAME.txt, its files to $tmp/NAME
  local name=$1
  shift
  "$bin" "$@" --out "$tmp/$name" >"$tmp/$name.txt" 2>&1 || { cat "$tmp/$name.txt" >&2; echo "figures.sh: $name failed" >&2; exit 1; }
}
run paper figures "$src/configs/paper.toml"
run clearance figures "$src/configs/clearance.toml"
run bar figures "$src/configs/bar.toml"
run forced response "$src/configs/forced.toml" --frequency 0.3:3.0:0.01 --amplitude 0.1,0.3
for set in paper clearance bar forced; do
  { echo "== $set"; "$python" "$src/scripts/check_figure_colours.py" "$tmp/$set"; } >>"$tmp/gallery/colours.txt" ||
    { cat "$tmp/gallery/colours.txt" >&2; echo "figures.sh: the chart check of $set failed" >&2; exit 1; }
  { echo "== $set"; cat "$tmp/$set.txt"; } >>"$tmp/gallery/figures.txt"
  # (Of the clearance's figures, Fig. 18 alone: the others are the paper's.)
  if [ $set = clearance ]; then cp "$tmp/$set"/fig18_* "$tmp/gallery/"; else cp "$tmp/$set"/* "$tmp/gallery/"; fi
done
mkdir -p "$out"
cp "$tmp/gallery"/* "$out/"
echo "figures.sh: $(ls "$tmp/gallery" | grep -c '\.png$') charts in $out"
