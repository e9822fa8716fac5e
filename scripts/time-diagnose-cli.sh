#!/usr/bin/env bash
# Times `pwsim diagnose` through the CLI on 30 trial folders written by `pwsim generate` (the
# same-model generator: tyre compliance at strength 1, speeds 0.6-2.4 m/s by 0.2, loads 0/50/
# 100 kg, over the cushion, seed 30; the chair without gm/lm, so the base model is identified
# first, as for a lab's trials), on 1 and 2 threads interleaved, each under `nice -n 10`, and
# checks that both give the same diagnosis.json (but its `seconds`). Prints the machine's load
# average before each run: the figure is for a quiet machine only when that load is low.
#   scripts/time-diagnose-cli.sh [BUILD_DIR] [ROUNDS]     (default: build, 2 rounds)
#   PWSIM=/path/to/other/pwsim scripts/time-diagnose-cli.sh   (another binary, e.g. a before/after)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
rounds=${2:-2}
pwsim=${PWSIM:-$build/pwsim}
[ -x "$pwsim" ] || cmake --build "$build" --target pwsim -j1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$pwsim" generate --out "$work/trials" --effect tyre_compliance --strength 1 \
  --speeds 0.6,0.8,1.0,1.2,1.4,1.6,1.8,2.0,2.2,2.4 --loads 0,50,100 --cushion with --seed 30 >/dev/null
count=$(find "$work/trials" -mindepth 1 -maxdepth 1 -type d | wc -l)
for round in $(seq 1 "$rounds"); do
  for threads in 1 2; do
    load=$(cut -d' ' -f1 /proc/loadavg)
    start=$(date +%s.%N)
    nice -n 10 "$pwsim" diagnose "$work"/trials/*/ --threads "$threads" --out "$work/dx$threads" >"$work/log$threads"
    end=$(date +%s.%N)
    printf 'round %d: pwsim diagnose, %d trials, %d thread(s): %.2f s wall (load average before: %s); %s\n' \
      "$round" "$count" "$threads" "$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')" "$load" "$(head -1 "$work/log$threads")"
  done
  python3 - "$work/dx1/diagnosis.json" "$work/dx2/diagnosis.json" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
a.pop("seconds", None); b.pop("seconds", None)
print("  diagnosis.json on 1 and 2 threads: " + ("identical" if a == b else "DIFFER"))
sys.exit(0 if a == b else 1)
PY
done
