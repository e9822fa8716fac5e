#!/usr/bin/env python3
"""Time `pwsim diagnose` on 30-trial sets of the independent truth: the distribution over sets.

Issue 41's goal is <= 10 s for ANY 30-trial set through the CLI on the 2-core machine, so this
benchmark takes one evaluation set of every row of the law space (scripts/evaluate-diagnosis.py
ROWS: no effect, each catalogue effect, one outside the catalogue, four pairs), each drawn with
30 trials (10 speeds x 3 loads) by `independent_truth_set --draw`, and runs the real CLI on it,
on 2 threads and then on 1 (the one-thread ratio says how much of the work runs in parallel).
Each set's timing is kept in WORK/results/NAME.json, so an interrupted run resumes. Per set it records the wall time, the CPU time of the process and the load average before it;
it prints the median, 90th percentile and maximum, and writes the per-set table.

  scripts/time-diagnose-sets.py [--build build] [--work out/diagnose-timing] [--rows a,b,...]
      [--seed-base 1000] [--one-thread] [--md FILE] [--csv FILE]

Seeds: 1000 + row index (the first evaluation set of each row; evaluation seeds are never tuned
on). A figure is for a quiet machine only where the load average before its run was low: the
table says what it was.
"""
import argparse
import csv
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import time

ROWS = ["none", "wheel_radius", "tyre_compliance", "cushion_compliance", "heave_pitch_coupling",
        "nonlinear_stiffness", "suspension_friction", "inertial_pitch", "marker_offset",
        "occupant_seat", "inertial_pitch+marker_offset", "cushion_compliance+suspension_friction",
        "tyre_compliance+inertial_pitch", "heave_pitch_coupling+nonlinear_stiffness"]
SPEEDS = "0.5,0.7,0.9,1.1,1.3,1.5,1.7,1.9,2.1,2.3"  # 10 speeds x 3 loads = 30 trials
LOADS = "0,50,100"


def load_average():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def percentile(values, q):
    """Linear interpolation between closest ranks (R's type 7, numpy's default)."""
    s = sorted(values)
    if not s:
        return float("nan")
    pos = (len(s) - 1) * q
    lo = int(pos)
    hi = min(lo + 1, len(s) - 1)
    return s[lo] + (s[hi] - s[lo]) * (pos - lo)


