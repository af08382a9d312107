#!/usr/bin/env python3
"""Fuzz loop over issue 26's classes: no false pass, no hang, no foreign file touched.

Classes (each case one mfv run, or two MPI ranks):
  above-critical  a transient run at safety in (1, 8] times the critical step it computes (rod
                  pulse with every 2D particle method, the compressed plate, the GRK bar) must
                  fail (exit 1) naming "the critical step"; never exit 0.
  petsc-files     a PETSc viewer, log, options-file or debugger option in petsc_options, from
                  the command line or a manifest, must be refused (exit 2) and the file it
                  names, a sentinel of the user's, stay as it was.
  special-files   a FIFO, a device, a directory or a file above 16 MiB as the manifest, the
                  baseline or the ledger must be refused (exit 2) within seconds.
  mpi-targets     under mpiexec -n 2, a report target of the user's must end both ranks with
                  exit 2 within seconds, the user's file untouched (skipped without mpiexec).
  support-size    a support parameter (dmax, radius, h, j) drawn up to 10^3 times its default on
                  a static problem must run within the timeout under a 6 GiB address-space limit
                  or be refused (exit 2) naming the support or the memory; never a signal, a
                  hang or an out-of-memory crash.
  load-scale      a linear transient run with its load or velocity scaled by 10^k: for |k| up
                  to 90 the relative errors must equal the unscaled run's (to 1e-6); beyond 100
                  the value must be refused (exit 2, "rescale it"); a denormal load must never
                  read as "unstable".
Any other outcome (exit 0 where a refusal or failure was due, a hang, a signal, an exit code
mfv never gives, a sentinel changed) is a failure.

  scripts/fuzz_honest.py --mfv build/release/apps/mfv --count 400 --seed 3
  scripts/fuzz_honest.py --mfv build/release/apps/mfv --corpus      # the CTest corpus
"""
import os
import random
import re
import shutil
import stat
import subprocess
import sys
import tempfile

from fuzz_common import arguments, crash, outcomes, run, tally

CLASSES = ["above-critical", "petsc-files", "special-files", "mpi-targets", "support-size",
           "load-scale"]
# Static cases whose support a parameter sets: (problem, method, nodes, parameter, default).
SUPPORTS = [("cantilever", "efg-ni", 21, "radius", 2.0), ("cantilever", "efg", 9, "dmax", 2.0),
            ("elastic-patch", "sph-galerkin", 21, "h", 1.5), ("elastic-patch", "rkpm", 21, "dmax", 2.0),
            ("laplace-tanh", "efg", 41, "dmax", 2.0), ("laplace-tanh", "rkpm", 41, "j", 1.0),
            ("cantilever", "kbm-si", 9, "dmax", 2.0)]
# Linear transient runs and the parameter that scales their response: (problem, method, nodes,
# parameter, its default, extra parameters, the powers of ten drawn, the smallest value the
# problem accepts). The rod pulse is linear at any scale; the GRK bar and the prestressed rod
# are finite-strain, so they are scaled down only, to the floor their messages state.
# The last entry is how closely the errors must agree: the finite-strain bars depart from their
# linear exact solutions by O(strain) (1.7e-4 at the GRK bar's default load moves its error by
# 0.5 %), so a scaled load changes their error at that order, not at round-off.
LOADS = [("rod-pulse", "sph", 13, "velocity", 1.0, "transits=1", (-90, 90), 1e-100, 1e-5),
         ("rod-pulse", "efg-ni", 13, "velocity", 1.0, "transits=1", (-90, 90), 1e-100, 1e-5),
         ("grk-bar", "fem", 11, "F0", 5000.0, "courant=0", (-12, 0), 0.3, 1e-2),
         ("prestressed-rod", "sph", 21, "v0", 40.0, "", (-9, 0), 2.0204e-5, 1e-2)]
# Cheap transient runs (problem, nodes, extra problem parameters) and their methods.
TRANSIENT = [("rod-pulse", 13, "transits=1"), ("rod-pulse", 25, "transits=1"),
             ("rod-pulse", 37, "transits=2"), ("compressed-plate", 7, "end_strain=0.005"),
             ("grk-bar", 11, "courant=0")]
