#!/bin/bash
# Re-measures a finished ring run's band under other rules from its frames
# (VALIDATION.md, "Band fraction of test 1"): each variant is a directory beside the run
# with the run's frames linked and its scenario's [analysis] tables replaced, analysed
# by `grains analyze` (the run's rule: `ring` in analysis.json; the dispersal
# analysis: `dispersal`).
#   r80: the run's rule at φ ≥ 0.8        d84: dispersal, 0.84, 5 d0, hat kernel (defaults)
#   d84_10: dispersal, 10 d0 bins         d80: dispersal at 0.8
#   d84_plain: dispersal, plain bins
# usage: bench/remeasure.sh RUN_DIR [GRAINS_BINARY]
set -e
G=${2:-grains}
run=$(realpath "$1"); name=$(basename "$run"); V=$(dirname "$run")
base=$(sed '/^\[analysis\]/,$d' "$run/scenario.toml")
mk() {
  local d=$V/${name}_$1
  rm -rf "$d"; mkdir -p "$d"; ln -s "$run/frames" "$d/frames"
  printf '%s\n\n%b\n' "$base" "$2" > "$d/scenario.toml"
  "$G" analyze "$d" --out "$d/analysis" --json > "$d/analysis.out"
}
mk r80 '[analysis]\nband_fraction = 0.8\n'
mk d84 '[analysis]\n[analysis.dispersal]\n'
mk d84_10 '[analysis]\n[analysis.dispersal]\nradial_bin = 10.0\n'
mk d80 '[analysis]\n[analysis.dispersal]\n[analysis.dispersal.band]\nband_fraction = 0.8\n'
mk d84_plain '[analysis]\n[analysis.dispersal]\nkernel_width = 0.0\n'
