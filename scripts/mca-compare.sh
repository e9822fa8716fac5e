#!/usr/bin/env bash
# Washout vs online MPC (held input, and with the trial previewed) vs the offline optimum on the
# speed cushion and the car's launch and lane change: `pwsim run --mca ...` for each, then
# scripts/mca_compare.py writes the table of docs/mca.md (perceived-motion RMS error per axis,
# false cues, actuator stroke used, MPC fallbacks) and the figure docs/images/mca_compare.png; then
# `pwsim omct --mca washout|mpc` on the PW 4-DoF and the car rail + yaw platforms for the OMCT
# gain and phase table (the MPC with the held input).
#   scripts/mca-compare.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
out=${2:-$root/out/mca-compare}
mkdir -p "$out"
for scene in speed_cushion car_launch car_lane_change; do
  for mode in washout mpc mpc-preview offline; do
    case $mode in
      washout) args=(--mca washout) ;;
      mpc) args=(--mca mpc) ;;
      mpc-preview) args=(--mca mpc --mca-preview) ;;
      offline) args=(--mca offline) ;;
    esac
    (cd "$root" && "$build/pwsim" run "scenes/$scene.yaml" --no-video --no-mca-compare "${args[@]}" --out "$out/$scene/$mode" > /dev/null)
    echo "mca-compare: $scene $mode done"
  done
done
for platform in pw4dof car2dof; do
  for mode in washout mpc; do
    (cd "$root" && "$build/pwsim" omct --platform "scenes/platforms/$platform.yaml" --mca "$mode" \
        --out "$out/omct/$platform/$mode" > /dev/null)
    echo "mca-compare: omct $platform $mode done"
  done
done
python3 "$root/scripts/mca_compare.py" "$out" | tee "$out/table.md"
gnuplot -e "dir='$out'" "$root/scripts/mca_compare.gp" > "$out/mca_compare.png"
echo "mca-compare: wrote $out/table.md and $out/mca_compare.png"
