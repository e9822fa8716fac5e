#!/usr/bin/env bash
# Times the identification of 30 generated trials with pwsim (Ceres) and, in the same run, the
# same output-error problem solved with scipy.optimize.least_squares; prints both and the ratio.
#   scripts/bench-identify.sh [BUILD_DIR]      (default: build; builds identify_bench if needed)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
if [ ! -x "$build/bench/identify_bench" ]; then
  cmake --build "$build" --target identify_bench -j2
fi
# Debian's python3 carries python3-scipy; a python3 earlier on PATH (pyenv, venv) may not.
python=python3
if ! "$python" -c "import scipy" 2>/dev/null && [ -x /usr/bin/python3 ]; then python=/usr/bin/python3; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

echo "== pwsim (C++, Ceres Solver)"
"$build/bench/identify_bench" --export "$work" --repeats 5
echo "== scipy.optimize.least_squares on the same output-error problem"
"$python" "$root/bench/identify_scipy.py" "$work" | tee "$work/scipy.txt"

pwsim_oe=$("$python" -c "import json,sys; print(json.load(open(sys.argv[1]))['pwsim_oe_seconds'])" "$work/problem.json")
pwsim_full=$("$python" -c "import json,sys; print(json.load(open(sys.argv[1]))['pwsim_full_seconds'])" "$work/problem.json")
scipy_s=$(awk '/^SCIPY_SECONDS/ {print $2}' "$work/scipy.txt")
"$python" - "$pwsim_full" "$pwsim_oe" "$scipy_s" <<'PY'
import sys
full, oe, sp = map(float, sys.argv[1:])
print("== summary")
print(f"pwsim identify, 30 trials (GM + linear start + 2 OE passes + fits): {full*1e3:8.1f} ms "
      f"(goal < 2000 ms: {'met' if full < 2.0 else 'NOT met'})")
print(f"output-error stage, pwsim (Ceres):                          {oe*1e3:8.1f} ms")
print(f"output-error stage, scipy least_squares:                    {sp*1e3:8.1f} ms")
print(f"ratio scipy / pwsim on the same problem:                    {sp/oe:8.1f} x")
PY
