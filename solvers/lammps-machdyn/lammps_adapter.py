#!/usr/bin/python3
"""LAMMPS MACHDYN (pair_style smd/tlsph, total-Lagrangian SPH) behind mfv's protocol
mfv-external-1 (docs/external-solvers.md; this adapter: docs/external-lammps.md).

mfv runs `/usr/bin/python3 lammps_adapter.py DIR`. The adapter:
1. reads DIR/input.json and DIR/particles.csv and refuses, with a reason, what it cannot
   run: not 2D, a material other than mfv's plane-strain St Venant-Kirchhoff (run as
   TLSPH's linear elasticity, *STRENGTH_LINEAR + *EOS_LINEAR, which agrees with it at small
   strain), prescribed velocities it cannot express, output times off a common step grid;
2. writes DIR/lammps/data.lmp (mfv's particles: reference positions, volumes, masses,
   initial velocities; LAMMPS atom id = mfv id + 1) and DIR/lammps/in.mfv (the deck);
3. runs LAMMPS once (`lmp -in in.mfv`): a fixed timestep dt <= cfl * h / c_p (fix
   smd/adjust_dt's rule) chosen so that every output time is a whole number of steps, one
   `run` for the whole case (a second `run` would repeat one stress increment in TLSPH's
   setup), and a dump at exactly the output times' steps;
4. converts each dump to DIR/frames/frame-<k>.csv: u = x - X (X: mfv's reference
   position), LAMMPS's velocities, and the Cauchy stress of compute smd/tlsph/stress; and
   writes frames/index.csv (k,time,steps) and, without prescribed velocities,
   frames/energy.csv (kinetic energy and TLSPH's internal energy, summed).

The lmp program: $MFV_LAMMPS if set, else `lmp` on PATH. `lammps_adapter.py --check` exits
non-zero (with the reason on stderr) when it is missing or lacks the MACHDYN package.
solver_params (solvers/lammps-machdyn.toml [solver.params]): h_over_dx (2.01: the kernel's
support radius over the spacing, the peer deck's `diameter`), cfl (0.1), q1 (0.06), q2 (0),
hg (10), cp (1), volumes ("mfv" or "uniform").
"""
import csv
import glob
import json
import math
import os
import shutil
import subprocess
import sys
import time
from fractions import Fraction

HINT = ("build LAMMPS with MACHDYN (scripts/bench_lammps.sh, docs/external-lammps.md) and "
        "set MFV_LAMMPS to its lmp")


def find_lmp():
    """The lmp program: $MFV_LAMMPS, else lmp on PATH; None with the reason if absent."""
    env = os.environ.get("MFV_LAMMPS")
    if env:
        if os.path.isfile(env) and os.access(env, os.X_OK):
            return env, None
        return None, f"MFV_LAMMPS={env} is not an executable file"
    found = shutil.which("lmp")
    if found:
        return found, None
    return None, "no lmp on PATH and MFV_LAMMPS is not set"


def check():
    lmp, why = find_lmp()
    if lmp is None:
        sys.exit(f"LAMMPS not found: {why}; {HINT}")
    try:
        out = subprocess.run([lmp, "-h"], stdin=subprocess.DEVNULL, capture_output=True,
                             text=True, timeout=50).stdout
    except (OSError, subprocess.TimeoutExpired) as e:
        sys.exit(f"{lmp} -h failed: {e}")
    pk = out.split("Installed packages:", 1)
    if len(pk) < 2 or "MACHDYN" not in pk[1].split("List of individual style options")[0]:
        sys.exit(f"{lmp} has no MACHDYN package (lmp -h lists none); {HINT}")
    sys.exit(0)


if len(sys.argv) == 2 and sys.argv[1] == "--check":
    check()
if len(sys.argv) != 2:
    sys.exit("usage: lammps_adapter.py CASE_DIR | --check")

import numpy as np  # noqa: E402

case = os.path.abspath(sys.argv[1])
inp = json.load(open(os.path.join(case, "input.json")))
if inp.get("protocol") != "mfv-external-1":
    sys.exit(f"protocol {inp.get('protocol')} is not mfv-external-1")
if inp["dim"] != 2:
    sys.exit(f"this adapter runs 2D cases only (dim = {inp['dim']}): LAMMPS's TLSPH here is "
             "set up as a 2D plane-strain solid")

