#!/usr/bin/env python3
"""Seed 000, section V: which rating sets are consistent with everything the paper reports,
and which test gives its "matched-paired Wilcoxon test (p = 0.5045, W = 180)".

usage: scripts/study-paper-case.py [--pwsim build/pwsim] [--out out/study-paper-case]

What the paper reports (section V.D), used as constraints:
  18 participants, each rates T_m and T_r once on the 1-6 scale; no 6 was given and the largest
  rating is 3 ("max. value is 3"); mean 1.89 (T_m) and 1.78 (T_r) at two decimals; both
  medians 2; Shapiro-Wilk: not normal (p < 0.05 for both); and "95 % of the participants gave
  either 1 or 2 for each condition" (printed below, not used as a filter: no set fits it exactly).
Step 1 enumerates every pair of rating distributions (counts of 1, 2, 3 per condition) that
satisfy the constraints and runs `pwsim study` on each (with --reported test=paired,W=180,
p=0.5045), printing the statistics each test gives. Step 2 takes the distributions that match
and enumerates every way of pairing the two ratings of a participant (3x3 tables with those
margins), running the paired signed-rank test on each: its statistic is bounded by 171. When
Rscript is on PATH the matching case is checked with R's wilcox.test as well.
Only the standard library and the pwsim binary are needed.
"""
import argparse
import itertools
import json
import os
import shutil
import subprocess
import sys


