#!/usr/bin/env bash
# The drawings of docs/platforms.md: for each shipped platform, `pwsim platform describe` writes
# the geometry (actuators in B at neutral and at a shown pose) and, where the legs roll and pitch
# the plate, the (roll, pitch) workspace slices at three heaves; gnuplot draws
# docs/images/platform_<name>.png and the describe reports go to OUT_DIR/<name>.txt.
#   scripts/platform-drawings.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
out=${2:-$root/out/platform-drawings}
mkdir -p "$out" "$root/docs/images"
commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)

draw() {  # name, pose (m, m, m, deg, deg, deg), pose in words
  local name=$1 pose=$2 words=$3
  (cd "$root" && "$build/pwsim" platform describe "scenes/platforms/$name.yaml" --pose "$pose" --margin 0.05 \
      --out "$out") > "$out/$name.txt"
  local slice="$out/platform_${name}_slice.dat"
  local roll=0 pitch=0 heave=0
  if [[ -f $slice ]]; then
    read -r roll pitch heave < <(awk '/^# box:/ {print $4, $6, $8; exit}' "$slice")
  fi
  gnuplot -e "geo='$out/platform_${name}_geometry.dat'; slice='$slice'; name='$name'; words='$words'; \
commit='$commit'; roll_box=$roll; pitch_box=$pitch; heave_box=$heave; tmp='$out/$name'" \
    "$root/scripts/platform_drawings.gp" > "$root/docs/images/platform_$name.png"
  echo "platform-drawings: wrote docs/images/platform_$name.png and $out/$name.txt"
}

draw pw4dof "0,0,0.03,8,-8,20" "heave +0.03 m, roll +8 deg, pitch -8 deg, yaw +20 deg"
draw stewart6dof "0.1,0,0.05,10,0,15" "surge +0.10 m, heave +0.05 m, roll +10 deg, yaw +15 deg"
draw car2dof "0.4,0,0,0,0,30" "surge (rail) +0.4 m, yaw +30 deg"
