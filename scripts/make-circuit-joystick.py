#!/usr/bin/env python3
"""Writes scenes/drives/circuit_weave_50hz.csv: a recorded-joystick stand-in for
scenes/circuit_recorded.yaml (50 Hz, header t_s,forward,turn). Forward deflection ramps to 0.55
over 1-2 s and holds; the turn weaves as 0.6 e(t) cos(2 pi (t - 2) / 5) from 2 s to 17 s, e rising
from 0 to 1 over the first second (a weave about the start heading); the stick is released
from 18 s. Deterministic: same file every run."""
import math
import pathlib
import sys

out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "scenes/drives/circuit_weave_50hz.csv")
rows = ["t_s,forward,turn"]
for k in range(0, 20 * 50 + 1):
    t = k / 50.0
    forward = 0.0 if t < 1.0 else min(0.55, 0.55 * (t - 1.0)) if t < 18.0 else max(0.0, 0.55 - 0.55 * (t - 18.0) / 0.5)
    envelope = min(1.0, t - 2.0)
    turn = 0.6 * envelope * math.cos(2.0 * math.pi * (t - 2.0) / 5.0) if 2.0 <= t <= 17.0 else 0.0
    rows.append(f"{t:.2f},{forward:.4f},{turn:.4f}")
out.write_text("\n".join(rows) + "\n")
