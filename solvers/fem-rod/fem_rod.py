#!/usr/bin/env python3
"""The whole mfv-external-1 protocol in one page: a 1D linear finite-element rod.

mfv runs `python3 fem_rod.py DIR`. DIR holds input.json and particles.csv
(docs/external-solvers.md); the adapter writes DIR/frames/index.csv and one
DIR/frames/frame-<k>.csv per requested output time. For the rod pulse (nu = 0) the
plane-strain rod moves as a 1D rod, so the nodes are the particles' distinct x.
"""
import csv, json, math, os, sys

# 1. Read the case.
case = sys.argv[1]
inp = json.load(open(os.path.join(case, "input.json")))
assert inp["protocol"] == "mfv-external-1", inp["protocol"]
parts = list(csv.DictReader(open(os.path.join(case, "particles.csv"))))
E = inp["material"]["params"]["E"]
rho = inp["material"]["density"]

# 2. Nodes at the particles' distinct x; initial velocity from the particles on each x.
xs = sorted({float(p["x"]) for p in parts})
node = {x: i for i, x in enumerate(xs)}
n = len(xs)
h = (xs[-1] - xs[0]) / (n - 1)
v = [0.0] * n
for p in parts:
    v[node[float(p["x"])]] = float(p["vx0"])
u = [0.0] * n
# Prescribed velocities (the rod's impulse): on the nodes of the particles named.
fixed = {node[float(parts[q["particle"]]["x"])]: (q["value"], q["until"])
         for q in inp["prescribed_velocity"] if q["component"] == 0}
m = [rho * h * (0.5 if i in (0, n - 1) else 1.0) for i in range(n)]  # lumped, per unit area


def force(u):
    f = [0.0] * n
    for e in range(n - 1):
        s = E * (u[e + 1] - u[e]) / h  # the element's stress
        f[e] += s
        f[e + 1] -= s
    return f


# 3. Central differences (velocity Verlet), landing exactly on every output time.
dt_max = 0.5 * h / math.sqrt(E / rho)
t = 0.0
a = [fi / mi for fi, mi in zip(force(u), m)]
os.makedirs(os.path.join(case, "frames"))
index = open(os.path.join(case, "frames", "index.csv"), "w")
index.write("mfv-external-1\nk,time,steps\n")  # steps: optional, for particle-steps/s
# The energy account (optional): kinetic energy and the internal forces' work since t = 0.
# With prescribed velocities the reactions' work would be owed too; this example then keeps none.
energy = None if fixed else open(os.path.join(case, "frames", "energy.csv"), "w")
kinetic = lambda: sum(0.5 * mi * vi * vi for mi, vi in zip(m, v))
w_int = 0.0
if energy:
    energy.write(f"mfv-external-1\ntime,kinetic,internal_work\n0,{kinetic()!r},0\n")
count = 0
for k, t_out in enumerate(inp["output_times"]):
    steps = max(1, math.ceil((t_out - t) / dt_max - 1e-9))
    dt = (t_out - t) / steps
    for _ in range(steps):
        vh = [vi + 0.5 * dt * ai for vi, ai in zip(v, a)]
        for i, (val, until) in fixed.items():
            vh[i] = val if t + 0.5 * dt < until else vh[i]
        u = [ui + dt * vi for ui, vi in zip(u, vh)]
        f_old = [ai * mi for ai, mi in zip(a, m)]
        a = [fi / mi for fi, mi in zip(force(u), m)]
        w_int -= sum(0.5 * (fo + ai * mi) * dt * vi for fo, ai, mi, vi in zip(f_old, a, m, vh))
        v = [vi + 0.5 * dt * ai for vi, ai in zip(vh, a)]
        t += dt
        count += 1
        for i, (val, until) in fixed.items():
            v[i] = val if t < until else v[i]
    t = t_out
    # 4. One frame: every particle, the fields of its node (sxx: the mean of its elements').
    with open(os.path.join(case, "frames", f"frame-{k}.csv"), "w") as out:
        out.write("id,ux,uy,vx,vy,sxx,syy,sxy\n")
        for p in parts:
            i = node[float(p["x"])]
            el = [e for e in (i - 1, i) if 0 <= e < n - 1]
            sxx = sum(E * (u[e + 1] - u[e]) / h for e in el) / len(el)
            out.write(f"{p['id']},{u[i]!r},0,{v[i]!r},0,{sxx!r},0,0\n")
    index.write(f"{k},{t_out!r},{count}\n")
    if energy:
        energy.write(f"{t_out!r},{kinetic()!r},{w_int!r}\n")
index.close()
