#!/usr/bin/env bash
# The EMPS diagnosis figures of docs/measurements.md and docs/platform.md (real data, DATA_EMPS.mat):
# `pwsim platform diagnose` with its default three-way split (blocks of 1 s: training fits,
# selection decides, report rows only report), printed as Markdown.
# usage: scripts/platform-diagnose-emps.sh [BUILD_DIR]   (PWSIM_EMPS_DIR or ../shared/data/emps)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
source "$root/scripts/emps-dir.sh"
out=${PWSIM_DIAGNOSE_OUT:-$(mktemp -d)}
"$build/pwsim" platform diagnose "$emps/DATA_EMPS.mat" --out "$out" > /dev/null
/usr/bin/python3 - "$out/diagnosis.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
roles = [b["role"] for b in d["split"]]
print("### EMPS diagnosis (real data, DATA_EMPS.mat), three-way split in blocks of 1 s\n")
print(f"blocks: {roles.count('training')} training, {roles.count('selection')} selection, "
      f"{roles.count('report')} report (order: {''.join(r[0] for r in roles)})\n")
print("| rows | base | extended | noise floor |\n|---|---|---|---|")
s = d["selection_relative_error_pct"]
print(f"| selection (decides) | {s['base']:.2f} % | {s['extended']:.2f} % | "
      f"{d['selection_noise_floor_relative_error_pct']:.2f} % |")
h = d["heldout_relative_error_pct"]
print(f"| report (held out, only reports) | {h['base']:.2f} % | {h['extended']:.2f} % | "
      f"{d['noise_floor_relative_error_pct']:.2f} % |\n")
print(f"verdict **{d['verdict']}**, cause `{d['cause']}`\n")
print("| cause, in the order found | selection gain | report gain ± se | lower bound (95 %) | confirmed |")
print("|---|---|---|---|---|")
for c in d["causes"]:
    print(f"| `{c['effect']}` | {c['selection_gain_pct']:.1f} % | {c['heldout_gain_pct']:.1f} ± "
          f"{c['heldout_gain_se_pct']:.1f} % | {c['heldout_gain_lower_pct']:.1f} % | "
          f"{'yes' if c['confirmed'] else 'no'} |")
print("\n| candidate on the base model | ΔBIC (training) | selection gain | earns | report gain |")
print("|---|---|---|---|---|")
for r in d["ranking"]:
    print(f"| `{r['effect']}` | {r['delta_bic']:.1f} | {r['selection_gain_pct']:.1f} % | "
          f"{'yes' if r['earns'] else 'no'} | {r['heldout_gain_pct']:.1f} % |")
print()
for c in d["closed_loop"]:
    if c["available"]:
        b, e = c["base"], c["extended"]
        print(f"closed loop over {c['recording']}, compared on the report samples: base position "
              f"{b['position_pct']:.4f} %, velocity {b['velocity_pct']:.3f} %, effort {b['effort_pct']:.2f} %; "
              f"extended {e['position_pct']:.4f} %, {e['velocity_pct']:.3f} %, {e['effort_pct']:.2f} %")
PY