ROD_METHODS = ["sph", "rlm", "kbm-si", "kbm-ni", "efg-ni", "efg-ci"]
PETSC_BAD = ["-ksp_monitor ascii:{f}", "-ksp_view ascii:{f}", "-ksp_view ascii:{f}::append",
             "-options_file {f}", "-options_file_yaml {f}", "-log_view ascii:{f}", "-log_view",
             "-info {f}", "-history {f}", "-mat_view binary:{f}", "-ksp_view_mat binary",
             "-vec_view hdf5:{f}", "-ksp_monitor draw", "-start_in_debugger",
             "-on_error_attach_debugger", "-ksp_type cg -ksp_monitor_true_residual ascii:{f}",
             "-sub_options_file {f}", "--options_file {f}", "-malloc_dump {f}",
             "-ksp_converged_reason ascii:{f}", "-pc_gamg_threshold 0.01 -log_trace {f}"]
SENTINEL = "a file of the user's\n"


def sentinel(path):
    with open(path, "w") as f:
        f.write(SENTINEL)


def unchanged(path):
    try:
        with open(path) as f:
            return f.read() == SENTINEL
    except OSError:
        return False


def manifest_text(extra_case="", suite="extra", baseline=None, ledger=None):
    s = f'[suite]\nname = "{suite}"\n'
    if baseline:
        s += f'baseline = "{baseline}"\n'
    if ledger:
        s += f'ledger = "{ledger}"\n'
    return s + ('[[case]]\nid = "lt"\nproblem = "laplace-tanh"\nmethod = "fem"\n'
                'nodes = [21, 41]\n' + extra_case)


def above_critical(rng, mfv, cwd, timeout):
    problem, n, extra = rng.choice(TRANSIENT)
    method = rng.choice(ROD_METHODS) if problem == "rod-pulse" else (
        "sph" if problem == "compressed-plate" else rng.choice(["fem", "rkpm"]))
    safety = round(rng.uniform(1.02, 8.0), 3)
    argv = ["run", problem, "-m", method, "-n", str(n), "--problem-params",
            f"{extra},frames=0,threads=1,safety={safety}"]
    if problem == "grk-bar":
        argv[-1] = f"frames=0,courant=0,safety={safety}"
    p = run(mfv, argv, cwd, timeout)
    why = crash(p, timeout)
    if why:
        return argv, p, why
    # The run divides its checkpoint interval into whole steps, so the step it takes may lie
    # below the one asked for: judge the ratio it reports ("(0.957 of the critical step").
    m = re.search(r"\(([0-9.]+) of the critical step", p.stdout)
    ratio = float(m.group(1)) if m else safety
    if p.returncode == 0 and ratio > 1:
        return argv, p, f"exit 0 at {ratio} × the critical step (a false pass)"
    if p.returncode == 1 and "critical step" not in p.stdout + p.stderr:
        return argv, p, "exit 1 without naming the critical step"
    return argv, p, None


def petsc_files(rng, mfv, cwd, timeout):
    victim = os.path.join(cwd, f"victim-{rng.randrange(1 << 30)}.txt")
    sentinel(victim)
    option = rng.choice(PETSC_BAD).format(f=victim)
    if rng.random() < 0.5:
        argv = ["run", "cantilever", "-m", rng.choice(["fem", "efg-ni"]), "-n", "3", "-p",
                f"solver=petsc,petsc_options={option}"]
    else:
        m = os.path.join(cwd, "petsc.toml")
        with open(m, "w") as f:
            f.write(manifest_text() .replace('method = "fem"\nnodes = [21, 41]\n',
                    'method = "fem"\nproblem_params = { solver = "petsc", '
                    f'petsc_options = "{option}" }}\nnodes = [21, 41]\n'))
        argv = ["verify", m, "--no-report"]
    p = run(mfv, argv, cwd, timeout)
    why = crash(p, timeout)
    if not why and p.returncode != 2:
        why = f"exit {p.returncode}, expected 2 (refused)"
    if not why and not unchanged(victim):
        why = f"the user's file {victim} was changed"
    if not why and not os.path.exists(victim):
        why = f"the user's file {victim} is gone"
    os.path.exists(victim) and os.remove(victim)
    return argv, p, why