def counts_for(total_sum, n=18):
    """(ones, twos, threes) with the given sum and median 2."""
    out = []
    for threes in range(n + 1):
        for twos in range(n + 1 - threes):
            ones = n - twos - threes
            if ones + 2 * twos + 3 * threes != total_sum:
                continue
            values = sorted([1] * ones + [2] * twos + [3] * threes)
            if (values[n // 2 - 1] + values[n // 2]) / 2 != 2:
                continue
            out.append((ones, twos, threes))
    return out


def expand(c):
    return [1] * c[0] + [2] * c[1] + [3] * c[2]


def write_ratings(path, tm, tr):
    with open(path, "w") as f:
        f.write("participant,condition,rating\n")
        for i, (a, b) in enumerate(zip(tm, tr)):
            f.write(f"P{i + 1:02d},T_m,{a}\nP{i + 1:02d},T_r,{b}\n")


def run_study(pwsim, ratings, out):
    subprocess.run([pwsim, "study", ratings, "--out", out, "--conditions", "T_m,T_r",
                    "--reported", "test=paired,W=180,p=0.5045"], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "study.json")) as f:
        return json.load(f)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pwsim", default="build/pwsim")
    ap.add_argument("--out", default="out/study-paper-case")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)

    # means at two decimals: 1.89 -> sum 34, 1.78 -> sum 32 (the only sums of 18 ratings that round so)
    sums_m = [s for s in range(18, 109) if round(s / 18, 2) == 1.89]
    sums_r = [s for s in range(18, 109) if round(s / 18, 2) == 1.78]
    cands_m = [c for s in sums_m for c in counts_for(s)]
    cands_r = [c for s in sums_r for c in counts_for(s)]
    print(f"T_m sum {sums_m}, T_r sum {sums_r}: {len(cands_m)} x {len(cands_r)} distributions with median 2")
    print("\nStep 1: every consistent pair of distributions (counts of ratings 1/2/3), the unpaired")
    print("rank-sum test of T_m vs T_r (R's wilcox.test(T_m, T_r): W, p with continuity correction,")
    print("p without it, exact conditional p), and Shapiro-Wilk p:")
    print(f"{'T_m':>10} {'T_r':>10} {'W':>6} {'p (R)':>8} {'p no cc':>8} {'p exact':>8} {'SW p T_m':>9} {'SW p T_r':>9}  1-or-2 share")
    matches = []
    work = os.path.join(args.out, "candidates")
    os.makedirs(work, exist_ok=True)
    for cm, cr in itertools.product(cands_m, cands_r):
        if max(cm[2], cr[2]) == 0:
            continue  # the largest rating must be 3
        tm, tr = expand(cm), expand(cr)
        ratings = os.path.join(work, "ratings.csv")
        write_ratings(ratings, tm, tr)
        j = run_study(args.pwsim, ratings, work)
        sw_m = j["conditions"]["T_m"]["shapiro_wilk"]["p"]
        sw_r = j["conditions"]["T_r"]["shapiro_wilk"]["p"]
        if not (sw_m < 0.05 and sw_r < 0.05):
            continue
        u = j["unpaired"]
        share = f"{(cm[0] + cm[1]) / 18:.0%} / {(cr[0] + cr[1]) / 18:.0%}"
        mark = ""
        if u["w"] == 180 and round(u["p"], 4) == 0.5045:
            mark = "  <== W = 180, p = 0.5045"
            matches.append((cm, cr, j))
        print(f"{str(cm):>10} {str(cr):>10} {u['w']:6.0f} {u['p']:8.4f} {u['p_uncorrected']:8.4f} "
              f"{u['p_exact']:8.4f} {sw_m:9.2e} {sw_r:9.2e}  {share}{mark}")
    if not matches:
        print("no distribution gives W = 180, p = 0.5045")
        return 1
    for cm, cr, j in matches:
        print(f"\nMatch: T_m counts {cm}, T_r counts {cr}. pwsim study's notes (--reported test=paired,W=180,p=0.5045):")
        for n in j["notes"]:
            print("  - " + n)

    # Step 2: every pairing of the matched distributions
    cm, cr, _ = matches[0]
    print(f"\nStep 2: every pairing of T_m {cm} with T_r {cr} (3x3 tables with these margins),")
    print("paired signed-rank test (R's wilcox.test(T_m, T_r, paired = TRUE)):")
    tables = []
    for t11, t12, t21, t22 in itertools.product(range(19), repeat=4):
        t13 = cm[0] - t11 - t12
        t23 = cm[1] - t21 - t22
        t31 = cr[0] - t11 - t21
        t32 = cr[1] - t12 - t22
        t33 = cm[2] - t31 - t32
        if min(t13, t23, t31, t32, t33) < 0 or t13 + t23 + t33 != cr[2]:
            continue
        tables.append(((t11, t12, t13), (t21, t22, t23), (t31, t32, t33)))
    v_values, p_values = [], []
    for table in tables:
        tm, tr = [], []
        for i in range(3):
            for k in range(3):
                tm += [i + 1] * table[i][k]
                tr += [k + 1] * table[i][k]
        ratings = os.path.join(work, "paired.csv")
        write_ratings(ratings, tm, tr)
        p = run_study(args.pwsim, ratings, work)["paired"]
        v_values.append(p["v"])
        p_values.append(p["p"])
    print(f"  {len(tables)} pairings: V in [{min(v_values):g}, {max(v_values):g}] (at most n(n+1)/2 = 171),"
          f" p in [{min(p_values):.4f}, {max(p_values):.4f}];"
          f" pairings with p = 0.5045 at 4 decimals: {sum(round(x, 4) == 0.5045 for x in p_values)}")

    example = os.path.join(args.out, "seed000_reconstructed.csv")
    write_ratings(example, expand(cm), expand(cr))
    print(f"\nExample ratings file (pairing arbitrary): {example}")
    if shutil.which("Rscript"):
        r = subprocess.run(["Rscript", "-e",
                            f"tm <- rep(1:3, c({cm[0]},{cm[1]},{cm[2]})); tr <- rep(1:3, c({cr[0]},{cr[1]},{cr[2]}));"
                            "r <- suppressWarnings(wilcox.test(tm, tr)); cat(R.version.string, ': W =', r$statistic,"
                            " ', p =', format(r$p.value, digits = 7), '\\n')"],
                           capture_output=True, text=True, check=True)
        print("R check, wilcox.test(T_m, T_r):", r.stdout.strip())
    return 0


if __name__ == "__main__":
    sys.exit(main())
