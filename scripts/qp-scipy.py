#!/usr/bin/env python3
"""The fallback reference of pwsim's QP benchmark where R's quadprog is absent: the same
problems (the plain-text form of mca/qp_problem.h, see scripts/qp-quadprog.R)

    minimise 1/2 x'Px + q'x   subject to   Gx <= h

solved as a least-distance program by scipy's NNLS (Lawson & Hanson, "Solving Least Squares
Problems", ch. 23), an exact active-set method of its own, independent of pwsim's solver:
with P = L L' and y = L'x + L^-1 q the problem is  min ||y||  s.t.  E y >= f,  E = -G L^-T,
f = -(h + G P^-1 q).  NNLS on  [E'; f'] u ~ [0; 1], u >= 0  gives the residual r; y = -r[:n]/r[n]
(r[n] = 0 means infeasible) and x = L^-T (y - L^-1 q), then polished on NNLS's active set by the equality-constrained
KKT system when that point is feasible with multipliers >= 0. Rows of G that are zero are checked
(0 <= h_i up to 1e-15 max|h|) and left out.

    python3 scripts/qp-scipy.py IN OUT [BATCHES PER_BATCH]

OUT: the line format of scripts/qp-quadprog.R (NAME STATUS OBJECTIVE SECONDS ITERATIONS x...);
ITERATIONS is NA (NNLS does not report it); SECONDS as there (time.perf_counter, inside Python,
start-up and reading excluded).
"""
import statistics
import sys
import time

import numpy as np
from scipy.linalg import cho_factor, solve_triangular
from scipy.optimize import nnls


def read_problems(path):
    with open(path) as f:
        lines = f.read().split("\n")
    if not lines or lines[0] != "pwsim-qp-text/1":
        sys.exit(f"{path}:1: expected the header 'pwsim-qp-text/1'")
    k = 1
    while k < len(lines) and lines[k]:
        head = lines[k].split(" ")
        if len(head) != 4 or head[0] != "problem":
            sys.exit(f"{path}:{k + 1}: expected 'problem NAME n m'")
        name, n, m = head[1], int(head[2]), int(head[3])
        vals = [np.array(lines[k + i].split(), dtype=float) for i in range(1, 5)]
        for i, (what, count) in enumerate((("P", n * n), ("q", n), ("G", m * n), ("h", m))):
            if vals[i].size != count:
                sys.exit(f"{path}:{k + 2 + i}: field '{what}': expected {count} numbers, got {vals[i].size}")
        yield name, vals[0].reshape(n, n), vals[1], vals[2].reshape(m, n), vals[3]
        k += 5


def solve(p, q, g, h):
    n = q.size
    # a zero row of G constrains nothing: 0 <= h_i holds up to the rounding of the data (a few
    # ulps of the largest |h|; the LIPMWALK set has h_i = -2.8e-17 there), else infeasible
    zero = ~g.any(axis=1)
    if np.any(h[zero] < -1e-15 * max(1e-300, np.abs(h).max(initial=0.0))):
        return None
    g, h = g[~zero], h[~zero]
    scale = np.abs(p).max()  # P/s, q/s: the same minimiser, ||y|| of order one for NNLS
    p, q = p / scale, q / scale
    c, lower = cho_factor(p, lower=True)
    l = np.tril(c)
    linv_q = solve_triangular(l, q, lower=True)
    g_lt = solve_triangular(l, g.T, lower=True).T          # G L^-T
    e = -g_lt
    f = -(h + g_lt @ linv_q)
    a = np.vstack([e.T, f[None, :]])
    b = np.zeros(n + 1)
    b[n] = 1.0
    u, _ = nnls(a, b, maxiter=50 * (a.shape[1] + 1))
    r = a @ u - b
    if abs(r[n]) < 1e-12 * np.linalg.norm(r):
        return None
    y = -r[:n] / r[n]
    x = solve_triangular(l.T, y - linv_q, lower=False)
    # y = -r/r[n] loses digits when r[n] is small (a far minimiser): polish on NNLS's active set
    # (u > 0) by the equality-constrained KKT system; kept when it is feasible with lambda >= 0
    active = np.flatnonzero(u > 0)
    if active.size:
        ga = g[active]
        kkt = np.block([[p, ga.T], [ga, np.zeros((active.size, active.size))]])
        try:
            sol = np.linalg.solve(kkt, np.concatenate([-q, h[active]]))
        except np.linalg.LinAlgError:
            return x
        x_polished, lam = sol[:n], sol[n:]
        scale_h = np.abs(h).max(initial=1.0)
        if lam.min() >= -1e-9 * max(1.0, np.abs(lam).max()) and (g @ x_polished - h).max() <= 1e-9 * scale_h:
            return x_polished
    return x


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: qp-scipy.py IN OUT [BATCHES PER_BATCH]")
    batches = int(sys.argv[3]) if len(sys.argv) > 3 else 0
    per_batch = int(sys.argv[4]) if len(sys.argv) > 4 else 1
    out = []
    for name, p, q, g, h in read_problems(sys.argv[1]):
        try:
            x = solve(p, q, g, h)
            status = "optimal" if x is not None else "infeasible"
        except Exception as error:  # noqa: BLE001 (any failure is reported, not raised)
            x, status = None, "error:" + "_".join(str(error).split())
        seconds = "NA"
        if x is not None and batches > 0:
            per_call = []
            for _ in range(batches):
                start = time.perf_counter()
                for _ in range(per_batch):
                    solve(p, q, g, h)
                per_call.append((time.perf_counter() - start) / per_batch)
            seconds = "%.6e" % statistics.median(per_call)
        if x is None:
            objective, xs = "NA", " ".join(["NA"] * q.size)
        else:
            objective = "%.17g" % (0.5 * x @ p @ x + q @ x)
            xs = " ".join("%.17g" % v for v in x)
        out.append(f"{name} {status} {objective} {seconds} NA {xs}")
    with open(sys.argv[2], "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
