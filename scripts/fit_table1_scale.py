#!/usr/bin/env python3
"""Fits the one window scale c (a = c 2^j dx, rkpm rule=custom) that best reproduces 004 II
Table 1 (peak u' at x = 3 of laplace-tanh, Gaussian window) over the 21/41/81-node rows.

Why: read literally, eq 7.4 gives windows so wide that the peak falls as j grows, the opposite
of Table 1 (see the catalogue). This script measures which single scale the table implies;
the default suite runs both readings. Usage: scripts/fit_table1_scale.py [build/release/apps/mfv]
"""
import math
import subprocess
import sys

MFV = sys.argv[1] if len(sys.argv) > 1 else "build/release/apps/mfv"
JS = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0]
ROWS = {21: [3.5100, 3.8315, 4.6672, 5.3217, 5.4837, 5.1865],
        41: [6.3599, 6.7798, 7.6968, 8.3095, 8.5252, 8.5419],
        81: [8.7556, 9.0684, 9.6081, 9.8416, 9.8864, 9.9010]}


def peak(nodes, j, scale):
    out = subprocess.run([MFV, "run", "laplace-tanh", "-m", "rkpm", "-n", str(nodes), "-p",
                          f"kernel=gaussian,j={j},rule=custom,scale={scale}"],
                         capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        if line.startswith("peak du/dx at x=3"):
            return float(line.split()[-1])
    raise RuntimeError("no peak in output:\n" + out)


def rms(scale):
    d = [peak(n, j, scale) - v for n, row in ROWS.items() for j, v in zip(JS, row)]
    return math.sqrt(sum(x * x for x in d) / len(d))


lo, hi = 0.15, 0.8
g = (math.sqrt(5) - 1) / 2
a, b = hi - g * (hi - lo), lo + g * (hi - lo)
fa, fb = rms(a), rms(b)
while hi - lo > 2e-3:
    if fa < fb:
        hi, b, fb = b, a, fa
        a = hi - g * (hi - lo)
        fa = rms(a)
    else:
        lo, a, fa = a, b, fb
        b = lo + g * (hi - lo)
        fb = rms(b)
c = 0.5 * (lo + hi)
print(f"best single scale c = {c:.4f} (a = c 2^j dx), rms peak difference {rms(c):.4f}")
print(f"eq 7.4 read literally: c = {2 / math.sqrt(math.pi):.4f}, rms {rms(2 / math.sqrt(math.pi)):.4f}")
