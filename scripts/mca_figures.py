#!/usr/bin/env python3
"""Collects scripts/mca-figures.sh's runs: OUT/<scene>/<platform>/{mpc,washout}/summary.json.
Writes OUT/cueing.csv (one row per scene and platform), OUT/actuators.csv (one row per actuator),
the gnuplot data OUT/error.dat, OUT/xcorr.dat, OUT/stroke_<platform>.dat and the markdown table
OUT/table.md of docs/mca.md."""
import csv
import json
import sys
from pathlib import Path

ALGORITHMS = ["washout", "mpc", "offline"]
SHORT = {"speed_cushion": "cushion", "car_lane_change": "lane change", "car_launch": "launch",
         "car_recorded_drive": "car recorded", "car_seed_drive": "car seed", "circuit_course": "course",
         "circuit_recorded": "circuit recorded", "circuit_room": "room"}


def load(path: Path) -> dict:
    with open(path) as f:
        return json.load(f)["mca"]


def main(out: Path, commit: str) -> None:
    rows, actuators = [], []
    for scene_dir in sorted(p for p in out.iterdir() if p.is_dir()):
        for platform_dir in sorted(p for p in scene_dir.iterdir() if p.is_dir()):
            mpc = load(platform_dir / "mpc" / "summary.json")
            washout = load(platform_dir / "washout" / "summary.json")
            platform = mpc["platform"]["name"]
            if platform_dir.name != "own" and platform == load(scene_dir / "own" / "mpc" / "summary.json")["platform"]["name"]:
                continue  # the scene's own platform already
            c = mpc["comparison"]
            row = {"scene": scene_dir.name, "platform": platform}
            for a in ALGORITHMS:
                row[f"{a}_error"] = c[a]["rms_error"]
                row[f"{a}_xcorr"] = c[a]["xcorr_peak"]
                row[f"{a}_lag_ms"] = 1000.0 * c[a]["lag_s"]
            row["mpc_fallbacks"] = c["mpc"]["fallbacks_to_washout"]
            for who, s in (("washout", washout), ("mpc", mpc)):
                row[f"{who}_within_limits"] = s["limits"]["within_limits"]
                row[f"{who}_stroke_use"] = max(u["stroke_use"] for u in s["actuators"])
                row[f"{who}_tilt_rate_s"] = s["false_cues"].get("tilt_rate_duration_s", 0.0)
            row["box_stroke_use"] = max(u["box_stroke_use"] for u in mpc["actuators"])
            rows.append(row)
            for w, m in zip(washout["actuators"], mpc["actuators"]):
                actuators.append({"scene": scene_dir.name, "platform": platform, "actuator": m["name"],
                                  "washout_stroke_use": w["stroke_use"], "mpc_stroke_use": m["stroke_use"],
                                  "box_stroke_use": m["box_stroke_use"],
                                  "washout_speed_fraction": w["speed_fraction"], "mpc_speed_fraction": m["speed_fraction"],
                                  "washout_accel_fraction": w["accel_fraction"], "mpc_accel_fraction": m["accel_fraction"]})
    with open(out / "cueing.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    with open(out / "actuators.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(actuators[0].keys()))
        writer.writeheader()
        writer.writerows(actuators)

    def label(r):
        return f"\"{SHORT.get(r['scene'], r['scene'])} / {r['platform']}\""

    with open(out / "error.dat", "w") as f:
        f.write("label washout mpc offline\n")
        for r in rows:
            f.write(f"{label(r)} {r['washout_error']:.4f} {r['mpc_error']:.4f} {r['offline_error']:.4f}\n")
    with open(out / "xcorr.dat", "w") as f:
        f.write("label washout mpc offline washout_lag mpc_lag offline_lag\n")
        for r in rows:
            f.write(f"{label(r)} {r['washout_xcorr']:.4f} {r['mpc_xcorr']:.4f} {r['offline_xcorr']:.4f} "
                    f"{r['washout_lag_ms']:.0f} {r['mpc_lag_ms']:.0f} {r['offline_lag_ms']:.0f}\n")
    platforms = sorted({a["platform"] for a in actuators})
    for platform in platforms:
        names = [a["actuator"] for a in actuators if a["platform"] == platform]
        names = list(dict.fromkeys(names))
        with open(out / f"stroke_{platform}.dat", "w") as f:
            f.write("actuator washout mpc box\n")
            for n in names:
                these = [a for a in actuators if a["platform"] == platform and a["actuator"] == n]
                f.write(f"\"{n}\" {max(a['washout_stroke_use'] for a in these):.4f} "
                        f"{max(a['mpc_stroke_use'] for a in these):.4f} {these[0]['box_stroke_use']:.4f}\n")
    with open(out / "platforms.txt", "w") as f:
        f.write(" ".join(platforms) + "\n")

    lines = [f"Data: `scripts/mca-figures.sh` at pwsim {commit}, every shipped scene on its own platform and on "
             "stewart6dof; `pwsim run --no-video`, default weights, the MPC without preview.", "",
             "| scene | platform | perceived error washout / MPC / ceiling | xcorr peak washout / MPC / ceiling | "
             "lag [ms] washout / MPC / ceiling | stroke use washout / MPC (boxes ask) | within limits | "
             "tilt rate > threshold [s] | QP fallbacks |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        within = "yes" if r["washout_within_limits"] and r["mpc_within_limits"] else "NO"
        lines.append(
            f"| {r['scene']} | {r['platform']} | {r['washout_error']:.3f} / **{r['mpc_error']:.3f}** / {r['offline_error']:.3f} | "
            f"{r['washout_xcorr']:.2f} / {r['mpc_xcorr']:.2f} / {r['offline_xcorr']:.2f} | "
            f"{r['washout_lag_ms']:.0f} / {r['mpc_lag_ms']:.0f} / {r['offline_lag_ms']:.0f} | "
            f"{100 * r['washout_stroke_use']:.0f} % / {100 * r['mpc_stroke_use']:.0f} % ({100 * r['box_stroke_use']:.0f} %) | "
            f"{within} | {r['washout_tilt_rate_s']:.2f} / {r['mpc_tilt_rate_s']:.2f} | {r['mpc_fallbacks']} |")
    text = "\n".join(lines) + "\n"
    (out / "table.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main(Path(sys.argv[1]), sys.argv[2])
