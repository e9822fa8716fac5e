#!/usr/bin/python3
"""Golden values for tests/sysid/platform/signal_filters_test.cc from scipy.signal (dev-time
only; the test carries the numbers). MATLAB filtfilt = scipy filtfilt(padtype='odd',
padlen=3*(nfilt-1)); MATLAB decimate = cheby1(8, 0.05, 0.8/r) + that filtfilt + nbeg."""
import numpy as np
import scipy.signal as sg

k = np.arange(100.0)
x = np.sin(0.05 * k) + 0.3 * np.cos(0.7 * k) + 0.01 * k
b, a = sg.butter(4, 0.2)
y = sg.filtfilt(b, a, x, padtype="odd", padlen=12)
bc, ac = sg.cheby1(8, 0.05, 0.08)
yc = sg.filtfilt(bc, ac, x, padtype="odd", padlen=24)
n, r = len(x), 10
nout = int(np.ceil(n / r))
nbeg = r - (r * nout - n)
d = yc[nbeg - 1::r]
for name, v in [("FF0", y[0]), ("FF37", y[37]), ("FF99", y[99]), ("DEC0", d[0]), ("DEC5", d[5])]:
    print(f"PWSIM_GOLDEN_{name} {v!r}")
