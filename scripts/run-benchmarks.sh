#!/usr/bin/env bash
# Runs every benchmark target of a build folder and prints their figures (quoted in README.md).
set -euo pipefail
build=${1:-build}
for bench in "$build"/bench/*_bench; do
  [ -x "$bench" ] || continue
  echo "== $(basename "$bench")"
  "$bench" --benchmark_min_time=0.5
done