def special_file(rng, cwd):
    kind = rng.choice(["fifo", "dev-zero", "dev-null", "directory", "huge", "socket-dir"])
    path = os.path.join(cwd, f"special-{kind}-{rng.randrange(1 << 30)}")
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "dev-zero":
        path = "/dev/zero"
    elif kind == "dev-null":
        path = "/dev/null"
    elif kind in ("directory", "socket-dir"):
        os.mkdir(path)
    else:
        with open(path, "wb") as f:
            f.seek(16 * 1024 * 1024)
            f.write(b"x")
    return kind, path


def special_files(rng, mfv, cwd, timeout):
    kind, path = special_file(rng, cwd)
    role = rng.choice(["manifest", "baseline", "ledger"])
    if role == "manifest":
        argv = ["verify", path, "--no-report"]
    else:
        m = os.path.join(cwd, f"m-{rng.randrange(1 << 30)}.toml")
        with open(m, "w") as f:
            f.write(manifest_text(baseline=path if role == "baseline" else None,
                                  ledger=path if role == "ledger" else None))
        argv = ["verify", m, "--no-report"]
    p = run(mfv, argv, cwd, min(timeout, 10))
    why = crash(p, min(timeout, 10))
    # Every one is refused as input: only regular files of at most 16 MiB are read.
    if not why and p.returncode != 2:
        why = f"{kind} as the {role}: exit {p.returncode}, expected 2 (refused)"
    if kind in ("fifo", "directory", "socket-dir", "huge") and os.path.exists(path):
        shutil.rmtree(path) if os.path.isdir(path) else os.remove(path)
    return argv, p, why


def mpi_targets(rng, mfv, cwd, timeout):
    mpiexec = shutil.which("mpiexec")
    if not mpiexec:
        return None, None, None
    target = os.path.join(cwd, f"mine-{rng.randrange(1 << 30)}")
    os.mkdir(target)
    sentinel(os.path.join(target, "thesis.txt"))
    sub = rng.choice([["study", "laplace-tanh", "-m", "fem", "-n", "5,9", "-p", "solver=petsc"],
                      ["verify", os.path.abspath("suites/default.toml"), "--case", "laplace-tanh/fem"],
                      ["compare", "laplace-tanh", "-m", "fem", "-m", "efg", "-n", "5,9"]])
    argv = sub + ["-r", target]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    try:
        p = subprocess.run([mpiexec, "-n", "2", "--oversubscribe", mfv] + argv, capture_output=True,
                           text=True, cwd=os.getcwd(), timeout=timeout, env=env, errors="replace")
    except subprocess.TimeoutExpired:
        p = None
    why = None
    if p is None:
        why = f"timeout after {timeout} s (a rank hung)"
    elif p.returncode != 2:
        why = f"exit {p.returncode}, expected 2 on every rank"
    elif not unchanged(os.path.join(target, "thesis.txt")):
        why = "the user's file was changed"
    shutil.rmtree(target, ignore_errors=True)
    return ["mpiexec -n 2"] + argv, p, why


def limited_memory():
    """The child's address space capped at 6 GiB: a dense system past it must be refused by
    the size check (which reads RLIMIT_AS), not crash."""
    import resource
    cap = 6 << 30
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))


