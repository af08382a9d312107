#!/usr/bin/python3
"""PySPH's elastic-solid scheme (Gray, Monaghan & Swift 2001) behind mfv's protocol
mfv-external-1 (docs/external-solvers.md).

mfv runs `/usr/bin/python3 pysph_adapter.py DIR`. The adapter:
1. reads DIR/input.json and DIR/particles.csv (mfv's particles, masses and initial
   velocities);
2. keeps the particles mfv holds fixed (both components prescribed to zero for the whole
   run: the plate's clamp) in place: with clamp = "held" (default, mfv's definition) they stay
   elastic particles whose accelerations and XSPH velocities are zero at every stage of the
   step (HoldClamp), so they start and stay at rest where they are; with
   clamp = "walls" they become PySPH's rigid "solids" array, as PySPH's own oscillating-plate
   example builds its wall (whose stress PySPH does not integrate);
3. runs ElasticSolidsScheme (momentum and continuity equations, Hookean stress rate with
   Jaumann rotation, Monaghan artificial viscosity and artificial stress, XSPH) with a fixed
   step, landing on every output time (PySPH's output_at_times);
4. writes DIR/frames/index.csv and one frames/frame-<k>.csv per output time (u = x - X,
   PySPH's velocities u, v, and the Cauchy stress s - p I);
5. keeps an energy account, DIR/frames/energy.csv, a row per step: the kinetic energy and
   the work of PySPH's forces (stress, artificial viscosity and stress: its accelerations
   au, av at the step's corrector) over the particles' displacements (x - x0, which XSPH
   moves), summed over the particles that move. PySPH's own EnergyEquationWithStress is not
   used: ElasticSolidsScheme does not include it, and in PySPH 1.0b1 its pairwise term
   lacks the factor v_ij . grad W_ij (it computes vijdotdwij and does not use it).

Prescribed velocities other than such a clamp (the rod's rectangular impulse) are not PySPH's
and are refused with a reason. The scheme's settings are printed to stdout (the report keeps
it). solver_params (solvers/pysph.toml [solver.params]): clamp, h_over_dx (1.3), alpha (1),
beta (1), eps (0.3 artificial stress), xsph (0.5), cfl (0.2: dt = cfl h / c_p).
"""
import csv
import json
import math
import os
import sys

import numpy as np

case = os.path.abspath(sys.argv[1])
inp = json.load(open(os.path.join(case, "input.json")))
if inp["protocol"] != "mfv-external-1":
    sys.exit(f"protocol {inp['protocol']} is not mfv-external-1")
if inp["dim"] != 2:
    sys.exit("this adapter runs 2D cases only")
rows = list(csv.DictReader(open(os.path.join(case, "particles.csv"))))
n = len(rows)
ids = np.array([int(r["id"]) for r in rows])
X = np.array([float(r["x"]) for r in rows])
Y = np.array([float(r["y"]) for r in rows])
mass = np.array([float(r["mass"]) for r in rows])
vx0 = np.array([float(r["vx0"]) for r in rows])
vy0 = np.array([float(r["vy0"]) for r in rows])

mat = inp["material"]
E, nu, rho = mat["params"]["E"], mat["params"].get("nu", 0.0), mat["density"]
if mat["params"].get("plane", "strain") != "strain":
    sys.exit("PySPH's elastic solids are plane strain; this case is not")
par = inp.get("solver_params", {})
h_over_dx = float(par.get("h_over_dx", 1.3))
cfl = float(par.get("cfl", 0.2))

# The clamp: particles with both components held at zero for the whole run.
held = {}
for p in inp["prescribed_velocity"]:
    if p["value"] != 0 or p["until"] < inp["end_time"]:
        sys.exit("prescribed velocity {} on particle {} (until t = {}) is not a clamp: PySPH's "
                 "scheme has no prescribed motion; use the problem's Gaussian loading"
                 .format(p["value"], p["particle"], p["until"]))
    held.setdefault(p["particle"], set()).add(p["component"])
clamped = np.array([held.get(i, set()) == {0, 1} for i in range(n)])
clamp = par.get("clamp", "held")
if clamp not in ("held", "walls"):
    sys.exit(f"clamp = {clamp!r}: use held or walls")
wall = clamped if clamp == "walls" else np.zeros(n, dtype=bool)

# The spacing: mfv's particles are a lattice; the smallest gap between its columns.
gaps = np.diff(np.unique(np.round(X, 12)))
dx = float(np.min(gaps[gaps > 0]))
h = h_over_dx * dx

from pysph.base.kernels import CubicSpline  # noqa: E402
from pysph.solver.application import Application  # noqa: E402
from pysph.sph.equation import Equation, Group  # noqa: E402
from pysph.sph.solid_mech.basic import (ElasticSolidsScheme,  # noqa: E402
                                        get_particle_array_elastic_dynamics)

c_p = math.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))
times = [float(t) for t in inp["output_times"]]
# PySPH lands on an output time by shortening the step before it, which it decides after a
# step: a first output time shorter than the step would be stepped over.
dt = min(cfl * h / c_p, min(np.diff([0.0] + times)))
os.makedirs(os.path.join(case, "frames"))
index = open(os.path.join(case, "frames", "index.csv"), "w")
index.write("mfv-external-1\nk,time,steps\n")
energy = open(os.path.join(case, "frames", "energy.csv"), "w")
energy.write("mfv-external-1\ntime,kinetic,internal_work\n")
energy.write(f"0,{0.5 * float(np.sum(mass * (vx0 ** 2 + vy0 ** 2)))!r},0\n")
print(f"PySPH ElasticSolidsScheme: dx = {dx:.6g}, h = {h_over_dx} dx, dt = {dt:.6g} "
      f"({cfl} h / c_p, c_p = {c_p:.6g}), {n} particles, {int(clamped.sum())} clamped "
      f"(clamp = {clamp}), alpha = {par.get('alpha', 1.0)}, beta = {par.get('beta', 1.0)}, "
      f"artificial stress {par.get('eps', 0.3)}, XSPH {par.get('xsph', 0.5)}, "
      f"{len(times)} output times", flush=True)