# --- The material: mfv's plane-strain SVK, run as TLSPH's linear elasticity. ---
mat = inp["material"]
if mat.get("model") != "svk":
    sys.exit(f"material model {mat.get('model')!r}: this adapter runs mfv's 'svk' (as TLSPH's "
             "*STRENGTH_LINEAR + *EOS_LINEAR, equal to it at small strain) and nothing else")
mp = mat["params"]
unknown = set(mp) - {"E", "nu", "plane"}
if unknown:
    sys.exit(f"material parameters {sorted(unknown)} are not E, nu, plane: not supported")
if mp.get("plane", "strain") != "strain":
    sys.exit(f"plane = {mp.get('plane')!r}: LAMMPS's 2D TLSPH is plane strain; this case is not")
E, nu, rho = float(mp["E"]), float(mp.get("nu", 0.0)), float(mat["density"])
if not (E > 0 and rho > 0 and -1 < nu < 0.5):
    sys.exit(f"material E = {E}, nu = {nu}, rho = {rho} is not a linear elastic solid")

par = inp.get("solver_params", {})
known = {"h_over_dx", "cfl", "q1", "q2", "hg", "cp", "volumes", "keep"}
if set(par) - known:
    sys.exit(f"unknown solver parameters {sorted(set(par) - known)}")
h_over_dx = float(par.get("h_over_dx", 2.01))
cfl = float(par.get("cfl", 0.1))
q1, q2 = float(par.get("q1", 0.06)), float(par.get("q2", 0.0))
hg, cp = float(par.get("hg", 10.0)), float(par.get("cp", 1.0))
volumes = str(par.get("volumes", "mfv"))
if volumes not in ("mfv", "uniform"):
    sys.exit(f"volumes = {volumes!r}: use mfv (mfv's Voronoi volumes and masses) or uniform "
             "(dx^2 and rho dx^2 for every particle, as the peer deck)")
if not (h_over_dx > 1.0 and 0 < cfl <= 1.0):
    sys.exit(f"h_over_dx = {h_over_dx} must exceed 1 and cfl = {cfl} lie in (0, 1]")

# --- mfv's particles. ---
rows = list(csv.DictReader(open(os.path.join(case, "particles.csv"))))
n = len(rows)
if n != inp["particles"]["count"]:
    sys.exit(f"particles.csv has {n} rows, input.json says {inp['particles']['count']}")
ids = np.array([int(r["id"]) for r in rows])
if not np.array_equal(ids, np.arange(n)):
    sys.exit("particles.csv ids are not 0 .. N-1 in order")
X = np.array([float(r["x"]) for r in rows])
Y = np.array([float(r["y"]) for r in rows])
vol = np.array([float(r["volume"]) for r in rows])
mass = np.array([float(r["mass"]) for r in rows])
vx0 = np.array([float(r["vx0"]) for r in rows])
vy0 = np.array([float(r["vy0"]) for r in rows])

# The spacing: mfv's particles are a lattice; the smallest gap between distinct x (or y).
def min_gap(a):
    g = np.diff(np.unique(np.round(a, 12)))
    g = g[g > 0]
    return float(g.min()) if g.size else math.inf


dx = min(min_gap(X), min_gap(Y))
if not math.isfinite(dx):
    sys.exit("cannot find the particle spacing (all particles on one point)")
if volumes == "uniform":
    vol = np.full(n, dx * dx)
    mass = rho * vol
h = h_over_dx * dx  # the kernel's support radius; LAMMPS: diameter = h, radius = h / 2

# --- Prescribed velocities: fix smd/setvel per (component, value, until). ---
end = float(inp["end_time"])
groups = {}
seen = {}
for p in inp["prescribed_velocity"]:
    i, c, val, until = int(p["particle"]), int(p["component"]), float(p["value"]), float(p["until"])
    if not (0 <= i < n) or c not in (0, 1):
        sys.exit(f"prescribed velocity on particle {i}, component {c}: out of range")
    if (i, c) in seen:
        sys.exit(f"particle {i} component {c} has two prescribed velocities: not supported")
    seen[(i, c)] = True
    groups.setdefault((c, val, until), []).append(i)

# --- The time grid: every output time a whole number of steps of one fixed dt. ---
times = [float(t) for t in inp["output_times"]]
if not times or any(b <= a for a, b in zip([0.0] + times, times)):
    sys.exit("output_times must be increasing and positive")
fr = []
for t in times:
    f = Fraction(t / end).limit_denominator(100000)
    if abs(float(f) * end - t) > 1e-10 * t:
        sys.exit(f"output time {t!r} is not a fraction of end_time {end!r} with a denominator "
                 "below 100000: this adapter runs LAMMPS in one run with one fixed step and "
                 "cannot land on it")
    fr.append(f)
