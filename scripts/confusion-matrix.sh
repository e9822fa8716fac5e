#!/usr/bin/env bash
# The diagnosis' confusion matrix (hidden effect × named cause) with the fitness gains, the
# paper's case and the time to diagnose 30 trials, as Markdown (docs/diagnosis.md quotes it).
#   scripts/confusion-matrix.sh [BUILD_DIR] [SEEDS]   (default: build, 3 seeds × 2 strengths)
set -euo pipefail
build=${1:-build}
seeds=${2:-3}
cmake --build "$build" --target diagnose_bench -j2 > /dev/null
bench="$build/bench/diagnose_bench"
echo "## Confusion matrix ($seeds seeds × strengths 0.7 and 1.4; no-effect control: $seeds seeds)"
echo
"$bench" --seeds "$seeds" --strengths 0.7,1.4 --matrix-only
echo
echo "## The paper's case"
echo
"$bench" --paper-case 2.0
echo
echo "## Time"
"$bench" --timing-only
