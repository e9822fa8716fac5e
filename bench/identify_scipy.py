#!/usr/bin/env python3
"""Solves the output-error problem exported by identify_bench with scipy.optimize.least_squares.

Same problem as pwsim's Ceres stage (sysid/identify/identify.cc): per trial and axis, the lumped
model (M s^2 + C s + K) X = (C s + K) X_GM, discretised exactly for a first-order hold on the
1 kHz grid, started at rest, sampled at the mocap times by linear interpolation; residuals are
the measured output minus its initial-window offset minus the model, weighted by 1/rms of each
channel; parameters log K, log C per axis; same linear start; central differences
('3-point', as Ceres' CENTRAL) and a trust-region method ('trf').

usage: identify_scipy.py DIR   (DIR holds problem.json and the .bin files)
"""
import json
import sys
import time

import numpy as np
import scipy
from scipy.linalg import expm
from scipy.optimize import least_squares
from scipy.signal import lfilter, lfilter_zi, ss2tf


def load(directory):
    with open(f"{directory}/problem.json") as f:
        meta = json.load(f)
    trials = []
    for entry in meta["trials"]:
        read = lambda name: np.fromfile(f"{directory}/{entry['stem']}_{name}.bin", dtype=np.float64)
        t = read("t")
        trials.append({
            "t0": entry["t0"], "dt": entry["dt"], "t": t,
            "grid_t": entry["t0"] + entry["dt"] * np.arange(read("z_gm").size),
            "axes": [
                {"u": read("z_gm"), "y": read("z"), "inertia": entry["mass"]},
                {"u": read("pitch_gm"), "y": read("pitch"), "inertia": entry["inertia"]},
            ],
            "window": max(1, int(np.count_nonzero(t - t[0] <= meta["offset_window_s"]))),
        })
    # Channel weights: 1 / rms of (y - trial mean), pooled over the trials.
    for axis in (0, 1):
        dev = np.concatenate([tr["axes"][axis]["y"] - tr["axes"][axis]["y"].mean() for tr in trials])
        weight = 1.0 / np.sqrt(np.mean(dev ** 2))
        for tr in trials:
            tr["axes"][axis]["weight"] = weight
    return meta, trials


def foh_filter(inertia, damping, stiffness, dt):
    """(b, a) of the exact FOH discretisation of (C s + K) / (M s^2 + C s + K)."""
    a = np.zeros((4, 4))  # augmented state [q, q', u, u']
    a[0, 1] = 1.0
    a[1, 0] = -stiffness / inertia
    a[1, 1] = -damping / inertia
    a[1, 2] = stiffness / inertia
    a[1, 3] = damping / inertia
    a[2, 3] = 1.0
    phi = expm(a * dt)
    a_d = phi[:2, :2]
    b0 = phi[:2, 2] - phi[:2, 3] / dt  # x+ = A x + b0 u_k + b1 u_{k+1}
    b1 = phi[:2, 3] / dt
    c = np.array([[1.0, 0.0]])
    # w = x - b1 u  =>  w+ = A w + (A b1 + b0) u,  q = C w + C b1 u
    b, den = ss2tf(a_d, (a_d @ b1 + b0).reshape(2, 1), c, (c @ b1).reshape(1, 1))
    return b[0], den


def axis_residuals(trial, axis, stiffness, damping):
    data = trial["axes"][axis]
    b, a = foh_filter(data["inertia"], damping, stiffness, trial["dt"])
    zi = lfilter_zi(b, a) * data["u"][0]  # at rest in equilibrium (unit DC gain)
    q, _ = lfilter(b, a, data["u"], zi=zi)
    model = np.interp(trial["t"], trial["grid_t"], q)
    error = data["y"] - model
    error -= error[: trial["window"]].mean()
    return data["weight"] * error


def residuals(p, trials):
    k_z, c_z, k_p, c_p = np.exp(p)
    parts = []
    for trial in trials:
        parts.append(axis_residuals(trial, 0, k_z, c_z))
        parts.append(axis_residuals(trial, 1, k_p, c_p))
    return np.concatenate(parts)


def main():
    meta, trials = load(sys.argv[1])
    x0 = np.log(np.array(meta["start"]))
    begin = time.perf_counter()
    solution = least_squares(residuals, x0, args=(trials,), jac="3-point", method="trf",
                             ftol=1e-12, xtol=1e-10, gtol=1e-14)
    seconds = time.perf_counter() - begin
    k_z, c_z, k_p, c_p = np.exp(solution.x)
    ours = meta["pwsim_result"]
    print(f"scipy {scipy.__version__} least_squares (trf, 3-point), {len(trials)} trials, "
          f"{solution.nfev} evaluations + {solution.njev} Jacobians: {seconds * 1e3:.1f} ms")
    print(f"  K_z {k_z:.6g}  C_z {c_z:.6g}  K_theta {k_p:.6g}  C_theta {c_p:.6g}")
    worst = max(abs(s / o - 1.0) for s, o in zip((k_z, c_z, k_p, c_p), ours))
    print(f"  largest relative difference to pwsim's solution: {worst:.2e}")
    print(f"SCIPY_SECONDS {seconds:.6f}")


if __name__ == "__main__":
    main()
