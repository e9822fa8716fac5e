#!/usr/bin/env bash
# Regenerates the platform figures of docs/platform.md (and the proposed README section):
# the EMPS identification beside the published values (real data), the EMPS diagnosis, the
# hidden-effect matrix (independent truth), the frequency response of platform-sim's chirp
# (same-model generated), and the identification speed against scipy (real data).
# usage: scripts/platform-figures.sh [BUILD_DIR] [SEEDS]   (needs the EMPS data, see below)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
seeds=${2:-5}
source "$root/scripts/emps-dir.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
pwsim="$build/pwsim"
mat="$emps/DATA_EMPS.mat"
"$pwsim" platform identify "$mat" --out "$work/id" > /dev/null
"$pwsim" platform identify "$mat" --model axis-asymmetric --out "$work/asym" > /dev/null
"$pwsim" platform-sim --chirp "$work/chirp/rail.yaml" > /dev/null
"$pwsim" platform frequency-response "$work/chirp/rail.yaml" --sweeps 3 --out "$work/fr" > /dev/null
/usr/bin/python3 - "$work" <<'PY'
import json, sys
w = sys.argv[1]
fit = json.load(open(f"{w}/id/platform-fit.json"))
asym = json.load(open(f"{w}/asym/platform-fit.json"))
p = fit["joints"][0]["parameters"]
pub = {"inertia": (95.1089, 0.1085), "viscous": (203.5034, 1.1460), "coulomb": (20.3935, 0.1012),
       "offset": (-3.1648, 0.0444)}
print("### EMPS (real data, DATA_EMPS.mat): IDIM-LS, pwsim beside the published values\n")
print("| parameter | pwsim | σ pwsim | published | σ published |\n|---|---|---|---|---|")
for k, (v, s) in pub.items():
    print(f"| {k} [{p[k]['unit']}] | {p[k]['value']:.4f} | {p[k]['sigma']:.4f} | {v:.4f} | {s:.4f} |")
print(f"| relative error | {fit['relative_error_pct']:.4f} % | | 4.0834 % | |")
print(f"| condition number | {fit['condition_number']:.4f} | | 25.9883 | |")
print(f"| rows | {fit['rows']} | | 2480 | |\n")
a = asym["joints"][0]["parameters"]
apub = {"inertia": 95.1540, "viscous_pos": 166.7061, "coulomb_pos": 20.1440, "viscous_neg": 240.4236,
        "coulomb_neg": 20.6277}
print("Direction-dependent friction (axis-asymmetric):\n")
print("| parameter | pwsim | published |\n|---|---|---|")
for k, v in apub.items():
    print(f"| {k} | {a[k]['value']:.4f} | {v:.4f} |")
print(f"| relative error | {asym['relative_error_pct']:.4f} % | 3.1117 % |\n")
fr = json.load(open(f"{w}/fr/frequency-response.json"))
for j in fr["joints"]:
    print(f"### platform-sim chirp, joint {j['joint']} (same-model generated)\n")
    print(f"bandwidth {j['bandwidth_rad_s']:.2f} rad/s (fit), {j['bandwidth_nonparametric_rad_s']:.2f} rad/s (H1); fits: "
          + ", ".join(f"order {f['order']} {f['fit_pct']:.2f} %" for f in j["fits"]) + "\n")
PY
PWSIM_EMPS_DIR="$emps" PWSIM_DIAGNOSE_OUT="$work/dg" "$root/scripts/platform-diagnose-emps.sh" "$build"
echo
mkdir -p "$root/docs/images"
cp "$work/id/identify-effort.png" "$root/docs/images/platform-emps-identify.png"
cp "$work/dg/diagnosis-velocity.png" "$root/docs/images/platform-emps-diagnosis-velocity.png"
cp "$work/fr/bode.png" "$root/docs/images/platform-chirp-bode.png"
echo "### Hidden-effect matrix"
echo
"$build/bench/platform_diagnose_matrix" "$seeds"
echo
echo "### Speed"
echo
"$root/scripts/bench-platform.sh" "$build"
