#!/usr/bin/env bash
# Runs every benchmark of a build folder and prints the figures quoted in docs/measurements.md:
# the Google Benchmark targets, the identification benchmark against scipy, and the time to
# diagnose 30 trials (the full confusion matrix is scripts/confusion-matrix.sh).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
for name in chair_model_bench effect_model_bench mca_bench mpc_bench render_bench can_codec_bench vehicle_bench; do
  echo "== $name"
  "$build/bench/$name" --benchmark_min_time=0.5
done
echo "== identify_bench (pwsim vs scipy)"
"$root/scripts/bench-identify.sh" "$build"
echo "== diagnose_bench (time to diagnose 30 trials)"
"$build/bench/diagnose_bench" --timing-only
echo "== pwsim diagnose through the CLI (30 generated trials, 1 and 2 threads)"
"$root/scripts/time-diagnose-cli.sh" "$build" 1
echo "== platform identify (EMPS, pwsim vs scipy)"
"$root/scripts/bench-platform.sh" "$build" || echo "(skipped: EMPS data absent)"
