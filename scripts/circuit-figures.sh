#!/usr/bin/env bash
# The circuit figures of README.md and docs/render.md, made through pwsim itself: each shipped
# circuit (scenes/circuit_*.yaml) driven to its end by `pwsim run` with video, then one frame
# of the occupant's view, the top view and the lateral MCA figure copied to docs/images/circuit/,
# with each summary.json. Data: same-model simulation of the shipped scenes (no measured drive).
# Usage: scripts/circuit-figures.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
dest=$root/docs/images/circuit
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$dest"
cd "$root"

for file in scenes/circuit_*.yaml; do
  scene=$(basename "$file" .yaml)
  "$build/pwsim" run "$file" --out "$work/$scene" --size 960x540 --fps 25 --decimate 10
  for figure in top_view mca_lateral wheels; do cp "$work/$scene/$figure.png" "$dest/${scene}_$figure.png"; done
  cp "$work/$scene/summary.json" "$dest/${scene}_summary.json"
  # the frame a third of the way through the drive
  frames=$(python3 -c "import json; print(json.load(open('$work/$scene/summary.json'))['render']['frames'])")
  ffmpeg -loglevel error -y -i "$work/$scene/video.mp4" -vf "select=eq(n\,$((frames / 3)))" -frames:v 1 \
    "$dest/${scene}_frame.png"
done
ls "$dest"
