#!/usr/bin/env python3
"""Table of the MCA comparison (scripts/mca-compare.sh): reads OUT/<scene>/<mode>/summary.json."""
import json
import sys
from pathlib import Path

SCENES = ["speed_cushion", "car_launch", "car_lane_change"]
MODES = [("washout", "washout"), ("mpc", "MPC, held input"), ("mpc-preview", "MPC, preview"),
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
               ["wrong-sign cues (count, s)", "tilt rate > threshold [s]", "workspace used (max of axes)",
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
            usage = s["platform"]["usage"]
            worst = max(usage, key=lambda u: u["pose_fraction_of_limit"])
            cells.append(f"{100 * worst['pose_fraction_of_limit']:.0f} % ({worst['dof']})")
            within = all(u["pose_fraction_of_limit"] <= 1 + 1e-9 and u["rate_fraction_of_limit"] <= 1 + 1e-9
                         and u["accel_fraction_of_limit"] <= 1 + 1e-6 for u in usage)
            cells.append("yes" if within else "NO")
            cells.append(str(s["algorithm"].get("fallbacks_to_washout", "–")))
            print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
