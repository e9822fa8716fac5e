#!/usr/bin/env python3
"""Each residual test's statistic against its limit, per set, from a diagnosis evaluation.

Reads WORK/results/*.json and WORK/dx/NAME/diagnosis.json as scripts/evaluate-diagnosis.py
leaves them and writes one Markdown table: per set (split, seed, noise kind, verdict) and per
channel of the base model's check (verdict.h): (a) structured RMS ρ / rho_max, (b) worst
window ρ_w / rho_local, (c) the structure's power share (r̄ − r̄_n)/(1 − r̄_n) / its limit
ρ_max²/(1 + ρ_max²) (only where r̄ − r̄_n also exceeds its 99 % bound, else '–'), (d) input
|r| / input_r_max (where outside its bound), and the drift found (noise_model.h: the slow
part's scale s_d, or '–'). A ratio above 1 fails that test. The last row is each column's
largest ratio: the margin the limits leave on these sets.

  scripts/verdict-statistics.py WORK [--split calibration] [--md FILE]
"""
import argparse
import glob
import json
import os
import sys


def ratios(check, noise, limits):
    rmax = limits["rho_max"]
    share_limit = rmax * rmax / (1.0 + rmax * rmax)
    out = {"a": check["rho"] / rmax, "b": check["rho_local"] / limits["rho_local"]}
    excess = check["whiteness"] - check["whiteness_noise"]
    share = excess / (1.0 - check["whiteness_noise"]) if check["whiteness_noise"] < 1.0 else 0.0
    out["c"] = share / share_limit if excess > check["whiteness_bound"] else None
    out["d"] = check["input_r"] / limits["input_r_max"] if check["input_r"] > check["input_bound"] else None
    out["drift"] = noise.get("slow_scale_s", 0.0)
    return out


def cell(v):
    return "–" if v is None else f"{v:.2f}"


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("work")
    p.add_argument("--split", default="", help="only sets of this split (calibration, false_alarm, ...)")
    p.add_argument("--md", default="", help="write here (default: stdout)")
    args = p.parse_args()
    rows, worst, commits = [], {}, set()
    for path in sorted(glob.glob(os.path.join(args.work, "results", "*.json"))):
        r = json.load(open(path))
        if args.split and r["split"] != args.split:
            continue
        commits.add(r.get("commit", "unknown"))
        dx = os.path.join(args.work, "dx", r["name"], "diagnosis.json")
        if not os.path.exists(dx):
            rows.append(f"| {r['name']} | {r['verdict']} |" + " – |" * 10)
            continue
        vi = json.load(open(dx))["verdict_inputs"]
        kind = r["name"].split("_")[-1] if r["row"] == "none" else r["row"]
        cells = [r["name"], kind, r["verdict"]]
        for ch in ("z", "pitch"):
            q = ratios(vi["base"][ch], vi["noise"][ch], vi["limits"])
            for key in ("a", "b", "c", "d"):
                cells.append(cell(q[key]))
                if q[key] is not None:
                    worst[(ch, key)] = max(worst.get((ch, key), 0.0), q[key])
            cells.append(f"{q['drift']:.2f} s" if q["drift"] > 0 else "–")
        rows.append("| " + " | ".join(cells) + " |")
    head = ("| set | noise | verdict | Z (a) ρ | Z (b) window | Z (c) whiteness | Z (d) input | Z drift s_d "
            "| pitch (a) ρ | pitch (b) window | pitch (c) whiteness | pitch (d) input | pitch drift s_d |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
    last = ["**largest**", "", ""]
    for ch in ("z", "pitch"):
        last += [cell(worst.get((ch, k))) for k in ("a", "b", "c", "d")] + [""]
    intro = ("# Each residual test's statistic against its limit\n\n"
             "Written by `scripts/verdict-statistics.py` from a `scripts/evaluate-diagnosis.py` run "
             f"at commit {', '.join(f'`{c}`' for c in sorted(commits))}; do not edit. Base model's check "
             "(selection + report trials), ratio statistic / limit (above 1 fails): (a) structured RMS, "
             "(b) worst 0.5 s window, (c) the structure's share of the whiteness (– where within its "
             "99 % bound), (d) input correlation (– where within its bound); s_d the slow part removed "
             "for drift (– none).\n\n")
    text = intro + head + "\n".join(rows) + "\n| " + " | ".join(last) + " |\n"
    if args.md:
        tmp = args.md + ".tmp"
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, args.md)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
