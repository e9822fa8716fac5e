#!/usr/bin/env bash
# EMPS identification speed, pwsim against the same chain in scipy (side by side, same data,
# reading included). Prints both and the ratio of CPU times (the machine may be shared: CPU
# time is less disturbed than wall time). usage: scripts/bench-platform.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
source "$root/scripts/emps-dir.sh"
cpp=$(PWSIM_EMPS_DIR=$emps "$build/bench/platform_identify_bench" --benchmark_filter=BM_EmpsReadAndIdentify \
      --benchmark_min_time=2 --benchmark_format=json)
py=$(/usr/bin/python3 "$root/bench/platform_identify_scipy.py" "$emps/DATA_EMPS.mat" --repeat 30)
/usr/bin/python3 - "$cpp" "$py" <<'PY'
import json, sys
cpp = json.loads(sys.argv[1])["benchmarks"][0]
py = json.loads(sys.argv[2])
c_wall, c_cpu = cpp["real_time"] / 1e3, cpp["cpu_time"] / 1e3  # ms -> s
print(f"EMPS read + IDIM-LS (24 841 samples, 2480 rows), real data:")
print(f"  pwsim  wall {c_wall*1e3:.1f} ms, cpu {c_cpu*1e3:.1f} ms")
print(f"  scipy  wall {py['median_s']*1e3:.1f} ms, cpu {py['median_cpu_s']*1e3:.1f} ms (median of {py['repeat']})")
print(f"  ratio scipy/pwsim: cpu {py['median_cpu_s']/c_cpu:.1f}x, wall {py['median_s']/c_wall:.1f}x")
print(f"  scipy parameters {[round(x, 4) for x in py['parameters']]}, rel {py['relative_error_pct']:.4f} %")
PY
