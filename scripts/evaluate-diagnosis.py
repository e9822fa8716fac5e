#!/usr/bin/env python3
"""The diagnosis' evaluation on the independent truth's law space, as a new user runs it.

Each set is drawn by seed from the law space of tests/truth/law_space.h (the effect's law,
parameters and strength, and the measurement noise: white, low-pass filtered, drifting,
outlying or mixed), written by `independent_truth_set --draw --seed N --effects ROW`, and
diagnosed by the real CLI: `pwsim diagnose SET/*/ --out ...`. Nothing here or in the truth is
tuned on the evaluation seeds.

Splits (seed = base + 100 j + row index, j = 0, 1, ... the set's number in its row):
  development   base 1     (seeds 1-999; tests and tuning may use them; at most 9 sets a row)
  evaluation    base 1000  (seeds >= 1000; never tuned on)
  calibration   no-effect seeds 900 + j     (development; noise kinds in turn: white, lowpass,
                drift, outliers, mix), for calibrating the verdict
  false alarm   no-effect seeds 90000 + j   (evaluation; kinds in turn as above)
  unseen noise  no-effect seeds 960 + j     (development; noise kinds the law space never draws,
                forced in turn: pink, sine, step, burst, quantised; law_space.h ExtraNoiseKinds)

Sets run in parallel with a bounded number of jobs, each under `nice`; a set already diagnosed
(WORK/results/NAME.json) is skipped, so an interrupted run resumes. Every file is written to a
temporary name and renamed. The table (Markdown) and one CSV line per set are written at the
end, with the commit they were measured at.

  scripts/evaluate-diagnosis.py [--build build] [--work out/diagnosis-eval]
      [--dev-sets N] [--eval-sets N] [--calibration N] [--false-alarm N] [--rows a,b+c,...]
      [--jobs 2] [--nice 15] [--speeds 0.5,0.9,1.3,1.7] [--loads 0,50,100]
      [--diagnose-arg=--threads=1 ...] [--md FILE] [--csv FILE] [--report-only]
"""
import argparse
import concurrent.futures as futures
import csv
import glob
import io
import json
import math
import os
import shutil
import subprocess
import sys
import time

ROWS = ["none", "wheel_radius", "tyre_compliance", "cushion_compliance", "heave_pitch_coupling",
        "nonlinear_stiffness", "suspension_friction", "inertial_pitch", "marker_offset",
        "occupant_seat", "inertial_pitch+marker_offset", "cushion_compliance+suspension_friction",
        "tyre_compliance+inertial_pitch", "heave_pitch_coupling+nonlinear_stiffness"]
OUTSIDE = {"occupant_seat"}
NOISE_KINDS = ["white", "lowpass", "drift", "outliers", "mix"]
UNSEEN_KINDS = ["pink", "sine", "step", "burst", "quantised"]
VERDICTS = ["adequate", "explained", "partly_explained", "unexplained", "failed"]
CATALOGUE = ["wheel_radius", "tyre_compliance", "cushion_compliance", "heave_pitch_coupling",
             "nonlinear_stiffness", "suspension_friction", "inertial_pitch", "marker_offset"]


