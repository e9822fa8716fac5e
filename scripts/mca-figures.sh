#!/usr/bin/env bash
# The cueing figures and table of docs/mca.md, per shipped scene and platform: every scene in
# scenes/*.yaml on its own platform and on stewart6dof, through `pwsim run --mca mpc` (the MPC
# without preview, as a live session runs it; its summary.json carries the comparison with the
# washout and the offline ceiling on the same trial) and `pwsim run --mca washout`. Then
# scripts/mca_figures.py collects the summaries (OUT/cueing.csv, OUT/actuators.csv, OUT/table.md;
# the CSVs copied beside the figures) and gnuplot draws, each figure naming its data and commit:
#   docs/images/mca_cueing_error.png   perceived-motion error (six-channel RMS), washout / MPC / ceiling
#   docs/images/mca_cueing_xcorr.png   cross-correlation peak and its lag (the delay), same
#   docs/images/mca_cueing_stroke.png  each actuator's stroke use against what the axis boxes ask
#   scripts/mca-figures.sh [BUILD_DIR] [OUT_DIR] [IMAGES_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
out=${2:-$root/out/mca-figures}
images=${3:-$root/docs/images}
commit=$(git -C "$root" rev-parse --short HEAD)
# the cueing code or the scenes differing from the commit
if ! git -C "$root" diff --quiet HEAD -- mca report/run_mca.cc report/run_mca.h report/car_run.cc scenes; then
  commit="$commit+uncommitted"
fi
mkdir -p "$out" "$images"
for scene in "$root"/scenes/*.yaml; do
  name=$(basename "$scene" .yaml)
  for platform in own stewart6dof; do
    args=()
    [ "$platform" = own ] || args=(--platform "scenes/platforms/$platform.yaml")
    (cd "$root" && "$build/pwsim" run "scenes/$name.yaml" --no-video --mca mpc "${args[@]}" \
        --out "$out/$name/$platform/mpc" > /dev/null)
    (cd "$root" && "$build/pwsim" run "scenes/$name.yaml" --no-video --mca washout --no-mca-compare "${args[@]}" \
        --out "$out/$name/$platform/washout" > /dev/null)
    echo "mca-figures: $name on $platform done"
  done
done
python3 "$root/scripts/mca_figures.py" "$out" "$commit"
gnuplot -e "dir='$out'; images='$images'; commit='$commit'" "$root/scripts/mca_figures.gp"
cp "$out/cueing.csv" "$images/mca_cueing.csv"  # the figures' data beside them
cp "$out/actuators.csv" "$images/mca_cueing_actuators.csv"
echo "mca-figures: wrote $out/table.md, $images/mca_cueing{,_actuators}.csv and $images/mca_cueing_{error,xcorr,stroke}.png (pwsim $commit)"
