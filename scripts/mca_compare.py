#!/usr/bin/env python3
"""Table of the MCA comparison (scripts/mca-compare.sh): reads OUT/<scene>/<mode>/summary.json and
the OMCT results OUT/omct/<platform>/<mode>/omct.csv."""
import csv
import json
import sys
from pathlib import Path

SCENES = ["speed_cushion", "car_launch", "car_lane_change"]
MODES = [("washout", "washout"), ("mpc", "MPC, no preview"), ("mpc-preview", "MPC, preview"),
         ("offline", "offline optimum")]
AXES = [("otolith", "x", "f_x", "m/s²"), ("otolith", "y", "f_y", "m/s²"), ("otolith", "z", "f_z", "m/s²"),
        ("canals", "x", "ω_x", "deg/s"), ("canals", "y", "ω_y", "deg/s"), ("canals", "z", "ω_z", "deg/s")]


def main(out: Path) -> None:
    for scene in SCENES:
        summaries = {m: json.load(open(out / scene / m / "summary.json"))["mca"] for m, _ in MODES}
        first = summaries["washout"]["consistency"]
        axes = []
        for group, axis, label, unit in AXES:
            key = "peak_true_" + ("mps2" if group == "otolith" else "radps")
            if first[group][axis][key] > 0.05 * (1.0 if group == "otolith" else 0.0174533):
                axes.append((group, axis, label, unit))
        print(f"\n**{scene}** (platform {summaries['washout']['platform']['name']})\n")
        head = ["algorithm"] + [f"RMS {l} [{u}]" for _, _, l, u in axes] + \
               ["wrong-sign cues (count, s)", "tilt rate > threshold [s]", "stroke used (max of actuators)",
                "within limits", "fallbacks"]
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
        for mode, name in MODES:
            s = summaries[mode]
            c = s["consistency"]
            cells = [name]
            for group, axis, _, _ in axes:
                v = c[group][axis]["rms_error_" + ("mps2" if group == "otolith" else "radps")]
                cells.append(f"{v:.3f}" if group == "otolith" else f"{v * 57.29578:.2f}")
            fc = s["false_cues"]
            cells.append(f"{fc['wrong_sign_count']}, {fc['wrong_sign_duration_s']:.2f}")
            cells.append(f"{fc['tilt_rate_duration_s']:.2f}" if "tilt_rate_duration_s" in fc else "–")
            worst = max(s["actuators"], key=lambda u: u["stroke_use"])
            cells.append(f"{100 * worst['stroke_use']:.0f} % ({worst['name']})")
            cells.append("yes" if s["limits"]["within_limits"] else "NO")
            cells.append(str(s["algorithm"].get("fallbacks_to_washout", "–")))
            print("| " + " | ".join(cells) + " |")

    omct(out)


OMCT_PLATFORMS = ["pw4dof", "car2dof"]
OMCT_MODES = [("washout", "washout"), ("mpc", "MPC, no preview")]
OMCT_FREQUENCIES = [0.251, 1.0, 3.98]  # rad/s, OMCT frequencies 10^(k/5), k = -3, 0, 3


def omct(out: Path) -> None:
    """Gain and phase per OMCT test (per axis) at a low, a mid and a high frequency."""
    for platform in OMCT_PLATFORMS:
        rows = {}
        for mode, _ in OMCT_MODES:
            with open(out / "omct" / platform / mode / "omct.csv") as f:
                for r in csv.DictReader(f):
                    rows[(mode, r["test"], round(float(r["frequency"]), 2))] = (float(r["gain"]), float(r["phase"]))
        tests = sorted({t for (_, t, _) in rows}, key=lambda t: TEST_ORDER.index(t))
        print(f"\n**OMCT, platform {platform}** (gain [-], phase [deg]; rotations in rad/s, forces in m/s²)\n")
        head = ["test", "algorithm"] + [f"{w:g} rad/s" for w in OMCT_FREQUENCIES]
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
        for test in tests:
            for mode, name in OMCT_MODES:
                cells = [test.replace("_to_", " → "), name]
                for w in OMCT_FREQUENCIES:
                    gain, phase = rows[(mode, test, round(w, 2))]
                    cells.append(f"{gain:.3g}, {phase:+.0f}°")
                print("| " + " | ".join(cells) + " |")


TEST_ORDER = ["p_to_p", "q_to_q", "r_to_r", "fx_to_fx", "fy_to_fy", "fz_to_fz", "fx_to_q", "fy_to_p", "q_to_fx",
              "p_to_fy"]


if __name__ == "__main__":
    main(Path(sys.argv[1]))