def write_atomic(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def plan(args):
    """(split, name, seed, row, forced noise kind) for every set asked for."""
    rows = args.rows.split(",") if args.rows else ROWS
    for row in rows:
        if row not in ROWS:
            sys.exit(f"--rows: unknown row '{row}' (one of {', '.join(ROWS)})")
    if args.dev_sets > 9:
        sys.exit("--dev-sets: at most 9 (development seeds stay below 1000)")
    tasks = []
    for split, base, count in (("evaluation", 1000, args.eval_sets), ("development", 1, args.dev_sets)):
        for j in range(count):
            for row in rows:
                seed = base + 100 * j + ROWS.index(row)
                tasks.append((split, f"{seed:05d}_{row.replace('+', '_')}", seed, row, ""))
    for split, base, count in (("calibration", 900, args.calibration), ("false_alarm", 90000, args.false_alarm)):
        for j in range(count):
            kind = NOISE_KINDS[j % len(NOISE_KINDS)]
            tasks.append((split, f"{base + j:05d}_none_{kind}", base + j, "none", kind))
    if args.unseen_noise and args.calibration > 60:
        sys.exit("--unseen-noise: seeds 960+ would meet calibration seeds beyond 60 sets")
    for j in range(args.unseen_noise):
        kind = UNSEEN_KINDS[j % len(UNSEEN_KINDS)]
        tasks.append(("unseen_noise", f"{960 + j:05d}_none_{kind}", 960 + j, "none", kind))
    return tasks


def run_set(args, task, commit):
    split, name, seed, row, kind = task
    result_path = os.path.join(args.work, "results", name + ".json")
    if os.path.exists(result_path):
        return json.load(open(result_path)), True
    sets = os.path.join(args.work, "sets")
    set_dir = os.path.join(sets, name)
    nice = ["nice", "-n", str(args.nice)]
    if not os.path.isdir(set_dir):  # generate in a scratch folder, then rename (set and truth)
        tmp = os.path.join(sets, ".partial", name)
        shutil.rmtree(tmp, ignore_errors=True)
        os.makedirs(os.path.dirname(tmp), exist_ok=True)
        cmd = nice + [os.path.join(args.build, "tests/truth/independent_truth_set"), "--draw",
                      "--seed", str(seed), "--effects", row.replace("+", ","), "--out", tmp,
                      "--speeds", args.speeds, "--loads", args.loads]
        if kind:
            cmd += ["--noise", kind]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        os.replace(tmp + ".truth.yaml", set_dir + ".truth.yaml")
        os.replace(tmp, set_dir)
    trials = sorted(glob.glob(os.path.join(set_dir, "*", "")))
    dx_dir = os.path.join(args.work, "dx", name)
    tmp = dx_dir + ".tmp"
    shutil.rmtree(tmp, ignore_errors=True)
    shutil.rmtree(dx_dir, ignore_errors=True)
    start = time.monotonic()
    proc = subprocess.run(nice + [os.path.join(args.build, "pwsim"), "diagnose"] + trials +
                          ["--out", tmp] + args.diagnose_arg, capture_output=True, text=True)
    seconds = time.monotonic() - start
    laws = [line.strip()[3:-1] for line in open(set_dir + ".truth.yaml") if line.startswith("  - \"")]
    result = {"split": split, "name": name, "seed": seed, "row": row, "trials": len(trials), "commit": commit,
              "laws": laws, "seconds": round(seconds, 1), "rc": proc.returncode}
    dx_json = os.path.join(tmp, "diagnosis.json")
    if proc.returncode == 0 and os.path.exists(dx_json):
        d = json.load(open(dx_json))
        os.replace(tmp, dx_dir)
        # Every cause forward selection added, confirmed or not (`selected_causes`; before issue 41
        # `causes` held them all), so that "found" below keeps its meaning.
        selected = d.get("selected_causes", d.get("causes", []))
        result.update({"verdict": d["verdict"], "cause": d.get("cause", "none"),
                       "causes": [{"effect": c["effect"], "gain_pct": c.get("heldout_gain_pct"),
                                   "confirmed": c.get("confirmed")} for c in selected],
                       "heldout_fit_pct": d.get("heldout_fit_pct"),
                       "probability": d.get("effect_probability"),
                       "probability_inputs": d.get("effect_probability_inputs")})
    else:
        result.update({"verdict": "failed", "cause": "none", "causes": [],
                       "error": (proc.stderr or proc.stdout)[-400:]})
    write_atomic(result_path, json.dumps(result, indent=1) + "\n")
    return result, False


def effects_of(row):
    return [] if row == "none" else row.split("+")


def named_first_with_gain(r):
    c = r["causes"]
    return bool(c) and c[0]["effect"] == r["row"] and (c[0]["gain_pct"] or 0) > 0


def both_found(r):
    """Both effects among the causes named, confirmed by the report trials or not."""
    found = {c["effect"] for c in r["causes"]}
    return all(e in found for e in effects_of(r["row"]))


def both_confirmed(r):
    """Both effects among the causes the report trials confirmed."""
    found = {c["effect"] for c in r["causes"] if c.get("confirmed")}
    return all(e in found for e in effects_of(r["row"]))


def rate(hits, n):
    return f"{hits}/{n} ({100.0 * hits / n:.0f} %)" if n else "–"


def short_law(line):
    """'effect: law, parameters' -> 'law' (noise: its kind)."""
    if line.startswith("noise "):
        return line[6:].split(":")[0]
    return line.split(": ", 1)[1].split(",")[0].split(":")[0]


def row_cell(results):
    """Verdict counts, then per set: seed, law(s) / noise, verdict, causes with held-out gains."""
    if not results:
        return "–"
    counts = {v: sum(r["verdict"] == v for r in results) for v in VERDICTS}
    cells = [", ".join(f"{v} ×{n}" for v, n in counts.items() if n)]
    for r in results:
        laws = "; ".join(short_law(line) for line in r["laws"][:-1])
        causes = " + ".join(f"{c['effect']} {c['gain_pct']:.0f} %" if c["gain_pct"] is not None else c["effect"]
                            for c in r["causes"]) or "no cause"
        cells.append(f"{r['seed']} ({laws + ' / ' if laws else ''}{short_law(r['laws'][-1])}): "
                     f"{r['verdict']}, {causes}")
    return "<br>".join(cells)


def goals(results):
    """(goal, target, figure) for one split's results."""
    singles = [r for r in results if len(effects_of(r["row"])) == 1 and r["row"] not in OUTSIDE]
    pairs = [r for r in results if len(effects_of(r["row"])) == 2]
    none = [r for r in results if r["row"] == "none"]
    outside = [r for r in results if r["row"] in OUTSIDE]
    return [("single effects named first with a positive held-out gain", "≥ 90 %",
             rate(sum(map(named_first_with_gain, singles)), len(singles))),
            ("both causes of a pair found", "≥ 80 %", rate(sum(map(both_found, pairs)), len(pairs))),
            ("both causes of a pair found and confirmed", "–", rate(sum(map(both_confirmed, pairs)), len(pairs))),
            ("no-effect sets `adequate`", "≥ 95 %", rate(sum(r["verdict"] == "adequate" for r in none), len(none))),
            ("outside the catalogue called `adequate`", "never",
             rate(sum(r["verdict"] == "adequate" for r in outside), len(outside)))]


def probabilities(inputs, prior, samples_per_unit):
    """sysid/diagnose/diagnose.cc EffectProbabilities from diagnosis.json's inputs, for other
    constants: every effect set weighs (π/(1−π))^|m| Π_u MS_u^(−ν/2) (its best fit when visited
    twice), normalised; P(e) = Σ of the weights of the sets holding e."""
    best = {}
    for m in inputs["models"]:
        ms = m["selection_ms"]
        if not ms or any(not (v > 0) or v != v or v == float("inf") for v in ms):
            continue
        lw = len(m["effects"]) * math.log(prior / (1 - prior)) - 0.5 * samples_per_unit * sum(map(math.log, ms))
        key = tuple(sorted(m["effects"]))
        best[key] = max(best.get(key, -math.inf), lw)
    if not best:
        return {}
    top = max(best.values())
    weights = {k: math.exp(v - top) for k, v in best.items()}
    total = sum(weights.values())
    effects = {e for k in weights for e in k} | set(CATALOGUE)
    return {e: sum(w for k, w in weights.items() if e in k) / total for e in effects}


def probability_pairs(results, constants=None):
    """(predicted probability, present 0/1) for every catalogue effect of every set with
    probabilities; `constants` (prior, ν) recomputes them from the stored inputs."""
    pairs = []
    for r in results:
        p = r.get("probability")
        if constants and r.get("probability_inputs"):
            p = probabilities(r["probability_inputs"], *constants)
        if not p:
            continue
        present = set(effects_of(r["row"]))
        for e in CATALOGUE:
            if e in p:
                pairs.append((p[e], int(e in present)))
    return pairs


def brier(pairs):
    return sum((p - y) ** 2 for p, y in pairs) / len(pairs) if pairs else float("nan")


def reliability(pairs, bins=10):
    """Per bin of predicted probability [k/bins, (k+1)/bins): (k, count, mean predicted, observed
    frequency, Wilson 90 % interval of the frequency)."""
    out = []
    z = 1.6448536269514722
    for k in range(bins):
        inside = [(p, y) for p, y in pairs if min(int(p * bins), bins - 1) == k]
        if not inside:
            continue
        n = len(inside)
        f = sum(y for _, y in inside) / n
        centre = (f + z * z / (2 * n)) / (1 + z * z / n)
        half = z * math.sqrt(f * (1 - f) / n + z * z / (4 * n * n)) / (1 + z * z / n)
        out.append((k, n, sum(p for p, _ in inside) / n, f, max(0.0, centre - half), min(1.0, centre + half)))
    return out


def reliability_figure(sets, png):
    """The reliability figure (gnuplot): observed frequency against predicted probability per
    bin, with its Wilson 90 % interval, one series per (title, pairs) of `sets`."""
    if not png or not shutil.which("gnuplot"):
        return False
    os.makedirs(os.path.dirname(os.path.abspath(png)), exist_ok=True)
    tmp = png + ".tmp"
    data = png + ".dat"
    with open(data, "w") as f:
        for title, pairs in sets:
            f.write(f"# {title}\n")
            for k, n, mean_p, freq, lo, hi in reliability(pairs):
                f.write(f"{mean_p:.6f} {freq:.6f} {lo:.6f} {hi:.6f} {n}\n")
            f.write("\n\n")
    plots = ["x lw 1 dt 2 lc rgb '#777777' title 'perfectly calibrated'"]
    colours = ["#D55E00", "#0072B2", "#009E73"]
    for i, (title, pairs) in enumerate(sets):
        plots.append(f"'{data}' index {i} using 1:2:3:4 with yerrorbars pt 7 ps 1.2 lc rgb '{colours[i % 3]}' "
                     f"title '{title} (Brier {brier(pairs):.3f}, {len(pairs)} effect-sets)'")
        plots.append(f"'{data}' index {i} using 1:2:5 with labels offset 1.6,0.6 font ',9' "
                     f"tc rgb '{colours[i % 3]}' notitle")
    script = ("set terminal pngcairo noenhanced size 760,640 font 'Sans,11'\n"
              f"set output '{tmp}'\nset xrange [0:1]\nset yrange [-0.02:1.02]\n"
              "set xlabel 'predicted probability that the effect is present (bin mean)'\n"
              "set ylabel 'observed frequency (90 % Wilson interval)'\n"
              "set key bottom right\nset grid\nset title 'pwsim diagnose: calibration of effect_probability'\n"
              "plot " + ", ".join(plots) + "\n")
    subprocess.run(["gnuplot"], input=script, text=True, check=True)
    os.replace(tmp, png)
    os.remove(data)
    return True


def calibration_section(args, results, md):
    """The calibration of the per-effect probabilities: reliability per bin and Brier score on
    each split that has them, with the figure."""
    splits = [("evaluation", ("evaluation",)), ("evaluation + false alarm", ("evaluation", "false_alarm")),
              ("development", ("development", "calibration"))]
    sets = [(name, probability_pairs([r for r in results if r["split"] in members])) for name, members in splits]
    sets = [(name, pairs) for name, pairs in sets if pairs]
    if not sets:
        return
    md.write("\n## Calibration of the probability per effect\n\n"
             "Each set's `effect_probability` (diagnosis.json) for every catalogue effect, against whether "
             "the set holds it (an effect outside the catalogue counts as none present). Per bin of predicted "
             "probability: the effect-sets in it, their mean prediction and the observed frequency (90 % "
             "Wilson interval). Brier score = mean (p − y)²; for reference, the Brier score of the constant "
             "base rate of that split and of the categorical answer (1 for a confirmed cause, else 0).\n\n")
    png = getattr(args, "reliability_png", "")
    # The figure shows the evaluation (the calibration measured) where there is one.
    shown = [(n, p) for n, p in sets if n == "evaluation"] or sets[:1]
    if png and reliability_figure(shown, png):
        md.write(f"![reliability](" + os.path.relpath(png, os.path.dirname(os.path.abspath(args.md))) + ")\n\n")
    for name, pairs in sets:
        members = dict(splits)[name]
        rs = [r for r in results if r["split"] in members and r.get("probability")]
        base = sum(y for _, y in pairs) / len(pairs)
        categorical = []
        for r in rs:
            found = {c["effect"] for c in r["causes"] if c.get("confirmed")}
            present = set(effects_of(r["row"]))
            categorical += [(float(e in found), int(e in present)) for e in CATALOGUE]
        stored = {}
        for r in rs:
            inputs = r.get("probability_inputs") or {}
            key = f"π {inputs.get('prior', '?'):.3g}, ν {inputs.get('samples_per_unit', '?'):.3g}" if inputs else "unknown"
            stored[key] = stored.get(key, 0) + 1
        constants = "; ".join(f"{k} in {n}" for k, n in stored.items())
        md.write(f"**{name}** ({len(rs)} sets, {len(pairs)} effect-sets, {sum(y for _, y in pairs)} present; "
                 f"probabilities as the diagnosis wrote them, constants {constants}): "
                 f"Brier **{brier(pairs):.4f}** (base rate {base:.3f}: {brier([(base, y) for _, y in pairs]):.4f}; "
                 f"categorical: {brier(categorical):.4f})\n\n")
        md.write("| predicted | effect-sets | mean predicted | observed | 90 % interval |\n|---|---|---|---|---|\n")
        for k, n, mean_p, freq, lo, hi in reliability(pairs):
            md.write(f"| {k / 10:.1f}-{(k + 1) / 10:.1f} | {n} | {mean_p:.3f} | {freq:.3f} | {lo:.2f}-{hi:.2f} |\n")
        md.write("\n")


def fit_probability(results):
    """The probability's constants (prior π, ν) that minimise the Brier score on the development
    and calibration sets only (never the evaluation seeds); prints the grid's best."""
    tuning = [r for r in results if r["split"] in ("development", "calibration")]
    best = None
    for prior in (0.002, 0.005, 0.01, 0.02, 0.03, 0.05, 0.07, 0.1, 0.111111, 0.15, 0.2, 0.3):
        for nu in (0.25, 0.5, 1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 64):
            score = brier(probability_pairs(tuning, (prior, nu)))
            if best is None or score < best[0]:
                best = (score, prior, nu)
    print(f"development: {len(tuning)} sets; Brier {best[0]:.4f} at prior {best[1]}, samples_per_unit {best[2]}")
    return best


def report(args, results):
    by = lambda split: [r for r in results if r["split"] == split]
    dev, ev, cal, fa = by("development"), by("evaluation"), by("calibration"), by("false_alarm")
    unseen = by("unseen_noise")
    rows = [row for row in ROWS if any(r["row"] == row for r in dev + ev)]
    md = io.StringIO()
    md.write("# The diagnosis on the independent truth's law space\n\n"
             "Written by `scripts/evaluate-diagnosis.py`; do not edit. Each set's effect law, parameters, "
             "strength and measurement noise are drawn by seed (`tests/truth/law_space.h`); a set is "
             "regenerated by `build/tests/truth/independent_truth_set --draw --seed SEED --effects ROW "
             "--out DIR` (rows `a+b`: `--effects a,b`; calibration and false-alarm sets add "
             "`--noise KIND`) and diagnosed by `build/pwsim diagnose DIR/*/ --out OUT`. Development "
             "seeds 1-999 may be tuned on; evaluation seeds >= 1000 are not. Per set (laws, noise, "
             "verdict, causes, gains, seconds): the CSV beside this file.\n\n")
    seconds = [r["seconds"] for r in results if r["verdict"] != "failed"]
    commits = ", ".join(f"`{c}`" for c in sorted({r.get("commit", "unknown") for r in results}))
    md.write(f"Measured at commit {commits} by `scripts/evaluate-diagnosis.py` "
             f"({len(dev)} development, {len(ev)} evaluation, {len(cal)} calibration, "
             f"{len(fa)} false-alarm sets; {results[0]['trials'] if results else 0} trials a set; "
             f"diagnosis {min(seconds, default=0):.0f}-{max(seconds, default=0):.0f} s a set under nice -n {args.nice}, "
             f"{args.jobs} at a time). The figures hold for the diagnosis at these commits only.\n\n")
    md.write("| goal | target | development (seeds 1-999) | evaluation (seeds ≥ 1000) |\n|---|---|---|---|\n")
    for (goal, target, d), (_, _, e) in zip(goals(dev), goals(ev)):
        md.write(f"| {goal} | {target} | {d} | {e} |\n")
    cal_ok = sum(r["verdict"] == "adequate" for r in cal)
    fa_bad = sum(r["verdict"] != "adequate" for r in fa)
    md.write(f"| calibration set (no effect, development seeds 900+): `adequate` | – | {rate(cal_ok, len(cal))} | |\n")
    md.write(f"| false-alarm set (no effect, evaluation seeds 90000+): not `adequate` | ≤ 5 % | | {rate(fa_bad, len(fa))} |\n")
    if unseen:
        md.write(f"| unseen noise kinds (no effect, development seeds 960+): `adequate` | – | "
                 f"{rate(sum(r['verdict'] == 'adequate' for r in unseen), len(unseen))} | |\n")
    md.write("\n")
    md.write("| hidden effect | development: seed (law / noise): verdict, causes with held-out gain "
             "| evaluation: the same |\n|---|---|---|\n")
    for row in rows:
        md.write(f"| {row} | {row_cell([r for r in dev if r['row'] == row])} | "
                 f"{row_cell([r for r in ev if r['row'] == row])} |\n")
    if cal or fa:
        md.write(f"| no effect, calibration (development) / false alarm (evaluation) | {row_cell(cal)} | "
                 f"{row_cell(fa)} |\n")
    if unseen:
        md.write(f"| no effect, unseen noise kinds (development) | {row_cell(unseen)} | – |\n")
    calibration_section(args, results, md)
    write_atomic(args.md, md.getvalue())
    out = io.StringIO()
    w = csv.writer(out)
    w.writerow(["split", "seed", "row", "trials", "verdict", "first_cause", "causes", "gains_pct", "confirmed",
                "named_first_with_gain", "seconds", "laws"])
    for r in sorted(results, key=lambda r: (r["split"], r["seed"])):
        w.writerow([r["split"], r["seed"], r["row"], r["trials"], r["verdict"],
                    r["causes"][0]["effect"] if r["causes"] else "none",
                    "+".join(c["effect"] for c in r["causes"]),
                    "+".join("" if c["gain_pct"] is None else f"{c['gain_pct']:.1f}" for c in r["causes"]),
                    "+".join(str(c["confirmed"]) for c in r["causes"]),
                    int(named_first_with_gain(r)), r["seconds"], " | ".join(r["laws"])])
    write_atomic(args.csv, out.getvalue())


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default="build")
    p.add_argument("--work", default="out/diagnosis-eval")
    p.add_argument("--dev-sets", type=int, default=1, help="sets per row on development seeds (<= 9)")
    p.add_argument("--eval-sets", type=int, default=1, help="sets per row on evaluation seeds")
    p.add_argument("--calibration", type=int, default=20, help="no-effect calibration sets")
    p.add_argument("--false-alarm", type=int, default=20, help="no-effect false-alarm sets")
    p.add_argument("--unseen-noise", type=int, default=0,
                   help="no-effect sets under noise kinds never drawn (seeds 960 + j, <= 39)")
    p.add_argument("--rows", default="", help="comma-separated rows (default: all)")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--nice", type=int, default=15)
    p.add_argument("--speeds", default="0.5,0.9,1.3,1.7")
    p.add_argument("--loads", default="0,50,100")
    p.add_argument("--diagnose-arg", action="append", default=[],
                   help="passed to pwsim diagnose, e.g. --diagnose-arg=--threads=1 (repeatable)")
    p.add_argument("--report-only", action="store_true",
                   help="no new runs: the table of every set in WORK/results")
    p.add_argument("--no-build", action="store_true",
                   help="use the build as it is (build it first, under the build lock if shared)")
    p.add_argument("--reliability-png", default="",
                   help="the reliability figure of the probabilities (default WORK/reliability.png)")
    p.add_argument("--fit-probability", action="store_true",
                   help="no new runs: the probability's constants that fit the development sets in WORK/results")
    p.add_argument("--md", default="", help="table (default WORK/evaluation.md)")
    p.add_argument("--csv", default="", help="one line per set (default WORK/evaluation.csv)")
    args = p.parse_args()
    if args.jobs < 1:
        sys.exit("--jobs: expected >= 1")
    if not 0 <= args.unseen_noise <= 39:
        sys.exit("--unseen-noise: 0-39 (development seeds 960-999)")
    args.diagnose_arg = [a for arg in args.diagnose_arg for a in arg.split("=", 1)]
    args.md = args.md or os.path.join(args.work, "evaluation.md")
    args.csv = args.csv or os.path.join(args.work, "evaluation.csv")
    args.reliability_png = args.reliability_png or os.path.join(args.work, "reliability.png")
    for sub in ("results", "sets", "dx"):
        os.makedirs(os.path.join(args.work, sub), exist_ok=True)
    if args.fit_probability:
        fit_probability([json.load(open(f)) for f in sorted(glob.glob(os.path.join(args.work, "results", "*.json")))])
        return
    if args.report_only:
        results = [json.load(open(f)) for f in sorted(glob.glob(os.path.join(args.work, "results", "*.json")))]
        report(args, results)
        print(f"table: {args.md}\nper set: {args.csv}")
        return
    if not args.no_build:
        subprocess.run(["cmake", "--build", args.build, "--target", "pwsim", "independent_truth_set", "-j1"],
                       check=True, stdout=subprocess.DEVNULL)
    tasks = plan(args)
    commit = subprocess.run(["git", "describe", "--always", "--dirty"], capture_output=True,
                            text=True).stdout.strip() or "unknown"
    results = []
    with futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        pending = {pool.submit(run_set, args, t, commit): t for t in tasks}
        for done, fut in enumerate(futures.as_completed(pending), 1):
            r, skipped = fut.result()
            results.append(r)
            causes = "+".join(c["effect"] for c in r["causes"]) or "no cause"
            when = " (already diagnosed)" if skipped else ", %s s" % r["seconds"]
            print(f"[{done}/{len(tasks)}] {r['name']}: {r['verdict']}, {causes}{when}", flush=True)
    report(args, results)
    print(f"table: {args.md}\nper set: {args.csv}")


if __name__ == "__main__":
    main()