def support_size(rng, mfv, cwd, timeout):
    problem, method, n, key, default = rng.choice(SUPPORTS)
    value = round(default * 10 ** rng.uniform(0, 3), 3)
    argv = ["run", problem, "-m", method, "-n", str(n), "-p", f"{key}={value}"]
    # Under AddressSanitizer (scripts/sanitize.sh sets ASAN_OPTIONS) the limit is left off: its
    # shadow memory alone reserves terabytes of address space, so any RLIMIT_AS aborts it.
    limit = None if "ASAN_OPTIONS" in os.environ else limited_memory
    try:
        p = subprocess.run([mfv] + argv, capture_output=True, text=True, cwd=cwd,
                           timeout=timeout, errors="replace", preexec_fn=limit,
                           env=dict(os.environ, OMP_NUM_THREADS="1"))
    except subprocess.TimeoutExpired:
        p = None
    why = crash(p, timeout)
    if not why and p.returncode == 2 and not re.search(
            r"support|memory|dense|dmax|radius|\bh\b|\bj\b|spacings|particles", p.stderr):
        why = f"refused without naming the support or the memory: {p.stderr.strip()[-200:]}"
    return argv, p, why


def scaled_errors(p):
    """The run's relative errors (the lines "... relative <number>"), in order."""
    return [float(x) for x in re.findall(r"relative\s+([-+0-9.eE]+)", p.stdout)]


def load_scale(rng, mfv, cwd, timeout):
    problem, method, n, key, default, extra, (k_lo, k_hi), floor, tol = rng.choice(LOADS)
    k = rng.choice([rng.randint(k_lo, k_hi), rng.choice([-320, -300, -150, -101, 101, 150, 300])])
    value = default * 10.0 ** k
    base = f"{extra + ',' if extra else ''}frames=0,threads=1"
    argv = ["run", problem, "-m", method, "-n", str(n), "--problem-params",
            f"{base},{key}={value:.6g}"]
    p = run(mfv, argv, cwd, timeout)
    why = crash(p, timeout)
    if why:
        return argv, p, why
    if abs(value) > 1e100 or abs(value) < floor:
        if p.returncode != 2 or "rescale it" not in p.stderr:
            why = f"{key} = {value:.3g}: exit {p.returncode}, expected 2 with \"rescale it\""
        return argv, p, why
    ref = run(mfv, ["run", problem, "-m", method, "-n", str(n), "--problem-params", base], cwd,
              timeout)
    if ref is None or ref.returncode != p.returncode:
        return argv, p, (f"{key} scaled by 1e{k}: exit {p.returncode}, the unscaled run "
                         f"{None if ref is None else ref.returncode}")
    a, b = scaled_errors(p), scaled_errors(ref)
    if len(a) != len(b) or any(abs(x - y) > tol * max(abs(y), 1e-300) for x, y in zip(a, b)):
        why = f"{key} scaled by 1e{k}: relative errors {a[:3]} against {b[:3]} unscaled"
    return argv, p, why


def main():
    a = arguments(__doc__, "the fixed corpus of the CTest test: 48 cases, seed 26, 20 s each",
                  48, 26)
    a.mfv = os.path.abspath(a.mfv)
    rng = random.Random(a.seed)
    runners = {"above-critical": above_critical, "petsc-files": petsc_files,
               "special-files": special_files, "mpi-targets": mpi_targets,
               "support-size": support_size, "load-scale": load_scale}
    failures, codes, per_class = [], {}, {c: [0, 0] for c in CLASSES}
    with tempfile.TemporaryDirectory(prefix="mfv-fuzz-honest-") as cwd:
        for i in range(a.count):
            cls = CLASSES[i % len(CLASSES)] if i < len(CLASSES) else rng.choice(CLASSES)
            argv, p, why = runners[cls](rng, a.mfv, cwd, a.timeout)
            if argv is None:
                continue
            per_class[cls][0] += 1
            tally(codes, p)
            if why:
                per_class[cls][1] += 1
                failures.append((cls, argv, why))
                print(f"FAIL {i} [{cls}]: mfv {' '.join(argv)}\n     {why}", flush=True)
    print(outcomes(codes))
    for c, (n, f) in per_class.items():
        print(f"  {c}: {n} case(s), {f} failure(s)")
    print(f"fuzz_honest: {sum(n for n, _ in per_class.values())} cases (seed {a.seed}), "
          f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