class HoldClamp(Equation):
    """The clamp of clamp = "held": a held particle's accelerations, its XSPH velocity
    included, are zero at every stage of PySPH's predictor-corrector, so it never moves and
    its velocity stays 0 (mfv's prescribed zero velocity). It stays an elastic particle: its
    stress follows its neighbours' motion. Resetting it only after each step instead let it
    move within the step, and the stress that motion integrated stayed when its position was
    put back (measured: the plate at 9 through the thickness drifted up and never swung
    back)."""

    def loop(self, d_idx, d_mfv_held, d_au, d_av, d_ax, d_ay):
        if d_mfv_held[d_idx] > 0.5:
            d_au[d_idx] = 0.0
            d_av[d_idx] = 0.0
            d_ax[d_idx] = 0.0
            d_ay[d_idx] = 0.0


class HeldClampScheme(ElasticSolidsScheme):
    """PySPH's ElasticSolidsScheme, then HoldClamp on the held particles (clamp = "held")."""

    def get_equations(self):
        equations = super().get_equations()
        if clamp == "held" and clamped.any():
            equations.append(Group(equations=[HoldClamp(dest="solid", sources=None)]))
        return equations


class MfvCase(Application):
    def create_particles(self):
        kernel = CubicSpline(dim=2)
        wdeltap = kernel.kernel(rij=dx, h=h)
        arrays = []
        for name, sel in (("solid", ~wall), ("wall", wall)):
            if not sel.any():
                continue
            pa = get_particle_array_elastic_dynamics(
                x=X[sel], y=Y[sel], m=mass[sel], h=h, rho=rho, name=name,
                constants=dict(wdeltap=wdeltap, n=4, rho_ref=rho, E=E, nu=nu))
            # Held and wall particles start at rest (mfv's prescribed zero velocity).
            pa.u[:] = np.where(clamped[sel], 0.0, vx0[sel])
            pa.v[:] = np.where(clamped[sel], 0.0, vy0[sel])
            pa.add_property("mfv_id")
            pa.mfv_id[:] = ids[sel]
            pa.add_property("mfv_held")
            pa.mfv_held[:] = clamped[sel]
            # Not x0, y0: PySPH's predictor-corrector keeps its stage-start positions there.
            pa.add_property("mfv_x0")
            pa.add_property("mfv_y0")
            pa.mfv_x0[:] = X[sel]
            pa.mfv_y0[:] = Y[sel]
            arrays.append(pa)
        return arrays

    def create_scheme(self):
        s = HeldClampScheme(elastic_solids=["solid"],
                                solids=["wall"] if wall.any() else [], dim=2,
                                artificial_stress_eps=float(par.get("eps", 0.3)),
                                xsph_eps=float(par.get("xsph", 0.5)),
                                alpha=float(par.get("alpha", 1.0)),
                                beta=float(par.get("beta", 1.0)))
        s.configure_solver(dt=dt, tf=inp["end_time"], output_at_times=times,
                           pfreq=10 ** 9)
        return s

    def post_step(self, solver):
        # Called after the integrator's step and before the solver adds dt to t.
        # The work of the step's forces on the particles that move: PySPH's corrector moved
        # them by x - x0 under the accelerations au, av it left in the arrays.
        for pa in self.particles:
            if pa.name == "solid":
                free = pa.mfv_held < 0.5
                self.w_int -= float(np.sum(pa.m[free] * (pa.au[free] * (pa.x[free] - pa.x0[free]) +
                                                          pa.av[free] * (pa.y[free] - pa.y0[free]))))
        t = solver.t + solver.dt
        kinetic = sum(0.5 * float(np.sum(pa.m * (pa.u ** 2 + pa.v ** 2)))
                      for pa in self.particles if pa.name == "solid")
        energy.write(f"{t!r},{kinetic!r},{self.w_int!r}\n")
        while self.next < len(times) and abs(t - times[self.next]) <= 1e-9 * max(
                1.0, abs(times[self.next])):
            self.write_frame(self.next, solver)
            self.next += 1

    def write_frame(self, k, solver):
        with open(os.path.join(case, "frames", f"frame-{k}.csv"), "w") as out:
            out.write("id,ux,uy,vx,vy,sxx,syy,sxy\n")
            for pa in self.particles:
                for j in range(pa.get_number_of_particles()):
                    out.write("{:d},{!r},{!r},{!r},{!r},{!r},{!r},{!r}\n".format(
                        int(pa.mfv_id[j]), pa.x[j] - pa.mfv_x0[j], pa.y[j] - pa.mfv_y0[j], pa.u[j],
                        pa.v[j], pa.s00[j] - pa.p[j], pa.s11[j] - pa.p[j], pa.s01[j]))
        index.write(f"{k},{times[k]!r},{solver.count + 1}\n")
        index.flush()


app = MfvCase(fname="mfv", output_dir=os.path.join(case, "pysph"))
app.next = 0
app.w_int = 0.0
app.run(["--disable-output", "-q"])
index.close()
energy.close()
if app.next < len(times):
    sys.exit(f"PySPH stopped at t = {app.solver.t:.9g} before output time {times[app.next]!r}")
print(f"PySPH: {app.solver.count} steps to t = {app.solver.t:.9g}", flush=True)
