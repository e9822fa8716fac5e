#!/bin/sh
# Runs the end-to-end tests that start pwsim processes N times while stress-ng keeps every core
# busy, and prints how often each test passed. Evidence that the tests synchronise on events,
# not on scheduling luck (issue 10, item 8; issue 42, item 5): the three-process session tests
# (hardware_e2e_test), platform-sim as a process (hardware_platform_sim_e2e_test) and the
# headset and drive links (hardware_link_e2e_test), all with tests/hardware/child_process.h.
#
# Usage: scripts/e2e-under-load.sh [N=50] [BUILD_DIR=build] [STRESSORS=nproc]
# Needs: BUILD_DIR/pwsim and the test binaries built; stress-ng.
# The binaries are copied first, so rebuilding meanwhile does not change what is tested.
set -eu
n=${1:-50}
build=${2:-build}
stressors=${3:-$(nproc)}
tests="hardware_e2e_test hardware_platform_sim_e2e_test hardware_link_e2e_test"
for f in "$build/pwsim" $(for t in $tests; do echo "$build/tests/hardware/$t"; done); do
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
for t in $tests; do cp "$build/tests/hardware/$t" "$work/$t"; done

# One CPU hog per core (or STRESSORS), for as long as the runs take.
stress-ng --cpu "$stressors" --cpu-method matrixprod --quiet >/dev/null 2>&1 &
stress_pid=$!

echo "e2e-under-load: $n runs of $tests with stress-ng --cpu $stressors on $(nproc) cores"
echo "  load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
: >"$work/results"
i=1
while [ "$i" -le "$n" ]; do
  failed=""
  for t in $tests; do
    PWSIM_E2E_PWSIM="$work/pwsim" "$work/$t" >"$work/run.log" 2>&1 || true
    grep -E '^\[ +(OK|FAILED|SKIPPED) +\] [A-Za-z0-9_/.]+ \(' "$work/run.log" |
      sed -E 's/^\[ +([A-Z]+) +\] ([A-Za-z0-9_/.]+) .*/\2 \1/' >>"$work/results"
    if grep -q '^\[  FAILED  \] [A-Za-z0-9_/.]* (' "$work/run.log"; then
      failed="$failed $t"
      grep -B2 -A12 'Failure' "$work/run.log" | head -40 | sed 's/^/    /'
    fi
  done
  if [ -n "$failed" ]; then
    echo "  run $i: FAILED in$failed"
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
