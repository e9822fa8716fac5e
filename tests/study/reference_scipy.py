#!/usr/bin/python3
"""Reference values for tests/study from scipy (Debian python3-scipy), plus exact conditional
p-values and effect sizes by brute-force enumeration (independent of the C++ recursions).

usage: reference_scipy.py CORPUS OUT
CORPUS: id,group,value (group x or y). OUT: one row per id; "NA" where a value does not apply.
scipy is called with R's conventions (see shared/spec/study.md): signed-rank with zeros
dropped and continuity correction; exact only where R 4.2 would use it (n < 50, no ties or
zeros); rank-sum likewise. scipy's signed-rank statistic is min(R+, R-).
"""
import csv
import itertools
import math
import sys

import numpy as np
from scipy import stats


def fmt(v):
    return "NA" if v is None or (isinstance(v, float) and math.isnan(v)) else repr(float(v))


def side_p(stat, mean, dist_values):
    """R's two-sided exact rule: double the tail on the side of the observation (capped at 1)."""
    vals = np.asarray(dist_values)
    eps = 1e-9
    if stat > mean + eps:
        tail = np.mean(vals >= stat - eps)
    else:
        tail = np.mean(vals <= stat + eps)
    return min(1.0, 2.0 * tail)


def main():
    groups = {}
    with open(sys.argv[1]) as f:
        for row in csv.DictReader(f):
            groups.setdefault(int(row["id"]), {"x": [], "y": []})[row["group"]].append(float(row["value"]))
    out = ["id,sw_x_w,sw_x_p,sw_y_w,sw_y_p,paired_stat,paired_p,unpaired_u,unpaired_p,"
           "paired_p_exact,unpaired_p_exact,matched_rank_biserial,rank_biserial"]
    for gid in sorted(groups):
        x = np.array(groups[gid]["x"])
        y = np.array(groups[gid]["y"])
        row = [str(gid)]
        for v in (x, y):
            if len(v) >= 3 and np.ptp(v) >= 1e-10:
                r = stats.shapiro(v)
                row += [fmt(r.statistic), fmt(r.pvalue)]
            else:
                row += ["NA", "NA"]
        # paired
        ps = pp = pex = mrb = None
        if len(x) == len(y):
            d = x - y
            nz = d[d != 0]
            if len(nz) > 0:
                ranks = stats.rankdata(np.abs(nz))
                ties = len(set(ranks)) != len(ranks)
                zeros = len(nz) != len(d)
                exact = len(nz) < 50 and not ties and not zeros
                r = stats.wilcoxon(x, y, zero_method="wilcox", correction=True,
                                   method="exact" if exact else "approx")
                ps, pp = r.statistic, r.pvalue
                rplus = ranks[nz > 0].sum()
                rminus = ranks[nz < 0].sum()
                mrb = (rplus - rminus) / (rplus + rminus)
                if len(nz) <= 14:  # all 2^n sign patterns
                    dist = [sum(r_ for r_, s in zip(ranks, signs) if s)
                            for signs in itertools.product((0, 1), repeat=len(nz))]
                    pex = side_p(rplus, len(nz) * (len(nz) + 1) / 4.0, dist)
        row += [fmt(ps), fmt(pp)]
        # unpaired
        pooled = np.concatenate([x, y])
        uu = up = uex = None
        if np.ptp(pooled) > 0:
            ranks = stats.rankdata(pooled)
            ties = len(set(ranks)) != len(ranks)
            exact = len(x) < 50 and len(y) < 50 and not ties
            r = stats.mannwhitneyu(x, y, use_continuity=True, alternative="two-sided",
                                   method="exact" if exact else "asymptotic")
            uu, up = r.statistic, r.pvalue
            n_all = len(pooled)
            if math.comb(n_all, len(x)) <= 20000:  # all splits of the pooled ranks
                u_obs = ranks[:len(x)].sum() - len(x) * (len(x) + 1) / 2.0
                dist = [sum(ranks[list(c)]) - len(x) * (len(x) + 1) / 2.0
                        for c in itertools.combinations(range(n_all), len(x))]
                uex = side_p(u_obs, len(x) * len(y) / 2.0, dist)
        row += [fmt(uu), fmt(up), fmt(pex), fmt(uex), fmt(mrb)]
        # rank-biserial from its definition P(x > y) - P(x < y) over all pairs
        diff = x[:, None] - y[None, :]
        row.append(fmt(float(np.mean(np.sign(diff)))))
        out.append(",".join(row))
    with open(sys.argv[2], "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
