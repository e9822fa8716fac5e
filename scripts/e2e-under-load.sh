#!/bin/sh
# Runs the three-process end-to-end tests (SessionEndToEnd.*) N times while stress-ng keeps
# every core busy, and prints how often each test passed. Evidence that the tests synchronise
# on events, not on scheduling luck (issue 10, item 8).
#
# Usage: scripts/e2e-under-load.sh [N=50] [BUILD_DIR=build] [STRESSORS=nproc]
# Needs: BUILD_DIR/pwsim and BUILD_DIR/tests/hardware/hardware_e2e_test built; stress-ng.
# The binaries are copied first, so rebuilding meanwhile does not change what is tested.
set -eu
n=${1:-50}
build=${2:-build}
stressors=${3:-$(nproc)}
test_bin="$build/tests/hardware/hardware_e2e_test"
for f in "$build/pwsim" "$test_bin"; do
  [ -x "$f" ] || { echo "e2e-under-load: $f not built" >&2; exit 2; }
done
command -v stress-ng >/dev/null 2>&1 || { echo "e2e-under-load: stress-ng not installed (scripts/install-deps.sh)" >&2; exit 2; }

work=$(mktemp -d "${TMPDIR:-/tmp}/pwsim_e2e_load.XXXXXX")
stress_pid=""
cleanup() {
  [ -n "$stress_pid" ] && kill "$stress_pid" 2>/dev/null && wait "$stress_pid" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT INT TERM
cp "$build/pwsim" "$work/pwsim"
cp "$test_bin" "$work/hardware_e2e_test"

# One CPU hog per core (or STRESSORS), for as long as the runs take.
stress-ng --cpu "$stressors" --cpu-method matrixprod --quiet >/dev/null 2>&1 &
stress_pid=$!

echo "e2e-under-load: $n runs of SessionEndToEnd.* with stress-ng --cpu $stressors on $(nproc) cores"
echo "  load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
: >"$work/results"
i=1
while [ "$i" -le "$n" ]; do
  PWSIM_E2E_PWSIM="$work/pwsim" "$work/hardware_e2e_test" --gtest_filter='SessionEndToEnd.*' \
    >"$work/run.log" 2>&1 || true
  grep -E '^\[ +(OK|FAILED|SKIPPED) +\] SessionEndToEnd\.[A-Za-z]+ \(' "$work/run.log" |
    sed -E 's/^\[ +([A-Z]+) +\] SessionEndToEnd\.([A-Za-z]+) .*/\2 \1/' >>"$work/results"
  if grep -q '^\[  FAILED  \] SessionEndToEnd\.[A-Za-z]* (' "$work/run.log"; then
    echo "  run $i: FAILED"; grep -B2 -A12 'Failure' "$work/run.log" | head -40 | sed 's/^/    /'
  else
    echo "  run $i: ok (load $(cut -d' ' -f1 /proc/loadavg))"
  fi
  i=$((i + 1))
done
echo "  load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "test passed/runs (skipped):"
awk '{ runs[$1]++; if ($2 == "OK") ok[$1]++; if ($2 == "SKIPPED") sk[$1]++ }
     END { bad = 0; for (t in runs) { printf "  %-60s %d/%d (%d)\n", t, ok[t] + 0, runs[t] - sk[t], sk[t] + 0;
                                      if (ok[t] + sk[t] < runs[t]) bad = 1 }
           exit bad }' "$work/results"