def diagnose(pwsim, trials, out, threads):
    """Wall and CPU seconds of one `pwsim diagnose` run, and its first stdout line."""
    shutil.rmtree(out, ignore_errors=True)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    load = load_average()
    start = time.monotonic()
    proc = subprocess.run([pwsim, "diagnose"] + trials + ["--out", out, "--threads", str(threads), "--quiet"],
                          capture_output=True, text=True)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if proc.returncode != 0:
        sys.exit(f"pwsim diagnose failed on {out} (exit {proc.returncode}):\n{proc.stderr}")
    return wall, cpu, load, (proc.stdout.splitlines() or [""])[0]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default="build")
    p.add_argument("--work", default="out/diagnose-timing")
    p.add_argument("--rows", default="")
    p.add_argument("--seed-base", type=int, default=1000)
    p.add_argument("--one-thread", action="store_true", help="also run each set on 1 thread (the ratio)")
    p.add_argument("--md", default="")
    p.add_argument("--csv", default="")
    args = p.parse_args()
    rows = args.rows.split(",") if args.rows else ROWS
    for row in rows:
        if row not in ROWS:
            sys.exit(f"--rows: unknown row '{row}' (one of {', '.join(ROWS)})")
    pwsim = os.path.join(args.build, "pwsim")
    draw = os.path.join(args.build, "tests/truth/independent_truth_set")
    for tool in (pwsim, draw):
        if not os.access(tool, os.X_OK):
            sys.exit(f"{tool}: not built (cmake --build {args.build} --target pwsim independent_truth_set)")
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    os.makedirs(args.work, exist_ok=True)
    results = []
    for n, row in enumerate(rows, 1):
        seed = args.seed_base + ROWS.index(row)
        name = f"{seed:05d}_{row.replace('+', '_')}"
        set_dir = os.path.join(args.work, "sets", name)
        if not os.path.isdir(set_dir):
            tmp = set_dir + ".partial"
            shutil.rmtree(tmp, ignore_errors=True)
            os.makedirs(os.path.dirname(tmp), exist_ok=True)
            subprocess.run([draw, "--draw", "--seed", str(seed), "--effects", row.replace("+", ","),
                            "--out", tmp, "--speeds", SPEEDS, "--loads", LOADS], check=True,
                           stdout=subprocess.DEVNULL)
            os.replace(tmp, set_dir)
        trials = sorted(os.path.join(set_dir, d, "") for d in os.listdir(set_dir)
                        if os.path.isdir(os.path.join(set_dir, d)))
        done = os.path.join(args.work, "results", name + ".json")
        if os.path.exists(done):  # timed already: an interrupted run resumes
            results.append(json.load(open(done)))
            print(f"[{n}/{len(rows)}] {name}: timed before, {results[-1]['wall_2_threads_s']:.1f} s", flush=True)
            continue
        wall2, cpu2, load2, line = diagnose(pwsim, trials, os.path.join(args.work, "dx", name), 2)
        r = {"set": name, "seed": seed, "row": row, "trials": len(trials), "commit": commit,
             "wall_2_threads_s": round(wall2, 2),
             "cpu_s": round(cpu2, 2), "load_before": load2, "result": line}
        if args.one_thread:
            wall1, _, load1, _ = diagnose(pwsim, trials, os.path.join(args.work, "dx1", name), 1)
            r.update({"wall_1_thread_s": round(wall1, 2), "one_thread_ratio": round(wall1 / wall2, 2),
                      "load_before_1_thread": load1})
        results.append(r)
        os.makedirs(os.path.dirname(done), exist_ok=True)
        with open(done + ".tmp", "w") as f:
            json.dump(r, f)
        os.replace(done + ".tmp", done)
        print(f"[{n}/{len(rows)}] {name}: {len(trials)} trials, {wall2:.1f} s on 2 threads "
              f"(CPU {cpu2:.1f} s, load before {load2:.1f})"
              + (f", {r['wall_1_thread_s']:.1f} s on 1 (ratio {r['one_thread_ratio']:.2f})" if args.one_thread else ""),
              flush=True)
    walls = [r["wall_2_threads_s"] for r in results]
    cpus = [r["cpu_s"] for r in results]
    commits = sorted({r.get("commit", "?") for r in results})
    summary = (f"{len(results)} sets of 30 trials (pwsim at {', '.join(commits)}): wall on 2 threads median {statistics.median(walls):.1f} s, "
               f"90th percentile {percentile(walls, 0.9):.1f} s, maximum {max(walls):.1f} s; CPU median "
               f"{statistics.median(cpus):.1f} s, 90th percentile {percentile(cpus, 0.9):.1f} s, maximum {max(cpus):.1f} s")
    if args.one_thread:
        ratios = [r["one_thread_ratio"] for r in results]
        summary += f"; one-thread ratio median {statistics.median(ratios):.2f}"
    print(summary)
    if args.csv:
        with open(args.csv + ".tmp", "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(results[0].keys()))
            w.writeheader()
            w.writerows(results)
        os.replace(args.csv + ".tmp", args.csv)
    if args.md:
        lines = ["# Time to diagnose a 30-trial set", "",
                 f"Written by `scripts/time-diagnose-sets.py` at commit `{commit}` from the timings in its work folder (each with the commit of the pwsim it timed); do not edit. One evaluation "
                 "set of each row of the independent truth's law space (seed 1000 + row), drawn with 30 trials "
                 f"(speeds {SPEEDS} m/s x loads {LOADS} kg), diagnosed by `pwsim diagnose SET/*/ --threads 2`. "
                 "Wall time depends on the machine's load: the load average before each run is in the table.", "",
                 summary + ".", "",
                 "| set | wall, 2 threads [s] | CPU [s] | load before | " + ("wall, 1 thread [s] | ratio | " if args.one_thread else "") + "result |",
                 "|---|---|---|---|" + ("---|---|" if args.one_thread else "") + "---|"]
        for r in results:
            lines.append(f"| {r['set']} | {r['wall_2_threads_s']:.1f} | {r['cpu_s']:.1f} | {r['load_before']:.1f} | "
                         + (f"{r['wall_1_thread_s']:.1f} | {r['one_thread_ratio']:.2f} | " if args.one_thread else "")
                         + r["result"].replace("|", "/") + " |")
        with open(args.md + ".tmp", "w") as f:
            f.write("\n".join(lines) + "\n")
        os.replace(args.md + ".tmp", args.md)


if __name__ == "__main__":
    main()
