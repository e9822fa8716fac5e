#!/usr/bin/env bash
# The circuit figures of docs/measurements.md and docs/render.md, made through pwsim itself: each shipped
# circuit (scenes/circuit_*.yaml) driven to its end by `pwsim run` with video; its top view and
# summary.json and its head specific force against the plausibility bound (head_force.png) go
# to docs/images/circuit/, and for circuit_course also one frame of the occupant's view, the
# MCA figures (mca.png, mca_lateral.png) and the caster/wheel-load figure. Data: same-model simulation of the shipped scenes (no measured drive).
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
  cp "$work/$scene/top_view.png" "$dest/${scene}_top_view.png"
  cp "$work/$scene/summary.json" "$dest/${scene}_summary.json"
  cp "$work/$scene/head_force.png" "$dest/${scene}_head_force.png"
  [ "$scene" = circuit_course ] || continue
  for figure in mca mca_lateral wheels; do cp "$work/$scene/$figure.png" "$dest/${scene}_$figure.png"; done
  # the frame a third of the way through the drive
  frames=$(python3 -c "import json; print(json.load(open('$work/$scene/summary.json'))['render']['frames'])")
  ffmpeg -loglevel error -y -i "$work/$scene/video.mp4" -vf "select=eq(n\,$((frames / 3)))" -frames:v 1 \
    "$dest/${scene}_frame.png"
done
ls "$dest"
