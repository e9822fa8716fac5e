#!/usr/bin/env bash
# Two attempts of every skill item (scenes/skills/*.yaml) driven by their own scripts through
# `pwsim run`, then their score sheet through `pwsim skills`: the first attempts as the session
# "before", the second as "after" (docs/skills.md). Data: same-model simulation of the shipped
# items (no person drove them; both attempts of a script are the same drive, so every change is 0).
# Usage: scripts/skills-sheet.sh [OUT_DIR] [BUILD_DIR]    (default out/skills-sheet, build)
# VIDEO=1 renders each run's video too (about 15 s per run instead of 1).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$root/out/skills-sheet}
build=${2:-$root/build}
video=(--no-video)
[ "${VIDEO:-0}" = 1 ] && video=(--size 640x360 --fps 25)
cd "$root"
mkdir -p "$out/runs"
before=() after=()
for file in scenes/skills/*.yaml; do
  item=$(basename "$file" .yaml)
  for attempt in 1 2; do
    "$build/pwsim" run "$file" --out "$out/runs/${item}_$attempt" --no-mca-compare --decimate 10 "${video[@]}" |
      grep "skill $item:" || { echo "no score for $item" >&2; exit 1; }
  done
  before+=("$out/runs/${item}_1") after+=("$out/runs/${item}_2")
done
join() { local IFS=,; echo "$*"; }
"$build/pwsim" skills --before "$(join "${before[@]}")" --after "$(join "${after[@]}")" --participant sim \
  --out "$out/sheet"
