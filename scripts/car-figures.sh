#!/usr/bin/env bash
# The figures and numbers of docs/car.md, made through pwsim itself:
#   pwsim car-checks          closed-form checks of the car model (understeer, 0-100, energy, stall)
#   pwsim run <car scenes>    trial.csv, summary.json, mca.png and the road video with the dashboard
#   vehicle_bench             steps per second of the car model
# Data: same-model simulation of assets/cars/midsize.yaml against closed forms (no measured car).
# Usage: scripts/car-figures.sh [BUILD_DIR]   (writes docs/images/car/)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
dest=$root/docs/images/car
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$dest"
cd "$root"

"$build/pwsim" car-checks --out "$work/checks"
for stem in car_understeer car_launch car_energy car_stall; do cp "$work/checks/$stem.png" "$dest/"; done
cp "$work/checks/car_checks.json" "$dest/"

for scene in car_launch car_lane_change car_seed_drive; do
  "$build/pwsim" run "scenes/$scene.yaml" --out "$work/$scene" --size 960x540 --fps 25 --decimate 10
  cp "$work/$scene/mca.png" "$dest/${scene}_mca.png"
  cp "$work/$scene/summary.json" "$dest/${scene}_summary.json"
done
# two frames of the driver's view with the instruments
ffmpeg -loglevel error -y -ss 3.6 -i "$work/car_lane_change/video.mp4" -frames:v 1 "$dest/car_lane_change_frame.png"
ffmpeg -loglevel error -y -ss 19 -i "$work/car_seed_drive/video.mp4" -frames:v 1 "$dest/car_seed_drive_frame.png"

"$build/bench/vehicle_bench" --benchmark_min_time=0.5 | tee "$dest/vehicle_bench.txt"
echo "wrote $dest"