M = 1
for f in fr:
    M = M * f.denominator // math.gcd(M, f.denominator)
c_p = math.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))
dt_max = cfl * h / c_p  # fix smd/adjust_dt's rule: cfl * 2 radius / c_p
per = max(1, math.ceil((end / M) / dt_max - 1e-9))
dt = end / (M * per)
steps = [int(f * M) * per for f in fr]  # exact: f * M is an integer
if len(set(steps)) != len(steps) or steps[0] <= 0:
    sys.exit("two output times fall on one step")
nsteps = steps[-1]
if nsteps > 10 ** 8:
    sys.exit(f"{nsteps} steps: too many (the output times need a grid of end_time / {M})")

# --- Write the data file and the deck. ---
work = os.path.join(case, "lammps")
os.makedirs(work, exist_ok=True)
os.makedirs(os.path.join(case, "frames"), exist_ok=True)
pad = 2.0 * h
with open(os.path.join(work, "data.lmp"), "w") as d:
    d.write("LAMMPS data file: mfv case particles (atom id = mfv id + 1)\n\n")
    d.write(f"{n} atoms\n1 atom types\n\n")
    d.write(f"{X.min() - pad!r} {X.max() + pad!r} xlo xhi\n")
    d.write(f"{Y.min() - pad!r} {Y.max() + pad!r} ylo yhi\n")
    d.write(f"{-0.5 * h!r} {0.5 * h!r} zlo zhi\n\n")
    # id type molecule vfrac rmass radius contact_radius x0 y0 z0 x y z
    d.write("Atoms # smd\n\n")
    for i in range(n):
        d.write(f"{i + 1} 1 1 {vol[i]!r} {mass[i]!r} {0.5 * h!r} {0.5 * dx!r} "
                f"{X[i]!r} {Y[i]!r} 0 {X[i]!r} {Y[i]!r} 0\n")
    d.write("\nVelocities\n\n")
    for i in range(n):
        d.write(f"{i + 1} {vx0[i]!r} {vy0[i]!r} 0\n")

with open(os.path.join(work, "steps.txt"), "w") as s:
    for st in steps:
        s.write(f"{st}\n")
    s.write(f"{nsteps + 1}\n")  # the dump reads one step beyond the run

deck = f"""# mfv lammps-machdyn adapter: {inp['problem']} {inp.get('nodes')}, {n} particles
# units: mm, ms, kg, GPa (a consistent set; 'si' is only LAMMPS's label)
dimension       2
units           si
boundary        sm sm p
atom_style      smd
atom_modify     map array
comm_modify     vel yes
neigh_modify    every 10 delay 0 check yes
newton          off
read_data       data.lmp
group           tlsph type 1
neighbor        {h!r} bin
pair_style      smd/tlsph
pair_coeff      1 1 *COMMON {rho!r} {E!r} {nu!r} {q1!r} {q2!r} {hg!r} {cp!r} &
                *STRENGTH_LINEAR &
                *EOS_LINEAR &
                *END
timestep        {dt!r}
fix             integration_fix tlsph smd/integrate_tlsph
"""
for g, ((c, val, until), members) in enumerate(sorted(groups.items())):
    deck += f"group           pv{g} id " + " ".join(str(i + 1) for i in members) + "\n"
    deck += f"variable        pv{g} equal ({val!r})*(step*dt<{until!r})\n"
    comp = ["NULL", "NULL", "NULL"]
    comp[c] = f"v_pv{g}"
    deck += f"fix             pv{g} pv{g} smd/setvel {' '.join(comp)}\n"
deck += f"""compute         S all smd/tlsph/stress
compute         E all smd/internal/energy
variable        f file steps.txt
variable        s equal next(f)
dump            frames all custom {nsteps} dump.*.txt id x y vx vy c_S[1] c_S[2] c_S[4] c_E
dump_modify     frames every v_s first no sort id format float %.17g
thermo          {max(1, nsteps // 10)}
thermo_style    custom step time cpu
run             {nsteps}
"""
with open(os.path.join(work, "in.mfv"), "w") as f:
    f.write(deck)

lmp, why = find_lmp()
if lmp is None:
    sys.exit(f"LAMMPS not found: {why}; {HINT}")
