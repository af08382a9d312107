#!/usr/bin/python3
"""PySPH peer run of mfv's 2D dam break, for the particle-steps/s comparison of issue 16.

A water column of width a and height 2a stands on a dry floor against the left wall of an
open tank of length L = 4a (default). Weakly compressible SPH (PySPH's WCSPHScheme):
  Tait equation of state  p = B((rho/rho0)^gamma - 1),  B = c0^2 rho0 / gamma,
  rho0 = 1000 kg/m^3, gamma = 7, B = 4.704e5 Pa  =>  c0 = sqrt(gamma B / rho0) = 57.38 m/s,
  continuity equation for the density, Monaghan artificial viscosity alpha = 0.1 (beta = 0),
  XSPH (eps = 0.5, the scheme's built-in), gravity g = 9.81 m/s^2, cubic-spline kernel with
  h = hdx dx (hdx = 1.2: support 2.4 dx, mfv's default), fixed h.
Walls: PySPH's usual dynamic boundary particles (3 layers, their density from the continuity
equation and pressure from the Tait law with the Hughes-Graham correction), fixed in place.
Initial state: hydrostatic, p = rho0 g (2a - y) in the column (and in the wall particles
beside and below it), rho from the inverse Tait law; particle mass rho0 dx^2.
Time step: fixed, dt = cfl h / c0 with cfl = 0.25 (PEC predictor-corrector integrator: one
right-hand-side evaluation and one neighbour update per stage, two stages per step).

Timing: only Application.solve() (the time loop) is timed, wall and CPU (process) time; the
Cython compilation and the particle/neighbour setup happen in Application.setup() before it
and are reported separately as setup_seconds (it includes the compilation when the kernel
cache ~/.pysph/source is cold). Output files are disabled; the front is sampled in a
post-step hook every 0.1 of T = t sqrt(2 g / a) (a few numpy reductions per sample).

The last stdout line is one JSON object (see the README in bench/).
"""

import argparse
import json
import math
import os
import shutil
import sys
import tempfile
import time

RHO0 = 1000.0
GAMMA = 7.0
B_TAIT = 4.704e5
GRAVITY = 9.81
C0 = math.sqrt(GAMMA * B_TAIT / RHO0)


