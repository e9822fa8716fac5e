#!/usr/bin/env bash
# DEVELOPMENT matrix: the diagnosis on the independent truth's fixed development variants
# (seeds 101-103, variants 0-2), the sets the families and starts were changed against and that
# tests/sysid/diagnose/independent_truth_diagnose_test.cc pins. Not an evaluation: for that,
# scripts/evaluate-diagnosis.py draws each set's laws and noise from the law space by seed and
# reports development (seeds 1-999) and evaluation (seeds >= 1000) side by side.
# The diagnosis' confusion matrix on data pwsim did NOT write: trial sets simulated by the
# independent truth (tests/truth/independent_truth.h: rigid chassis on per-wheel suspensions,
# Dormand-Prince, each effect in a physical form of its own, one effect outside the catalogue),
# diagnosed by `pwsim diagnose` exactly as a lab would run it: GM identified from the trials
# (chair.yaml carries no gm/lm), K and C started from Table I (not the truth), no bounds on the
# truth, the effect never named. Prints Markdown: rows = hidden effect(s), columns = verdict and
# first named cause, with the held-out fitness and each cause's held-out gain.
#   scripts/confusion-matrix.sh [BUILD_DIR] [SEEDS] [JOBS]   (default: build, 3, 2: every variant)
# SEEDS seeds per effect; seed s uses physical variant ("form") s-1 of the effect and strength
# 0.7 (odd seeds) or 1.4 (even seeds). 12 trials per set (0.5/0.9/1.3/1.7 m/s × 0/50/100 kg).
# Same-model figures (pwsim's own generator): bench/diagnose_bench --matrix-only.
set -euo pipefail
build=${1:-build}
seeds=${2:-3}
jobs=${3:-2}
cmake --build "$build" --target pwsim independent_truth_set -j2 > /dev/null
work=$(mktemp -d /tmp/pwsim-confusion.XXXXXX)
trap 'rm -rf "$work"' EXIT
rows=(none wheel_radius tyre_compliance cushion_compliance heave_pitch_coupling
      nonlinear_stiffness suspension_friction inertial_pitch marker_offset occupant_seat
      inertial_pitch+marker_offset cushion_compliance+suspension_friction)
tasks=()
for row in "${rows[@]}"; do
  for ((s = 1; s <= seeds; ++s)); do tasks+=("$row:$s"); done
done
run_one() {
  local row=${1%%:*} seed=${1##*:}
  local strength=0.7 form=$((seed - 1)) name=${1//[:+]/_}
  ((seed % 2 == 0)) && strength=1.4
  local effects=${row//+/,}
  [ "$row" = none ] && effects=none
  "$build/tests/truth/independent_truth_set" --out "$work/$name" --effects "$effects" \
    --strength "$strength" --form "$form" --seed "$((100 + seed))" > /dev/null
  "$build/pwsim" diagnose "$work/$name"/*/ --out "$work/$name.dx" > "$work/$name.log" 2>&1 || true
  echo "$row $seed $strength $form" > "$work/$name.row"
}
export -f run_one
export build work
printf '%s\n' "${tasks[@]}" | xargs -P "$jobs" -I{} bash -c 'run_one "$@"' _ {}
python3 - "$work" "${rows[@]}" <<'EOF'
import json, os, sys, glob
work, rows = sys.argv[1], sys.argv[2:]
verdicts = ["adequate", "explained", "partly_explained", "unexplained", "failed"]
ids = ["none", "wheel_radius", "tyre_compliance", "cushion_compliance", "heave_pitch_coupling",
       "nonlinear_stiffness", "suspension_friction", "inertial_pitch", "marker_offset"]
res = {r: [] for r in rows}
for f in sorted(glob.glob(os.path.join(work, "*.row"))):
    row, seed, strength, form = open(f).read().split()
    path = f[:-4] + ".dx/diagnosis.json"
    d = json.load(open(path)) if os.path.exists(path) else None
    res[row].append((seed, strength, form, d))
print("| hidden (independent truth) | sets | " + " | ".join(verdicts) +
      " | first cause named | causes found | held-out fit base → extended, Z/pitch [%] | noise floor Z/pitch [%] | held-out gain per cause [%] |")
print("|" + "---|" * 12)
for row in rows:
    sets = res[row]
    count = {v: 0 for v in verdicts}
    first, found, fits, floors, gains = {}, [], [], [], []
    for seed, strength, form, d in sets:
        if d is None:
            count["failed"] += 1
            continue
        count[d["verdict"]] += 1
        first[d["cause"]] = first.get(d["cause"], 0) + 1
        found.append("+".join(c["effect"] for c in d["causes"]) or "-")
        h = d["heldout_fit_pct"]
        fits.append(f'{h["base"]["z"]:.1f}/{h["base"]["pitch"]:.1f} → {h["extended"]["z"]:.1f}/{h["extended"]["pitch"]:.1f}')
        n = d["noise_floor_fit_pct"]
        floors.append(f'{n["z"]:.1f}/{n["pitch"]:.1f}')
        gains.append(", ".join(f'{c["effect"]} {c["heldout_gain_pct"]:.0f}' for c in d["causes"]) or "-")
    cells = [str(count[v]) if count[v] else "" for v in verdicts]
    named = ", ".join(f"{k} ×{v}" for k, v in sorted(first.items()))
    print(f"| {row} | {len(sets)} | " + " | ".join(cells) + f" | {named} | {'; '.join(found)} | " +
          "; ".join(fits) + " | " + "; ".join(floors) + " | " + "; ".join(gains) + " |")
EOF
