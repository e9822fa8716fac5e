#!/usr/bin/python3
"""IDIM-LS of the EMPS axis with scipy: the same chain as `pwsim platform identify`
(Janot/Gautier reference method) written independently with scipy.signal, used as the parity
oracle and as the side-by-side timing of bench/platform_identify_bench (same chain, C++).

usage: platform_identify_scipy.py DATA_EMPS.mat [--repeat N]
Prints the parameters, their standard deviations, the relative error, cond(X), rows and the
median wall and CPU time of N runs (reading included) in JSON.
"""
import json
import sys
import time

import numpy as np
import scipy.io
import scipy.signal as sg


def filtfilt_matlab(b, a, x):
    # MATLAB filtfilt: odd reflection of 3*(nfilt-1) samples, steady-state initial conditions.
    nfilt = max(len(a), len(b))
    return sg.filtfilt(b, a, x, axis=0, padtype="odd", padlen=3 * (nfilt - 1))


def decimate_matlab(x, r):
    # MATLAB decimate(x, r): cheby1(8, 0.05 dB, 0.8/r), filtfilt, keep nbeg = r - (r*nout - n).
    b, a = sg.cheby1(8, 0.05, 0.8 / r)
    y = filtfilt_matlab(b, a, x)
    n = len(x)
    nout = int(np.ceil(n / r))
    nbeg = r - (r * nout - n)  # 1-based
    return y[nbeg - 1::r]


def diffcent(x, dt):
    d = np.empty_like(x)
    d[1:-1] = (x[2:] - x[:-2]) / (2 * dt)
    d[0] = (x[1] - x[0]) / dt
    d[-1] = (x[-1] - x[-2]) / dt
    return d


def identify(path):
    m = scipy.io.loadmat(path)
    t = m["t"].ravel()
    qm = m["qm"].ravel()
    vir = m["vir"].ravel()
    gtau = float(m["gtau"].ravel()[0])
    dt = (t[-1] - t[0]) / (len(t) - 1)
    fs = 1.0 / dt
    b, a = sg.butter(4, 100.0 / (fs / 2))  # 100 Hz cut-off (about 5x the 20 Hz loop bandwidth)
    q = filtfilt_matlab(b, a, qm)
    qd = diffcent(q, dt)
    qdd = diffcent(qd, dt)
    tau = gtau * vir
    s = slice(49, None)
    X = np.column_stack([qdd[s], qd[s], np.sign(qd[s]), np.ones(len(qd[s]))])
    y = tau[s]
    Xd = np.column_stack([decimate_matlab(X[:, j], 10) for j in range(X.shape[1])])
    yd = decimate_matlab(y, 10)
    theta, *_ = np.linalg.lstsq(Xd, yd, rcond=None)
    e = yd - Xd @ theta
    n, p = Xd.shape
    sig_e = np.std(e, ddof=1)  # the reference script: std(e), mean removed, N-1
    sigma = sig_e * np.sqrt(np.diag(np.linalg.inv(Xd.T @ Xd)))
    return {
        "parameters": theta.tolist(),
        "sigma": sigma.tolist(),
        "relative_error_pct": float(100 * np.linalg.norm(e) / np.linalg.norm(yd)),
        "condition_number": float(np.linalg.cond(Xd)),
        "rows": int(n),
    }


def main():
    path = sys.argv[1]
    repeat = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 5
    times, cpu = [], []
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        result = identify(path)
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    result["median_s"] = float(np.median(times))
    result["median_cpu_s"] = float(np.median(cpu))
    result["repeat"] = repeat
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