def _options(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--a", type=float, default=0.1, help="column width a [m] (height 2a)")
    p.add_argument("--dx", type=float, default=0.005, help="particle spacing [m]")
    p.add_argument("--tank-length", type=float, default=4.0,
                   help="tank length in units of a (right wall at x = L a)")
    p.add_argument("--hdx", type=float, default=1.2, help="h / dx (cubic-spline support 2h)")
    p.add_argument("--cfl", type=float, default=0.25, help="dt = cfl h / c0")
    p.add_argument("--alpha", type=float, default=0.1, help="artificial viscosity alpha")
    p.add_argument("--T-end", dest="T_end", type=float, default=3.0,
                   help="end time in T = t sqrt(2 g / a)")
    p.add_argument("--steps", type=int, default=0,
                   help="run exactly this many steps instead (0: run to --T-end)")
    p.add_argument("--threads", type=int, default=1,
                   help="OpenMP threads (1: PySPH's serial build, no OpenMP)")
    p.add_argument("--series", default="",
                   help="write the front and column-height history to this CSV file")
    o = p.parse_args(argv)
    for name in ("a", "dx", "tank_length", "hdx", "cfl", "T_end"):
        v = getattr(o, name)
        if not (math.isfinite(v) and v > 0):
            p.error(f"--{name.replace('_', '-')} must be a positive finite number, got {v}")
    if not 0 < o.alpha < 10:
        p.error(f"--alpha must be in (0, 10), got {o.alpha}")
    if o.steps < 0:
        p.error(f"--steps must be >= 0, got {o.steps}")
    if o.threads < 1:
        p.error(f"--threads must be >= 1, got {o.threads}")
    if o.tank_length < 1.5:
        p.error("--tank-length must be at least 1.5 (a, the column, plus a floor to flow on)")
    nx = round(o.a / o.dx)
    if nx < 4 or abs(nx * o.dx - o.a) > 1e-6 * o.a:
        p.error(f"--dx must divide --a into at least 4 spacings (a/dx = {o.a / o.dx:g})")
    if nx * round(2 * o.a / o.dx) > 2_000_000:
        p.error("more than 2e6 fluid particles: increase --dx")
    return o


# OpenMP reads OMP_NUM_THREADS when the compiled kernels load, so set it before PySPH loads.
OPT = _options(sys.argv[1:])
os.environ["OMP_NUM_THREADS"] = str(OPT.threads)

import numpy as np  # noqa: E402
import pysph  # noqa: E402
from pysph.base.kernels import CubicSpline  # noqa: E402
from pysph.base.utils import get_particle_array  # noqa: E402
from pysph.solver.application import Application  # noqa: E402
from pysph.sph.integrator import PECIntegrator  # noqa: E402
from pysph.sph.scheme import WCSPHScheme  # noqa: E402


def hydrostatic_density(depth):
    """Inverse Tait law for p = rho0 g depth (depth <= 0 gives rho0)."""
    p = RHO0 * GRAVITY * np.maximum(depth, 0.0)
    return RHO0 * (1.0 + p / B_TAIT) ** (1.0 / GAMMA)


class DamBreakPeer(Application):
    def initialize(self):
        o = OPT
        self.a, self.dx = o.a, o.dx
        self.h = o.hdx * o.dx
        self.dt = o.cfl * self.h / C0
        self.t_scale = math.sqrt(2.0 * GRAVITY / self.a)  # T = t * t_scale
        self.samples = []  # (T, Z, Zmax, H, all positions finite)
        self.next_sample = 0.1

    def create_scheme(self):
        return WCSPHScheme(
            ["fluid"], ["wall"], dim=2, rho0=RHO0, c0=C0, h0=OPT.hdx * OPT.dx,
            hdx=OPT.hdx, gamma=GAMMA, gy=-GRAVITY, alpha=OPT.alpha, beta=0.0,
            hg_correction=True, update_h=False,
        )

    def configure_scheme(self):
        # With --steps the end time is out of reach and PySPH's --max-steps (set in main) stops.
        tf = 1e30 if OPT.steps > 0 else OPT.T_end / self.t_scale
        self.scheme.configure_solver(
            kernel=CubicSpline(dim=2), integrator_cls=PECIntegrator,
            dt=self.dt, tf=tf, adaptive_timestep=False, n_damp=0, pfreq=2**62,
        )

    def create_particles(self):
        a, dx = self.a, self.dx
        nx, ny = round(a / dx), round(2 * a / dx)
        xf, yf = np.meshgrid((np.arange(nx) + 0.5) * dx, (np.arange(ny) + 0.5) * dx)
        xf, yf = xf.ravel(), yf.ravel()

        layers = math.ceil(2.0 * OPT.hdx)  # wall thickness covers the kernel support 2h
        length = OPT.tank_length * a
        nwx = round(length / dx)
        nwy = round(max(2.5 * a, 2 * a + 4 * dx) / dx)
        k = np.arange(layers)
        xs, ys = [], []
        floor_x = (np.arange(-layers, nwx + layers) + 0.5) * dx
        for j in k:  # floor, under the whole tank and both walls
            xs.append(floor_x)
            ys.append(np.full_like(floor_x, -(j + 0.5) * dx))
        side_y = (np.arange(nwy) + 0.5) * dx
        for j in k:  # left and right walls
            xs += [np.full_like(side_y, -(j + 0.5) * dx),
                   np.full_like(side_y, length + (j + 0.5) * dx)]
            ys += [side_y, side_y]
        xw, yw = np.concatenate(xs), np.concatenate(ys)

        rho_f = hydrostatic_density(2 * a - yf)
        # Wall particles that touch the column start at its hydrostatic pressure.
        wet = (xw < a) & (yw < 2 * a)
        rho_w = np.where(wet, hydrostatic_density(2 * a - yw), RHO0)

        m = RHO0 * dx * dx
        fluid = get_particle_array(name="fluid", x=xf, y=yf, m=m, rho=rho_f, h=self.h)
        wall = get_particle_array(name="wall", x=xw, y=yw, m=m, rho=rho_w, h=self.h)
        self.scheme.setup_properties([fluid, wall])
        self.n_fluid, self.n_wall = fluid.get_number_of_particles(), wall.get_number_of_particles()
        return [fluid, wall]

    def _sample(self, t):
        fluid = self.particles[0]
        x, y = fluid.x, fluid.y
        dx = self.dx
        near_floor = y < 2.0 * dx
        near_wall = x < 2.0 * dx
        z = (x[near_floor].max() + 0.5 * dx) / self.a if near_floor.any() else float("nan")
        z_all = (x.max() + 0.5 * dx) / self.a
        hgt = (y[near_wall].max() + 0.5 * dx) / (2 * self.a) if near_wall.any() else 0.0
        self.samples.append((t * self.t_scale, z, z_all, hgt,
                             bool(np.isfinite(x).all() and np.isfinite(y).all())))

    def post_step(self, solver):
        # PySPH calls this after the step but before it advances solver.t.
        t = solver.t + solver.dt
        if t * self.t_scale >= self.next_sample - 1e-12:
            self._sample(t)
            self.next_sample += 0.1


def front_at(samples, target):
    """The first sample at or after T = target (within one step of it)."""
    for s in samples:
        if s[0] >= target - 1e-9:
            return {"T": round(s[0], 5), "Z_over_a": round(s[1], 4),
                    "Zmax_over_a": round(s[2], 4), "H_over_2a": round(s[3], 4)}
    return None


def main():
    out = tempfile.mkdtemp(prefix="pysph_dam_break_")
    app = DamBreakPeer(fname="dam_break_peer", output_dir=out)
    argv = ["-d", out, "--disable-output", "-q"]
    # compyle's own --openmp flag (it resets the global config when the arguments are parsed).
    argv.append("--openmp" if OPT.threads > 1 else "--no-openmp")
    if OPT.steps > 0:
        argv += ["--max-steps", str(OPT.steps)]
    t0 = time.perf_counter()
    app.setup(argv)
    setup_s = time.perf_counter() - t0
    app._sample(0.0)

    wall0, cpu0 = time.perf_counter(), time.process_time()
    app.solve()
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    shutil.rmtree(out, ignore_errors=True)
    steps = app.solver.count
    if app.samples[-1][0] < app.solver.t * app.t_scale - 1e-9:
        app._sample(app.solver.t)

    if OPT.series:
        with open(OPT.series, "w") as f:
            f.write("# PySPH dam break: T = t sqrt(2g/a), Z = front/a (fluid within 2 dx of the "
                    "floor, + dx/2), Zmax = max x/a + dx/2a, H = column height at the left "
                    "wall / 2a\n")
            f.write(f"# a = {OPT.a} m, dx = {OPT.dx} m, hdx = {OPT.hdx}, cfl = {OPT.cfl}, "
                    f"alpha = {OPT.alpha}, c0 = {C0:.4f} m/s, dt = {app.dt:.6e} s\n")
            f.write("T,tau,Z_over_a,Zmax_over_a,H_over_2a\n")
            for s in app.samples:
                f.write(f"{s[0]:.5f},{s[0] / math.sqrt(2):.5f},{s[1]:.5f},{s[2]:.5f},{s[3]:.5f}\n")

    finite = all(s[4] for s in app.samples)
    result = {
        "peer": "pysph",
        "version": pysph.__version__,
        "package": "python3-pysph (Debian)",
        "scheme": "WCSPH (continuity density, Tait, alpha=%g, XSPH 0.5), CubicSpline hdx=%g, "
                  "PEC, dynamic wall particles" % (OPT.alpha, OPT.hdx),
        "a": OPT.a, "dx": OPT.dx, "h": app.h, "c0": round(C0, 4), "dt": app.dt,
        "particles": app.n_fluid, "wall_particles": app.n_wall,
        "steps": steps, "t_end": app.solver.t, "T_end": app.solver.t * app.t_scale,
        "setup_seconds": round(setup_s, 4),
        "wall_seconds": round(wall, 4), "cpu_seconds": round(cpu, 4),
        "particle_steps_per_s": app.n_fluid * steps / wall,
        "particle_steps_per_cpu_s": app.n_fluid * steps / cpu,
        "all_particle_steps_per_s": (app.n_fluid + app.n_wall) * steps / wall,
        "threads": OPT.threads, "nproc": os.cpu_count(), "finite": finite,
        "front": {str(T): front_at(app.samples, T) for T in (1, 2, 3)},
    }
    print(json.dumps(result))
    return 0 if finite else 1


if __name__ == "__main__":
    sys.exit(main())