print(f"LAMMPS TLSPH: {lmp}; dx = {dx:.6g}, h (support) = {h_over_dx} dx = {h:.6g}, "
      f"c_p = {c_p:.6g}, dt = {dt:.6g} (<= {cfl} h / c_p = {dt_max:.6g}), {nsteps} steps, "
      f"{n} particles, volumes {volumes}, q1 = {q1}, q2 = {q2}, hg = {hg}, cp = {cp}, "
      f"{len(seen)} prescribed velocity components in {len(groups)} fix smd/setvel, "
      f"{len(times)} output times", flush=True)
env = dict(os.environ)
env.setdefault("OMP_NUM_THREADS", "1")
t0 = time.time()
with open(os.path.join(work, "stdout.txt"), "w") as so:  # TLSPH printf()s go here
    r = subprocess.run([lmp, "-in", "in.mfv", "-log", "log.lammps", "-screen", "none"],
                       cwd=work, stdin=subprocess.DEVNULL, stdout=so, stderr=subprocess.STDOUT,
                       env=env)
screen = open(os.path.join(work, "stdout.txt")).read()
log = open(os.path.join(work, "log.lammps")).read() if os.path.exists(
    os.path.join(work, "log.lammps")) else ""
errors = [line for line in (log + screen).splitlines() if line.startswith("ERROR")]
if r.returncode != 0 or errors:
    tail = "\n".join((log or screen).splitlines()[-15:])
    sys.exit(f"lmp exited {r.returncode} after {time.time() - t0:.1f} s: "
             f"{errors[0] if errors else 'no ERROR line'}\n{tail}")
for line in log.splitlines():
    if line.startswith("Loop time") or line.startswith("Performance"):
        print(line, flush=True)
deleted = screen.count("deleting particle")  # printf() to stdout, not in the log
if deleted:
    sys.exit(f"LAMMPS deleted {deleted} particles (det F out of range): the run went unstable")

# --- Convert the dumps to frames. ---
index = open(os.path.join(case, "frames", "index.csv"), "w")
index.write("mfv-external-1\nk,time,steps\n")
# The energy account (docs/external-solvers.md section 4): kinetic energy and TLSPH's own
# internal energy (esph: the work of stress, viscous and hourglass forces, summed). Written
# only without prescribed velocities: their work is not in TLSPH's account.
energy = None
if not seen:
    energy = open(os.path.join(case, "frames", "energy.csv"), "w")
    energy.write("mfv-external-1\ntime,kinetic,internal_work\n")
    energy.write(f"0,{0.5 * float(np.sum(mass * (vx0 ** 2 + vy0 ** 2)))!r},0\n")
for k, (t, st) in enumerate(zip(times, steps)):
    path = os.path.join(work, f"dump.{st}.txt")
    if not os.path.exists(path):
        sys.exit(f"LAMMPS wrote no dump at step {st} (output time {t!r}, frame {k})")
    with open(path) as fh:
        head = [fh.readline() for _ in range(9)]
        if not head[8].startswith("ITEM: ATOMS id x y vx vy"):
            sys.exit(f"{path}: unexpected header {head[8].strip()!r}")
        if int(head[1]) != st or int(head[3]) != n:
            sys.exit(f"{path}: step {head[1].strip()} with {head[3].strip()} atoms, expected "
                     f"step {st} with {n}")
        a = np.loadtxt(fh, ndmin=2)
    if a.shape != (n, 9):
        sys.exit(f"{path}: {a.shape[0]} rows of {a.shape[1]} columns, expected {n} of 9")
    j = a[:, 0].astype(np.int64) - 1
    if not np.array_equal(np.sort(j), np.arange(n)):
        sys.exit(f"{path}: the atom ids are not 1 .. {n}")
    out = np.empty((n, 8))
    out[j, 0] = j
    out[j, 1] = a[:, 1] - X[j]
    out[j, 2] = a[:, 2] - Y[j]
    out[j, 3:8] = a[:, 3:8]
    np.savetxt(os.path.join(case, "frames", f"frame-{k}.csv"), out, delimiter=",",
               fmt=["%d"] + ["%.17g"] * 7, header="id,ux,uy,vx,vy,sxx,syy,sxy", comments="")
    index.write(f"{k},{t!r},{st}\n")
    if energy:
        kin = 0.5 * float(np.sum(mass[j] * (a[:, 3] ** 2 + a[:, 4] ** 2)))
        energy.write(f"{t!r},{kin!r},{float(np.sum(a[:, 8]))!r}\n")
    os.remove(path)
index.close()
if energy:
    energy.close()
print(f"LAMMPS: {nsteps} steps to t = {nsteps * dt:.9g}, {len(times)} frames", flush=True)
