#!/usr/bin/env bash
# Overhead per task of `pwsim sweep` on this machine, for the local engine and for a private
# single-node Slurm cluster (tests/sweep/slurm_cluster.sh), on scenes/sweeps/speed_sweep.yaml
# (8 tasks of `pwsim run --no-video`).
#   scripts/sweep-overhead.sh [BUILD_DIR] [REPEATS]
# For each engine and K = 1 (one task at a time): overhead per task =
#   (wall time of `pwsim sweep submit` - sum of the tasks' own command time) / tasks,
# the command time being what each task's result.json records (command_s: the child pwsim).
# It covers starting `pwsim sweep run`, reading the plan, writing logs and result.json, and for
# Slurm: sbatch, scheduling, slurmstepd, and the squeue polling (--poll-s 0.1).
set -euo pipefail
build=$(realpath "${1:-build}")
repeats=${2:-3}
src=$(cd "$(dirname "$0")/.." && pwd)
pwsim="$build/pwsim"
work=$(mktemp -d /tmp/pwsim-sweep-overhead.XXXXXX)
cluster="$work/cluster"
trap '"$src/tests/sweep/slurm_cluster.sh" stop "$cluster" 2>/dev/null || true; rm -rf "$work"' EXIT

have_slurm=1
"$src/tests/sweep/slurm_cluster.sh" start "$cluster" > /dev/null || have_slurm=0
[ $have_slurm -eq 1 ] && . "$cluster/env"

measure() {  # engine K repeat
  local dir="$work/$1-$2-$3"
  "$pwsim" sweep plan "$src/scenes/sweeps/speed_sweep.yaml" --out "$dir" > /dev/null
  local start end
  start=$(date +%s.%N)
  "$pwsim" sweep submit "$dir" --engine "$1" --max-parallel "$2" --poll-s 0.1 > /dev/null
  end=$(date +%s.%N)
  python3 - "$dir" "$start" "$end" "$2" <<'PY'
import json, pathlib, sys
d, start, end, k = pathlib.Path(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
results = [json.loads(p.read_text()) for p in sorted(d.glob("tasks/*/result.json"))]
assert len(results) == 8 and all(r["status"] == "ok" for r in results), "not all tasks ok"
command = sum(r["command_s"] for r in results)
wall = end - start
print(f"{wall:.2f} {command:.2f} {(wall * k - command) / len(results):.3f}")
PY
}

echo "pwsim sweep overhead on $(nproc) cores ($(uname -n)), load average $(cut -d' ' -f1-3 /proc/loadavg)"
startup=$(python3 - "$pwsim" <<'PY'
import statistics, subprocess, sys, time
times = []
for _ in range(5):
    start = time.monotonic()
    subprocess.run([sys.argv[1], "--help"], stdout=subprocess.DEVNULL, check=True)
    times.append(time.monotonic() - start)
print(f"{statistics.median(times):.3f}")
PY
)
echo "start of one pwsim process (pwsim --help, median of 5): $startup s"
echo "speed_sweep.yaml, 8 tasks; overhead/task = (wall x K - sum command_s) / 8"
printf "%-7s %2s %6s %10s %14s %16s\n" engine K repeat wall_s command_s overhead_s/task
for engine in local slurm; do
  [ "$engine" = slurm ] && [ $have_slurm -eq 0 ] && { echo "slurm: skipped (no Slurm here)"; continue; }
  for k in 1 2; do
    for r in $(seq 1 "$repeats"); do
      read -r wall command overhead < <(measure "$engine" "$k" "$r")
      printf "%-7s %2s %6s %10s %14s %16s\n" "$engine" "$k" "$r" "$wall" "$command" "$overhead"
    done
  done
done
