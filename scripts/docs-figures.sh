#!/usr/bin/env bash
# Regenerates the MCA and render figures of docs/measurements.md and docs/ (mca.md, render.md) with the
# built pwsim. Data: the default scene (simulated, scenes/speed_cushion.yaml), the OMCT of both
# shipped platforms (simulated test signals), and mca-validate on trials generated in-process by
# synth/ (the same chair model as the MCA's model input: a consistency check, not real data).
# Usage: scripts/docs-figures.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
pwsim="$build/pwsim"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$pwsim" run --out "$work/run" --png-frames > /dev/null
cp "$work/run/mca.png" docs/mca_speed_cushion.png
cp "$work/run/mca.svg" docs/mca_speed_cushion.svg
cp "$work/run/visual_check.png" docs/images/visual_check.png
cp "$work/run/frames/frame_00150.png" docs/images/default_frame.png

"$pwsim" omct --platform scenes/platforms/pw4dof.yaml --out "$work/omct_pw" > /dev/null
cp "$work/omct_pw/omct.png" docs/mca_omct_pw4dof.png
"$pwsim" omct --platform scenes/platforms/car2dof.yaml --out "$work/omct_car" > /dev/null
cp "$work/omct_car/omct.png" docs/mca_omct_car2dof.png

"$pwsim" mca-validate --out "$work/validate" > /dev/null
cp "$work/validate/mca_validation.png" docs/mca_validation.png
echo "docs-figures: wrote docs/mca_*.png, docs/images/visual_check.png, docs/images/default_frame.png"
