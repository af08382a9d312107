#!/usr/bin/env python3
"""Fuzz loop over the external-solver protocol mfv-external-1 (docs/external-solvers.md).

Each case writes a solver file `fz.toml` into a directory of its own ($MFV_SOLVERS) naming a
hostile adapter, and runs `mfv run rod-pulse -m external:fz -n 25` or `mfv verify` of a
one-case manifest with a band on the velocity error, with $TMPDIR a fresh directory (where
mfv makes the case directory), a marker in the environment (which every descendant of the
adapter inherits), a victim directory of the user's beside it, and a 6 GiB address-space
limit (RLIMIT_AS). The adapter (a Python script written at fuzz time) first runs the
repository's honest adapter, solvers/fem-rod/fem_rod.py, then breaks its output or itself:
  honest            nothing broken: must pass (exit 0)
  blowup            velocities of the frames from k on multiplied by 1e3 … 1e200, or growing
                    to 1e30: never a pass
  zeros             every displacement and velocity 0 (the energy account kept or dropped)
  wrong             valid output of wrong physics (velocities halved, the body stopped half
                    way, the frames one step late; no energy account): a verify must fail
  nonfinite         one field of one frame nan, inf, 1e400, empty, …: never a pass
  steps             index.csv's steps column negative, fractional, nan, inf, 1e18, 1e30
  garble            byte mutations of index.csv, a frame or energy.csv
  missing           index.csv, a frame, the frames directory or energy.csv removed or emptied
  special           a FIFO, /dev/zero, /dev/urandom, a directory or a link loop in place of an
                    output file, or of stdout.txt/stderr.txt
  longline          a line of 10^6 or 2·10^6 bytes, a number of 10^6 digits, 2·10^6 energy rows,
                    10^5 columns, 50 MB on stdout
  exit              a non-zero exit, or a signal, after writing good output; exit 0 writing
                    nothing
  timeout           sleeping past the solver file's timeout (ignoring SIGTERM or not)
  children          children that call setsid(), double-fork, ignore SIGTERM, exec sleep or
                    keep forking, and outlive the adapter
  outside           symbolic and hard links from the case directory to the user's files
Oracles: no signal, no exit code outside 0-3, no hang; never exit 0 for an output that is
broken, blown up, all zeros or not finite (nor a verify PASS for a run whose physics is
wrong); the honest adapter passes; no mfv-external-* or mfv-check-* directory left in
$TMPDIR and no process carrying the marker alive after mfv exits; the user's files untouched.

  scripts/fuzz_external.py --mfv build/release/apps/mfv --count 300 --seed 3
  scripts/fuzz_external.py --mfv build/release/apps/mfv --corpus   # the fixed CTest corpus
  scripts/fuzz_external.py --mfv build/release/apps/mfv --seed 3 --only 17   # one case
"""
import json
import os
import re
import shutil
import sys
import tempfile
import time
import uuid

from fuzz_common import (address_space_limit, arguments, changed, crash, digest, drive,
                         kill_all, only_option, preexec, processes_with, shown, spawn)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FEM_ROD = os.path.join(REPO, "solvers", "fem-rod", "fem_rod.py")

ADAPTER = r'''
"""A hostile mfv-external-1 adapter: fem_rod.py's honest output, then broken as argv says."""
import json, os, random, runpy, signal, subprocess, sys, time
mode, arg, case = sys.argv[1], sys.argv[2], sys.argv[3]
rng = random.Random(arg)
frames = os.path.join(case, "frames")


def honest():
    sys.argv = [os.environ["FUZZ_FEM_ROD"], case]
    g = runpy.run_path(sys.argv[0], run_name="__main__")
    if g.get("energy"):
        g["energy"].close()
    sys.argv = [__file__, mode, arg, case]


def frame_files():
    return sorted((f for f in os.listdir(frames) if f.startswith("frame-")),
                  key=lambda f: int(f[6:-4]))


def edit_frame(path, fn):
    """fn(header, row fields) -> row fields, for every row of a frame."""
    lines = open(path).read().splitlines()
    head = lines[0].split(",")
    out = [lines[0]] + [",".join(fn(head, r.split(","))) for r in lines[1:] if r]
    open(path, "w").write("\n".join(out) + "\n")


def scale(cols, factor):
    def fn(head, r):
        for c in cols:
            i = head.index(c) if c in head else None
            if i is not None:
                r[i] = repr(float(r[i]) * factor)
        return r
    return fn


if mode == "timeout":
    if arg.startswith("ignore"):
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
    time.sleep(120)
if mode == "exit" and arg == "nothing":
    sys.exit(0)
if mode == "children":
    kind = arg.split(":")[0]
    if os.fork() == 0:
        if kind != "pgroup":
            os.setsid()
        if kind == "double" and os.fork() != 0:
            os._exit(0)
        if kind == "ignore":
            signal.signal(signal.SIGTERM, signal.SIG_IGN)
        if kind == "exec":
            os.execvp("sleep", ["sleep", "120"])
        if kind == "forker":
            for _ in range(20):
                if os.fork() == 0:
                    os.setsid()
                    break  # each child sleeps; only the first one forks
                time.sleep(0.05)
        time.sleep(120)
        os._exit(0)
honest()
fs = frame_files()
if mode == "blowup":
    k0, factor = arg.split(":")[:2]
    k0 = int(k0) % len(fs)
    for k, f in enumerate(fs):
        if factor == "grow":
            fac = 10.0 ** (30 * (k + 1) / len(fs))
        else:
            fac = float(factor) if k >= k0 else 1.0
        if fac != 1.0:
            edit_frame(os.path.join(frames, f), scale(["vx", "vy"], fac))
elif mode == "wrong":
    what = arg.split(":")[0]
    for k, f in enumerate(fs):
        path = os.path.join(frames, f)
        if what == "half":
            edit_frame(path, scale(["vx", "vy"], 0.5))
        elif what == "late-zeros" and k >= len(fs) // 2:
            edit_frame(path, scale(["ux", "uy", "vx", "vy", "sxx", "syy", "sxy"], 0.0))
    if what == "shift":
        # Each frame holds the state a quarter of the run later (the last ones the final
        # state): wrong by far more than the band. A one-frame shift, as before, moved the
        # error at 2L/c by less than the band where the frames are dense, which is no fault.
        d = max(1, len(fs) // 4)
        texts = [open(os.path.join(frames, f)).read() for f in fs]
        for k, f in enumerate(fs):
            open(os.path.join(frames, f), "w").write(texts[min(k + d, len(fs) - 1)])
    os.remove(os.path.join(frames, "energy.csv"))
elif mode == "zeros":
    for f in fs:
        edit_frame(os.path.join(frames, f), scale(["ux", "uy", "vx", "vy", "sxx", "syy", "sxy"], 0.0))
    if arg.startswith("noenergy"):
        os.remove(os.path.join(frames, "energy.csv"))
elif mode == "nonfinite":
    value, col = arg.split(":")[:2]
    f = os.path.join(frames, rng.choice(fs))
    row = rng.randrange(1, len(open(f).read().splitlines()))
    lines = open(f).read().splitlines()
    head = lines[0].split(",")
    r = lines[row].split(",")
    r[head.index(col)] = value
    lines[row] = ",".join(r)
    open(f, "w").write("\n".join(lines) + "\n")
elif mode == "steps":
    ix = os.path.join(frames, "index.csv")
    lines = open(ix).read().splitlines()
    k = rng.randrange(2, len(lines))
    r = lines[k].split(",")
    r[2] = arg.split(":")[0]
    lines[k] = ",".join(r)
    open(ix, "w").write("\n".join(lines) + "\n")
elif mode == "garble":
    target = arg.split(":")[0]
    name = {"index": "index.csv", "energy": "energy.csv"}.get(target) or rng.choice(fs)
    path = os.path.join(frames, name)
    data = bytearray(open(path, "rb").read())
    for _ in range(rng.randint(1, 6)):
        op = rng.choice(["flip", "insert", "delete", "token", "truncate"])
        i = rng.randrange(len(data) + 1) if data else 0
        if op == "flip" and data:
            data[min(i, len(data) - 1)] ^= 1 << rng.randrange(8)
        elif op == "insert":
            data[i:i] = bytes([rng.randrange(256)])
        elif op == "delete":
            del data[i:i + rng.randint(1, 12)]
        elif op == "token":
            data[i:i + rng.randint(0, 4)] = rng.choice([b"nan", b"inf", b"-", b",", b"\n",
                                                        b"1e308", b"\x00", b"\r\n", b"mfv-external-1\n",
                                                        b"k,time\n", b"0,0,0\n"])
        elif op == "truncate":
            del data[i:]
    open(path, "wb").write(bytes(data))
elif mode == "missing":
    what = arg.split(":")[0]
    if what == "index":
        os.remove(os.path.join(frames, "index.csv"))
    elif what == "index-empty":
        open(os.path.join(frames, "index.csv"), "w").close()
    elif what == "index-protocol-only":
        open(os.path.join(frames, "index.csv"), "w").write("mfv-external-1\n")
    elif what == "index-wrong-protocol":
        open(os.path.join(frames, "index.csv"), "w").write("mfv-external-2\nk,time\n0,1\n")
    elif what == "frame":
        os.remove(os.path.join(frames, rng.choice(fs)))
    elif what == "frame-empty":
        open(os.path.join(frames, rng.choice(fs)), "w").close()
    elif what == "frame-header-only":
        f = os.path.join(frames, rng.choice(fs))
        open(f, "w").write(open(f).readline())
    elif what == "frames-dir":
        for f in os.listdir(frames):
            os.remove(os.path.join(frames, f))
        os.rmdir(frames)
    elif what == "energy":
        os.remove(os.path.join(frames, "energy.csv"))
    elif what == "energy-empty":
        open(os.path.join(frames, "energy.csv"), "w").close()
elif mode == "special":
    where, what = arg.split(":")[:2]
    name = {"index": "frames/index.csv", "energy": "frames/energy.csv",
            "frame": "frames/" + rng.choice(fs), "stdout": "stdout.txt",
            "stderr": "stderr.txt"}[where]
    path = os.path.join(case, name)
    os.remove(path)
    if what == "fifo":
        os.mkfifo(path)
    elif what == "dir":
        os.mkdir(path)
    elif what == "loop":
        os.symlink(path + ".b", path)
        os.symlink(path, path + ".b")
    else:
        os.symlink("/dev/" + what, path)
elif mode == "longline":
    what = arg.split(":")[0]
    if what in ("index-1e6", "index-2e6"):
        n = 10 ** 6 if what == "index-1e6" else 2 * 10 ** 6
        open(os.path.join(frames, "index.csv"), "a").write("9" * n + "\n")
    elif what == "digits":
        f = os.path.join(frames, rng.choice(fs))
        lines = open(f).read().splitlines()
        head = lines[0].split(",")
        r = lines[1].split(",")
        r[head.index("vx")] = rng.choice(["1" + "0" * 10 ** 6, "0." + "0" * 10 ** 6 + "1",
                                          "1" * (10 ** 6 - 10)])
        lines[1] = ",".join(r)
        open(f, "w").write("\n".join(lines) + "\n")
    elif what == "energy-rows":
        e = os.path.join(frames, "energy.csv")
        last = float(open(e).read().splitlines()[-1].split(",")[0])
        with open(e, "a") as out:
            for j in range(1, 2 * 10 ** 6):
                out.write(f"{last + j * 1e-6!r},0.1,0.1\n")
    elif what == "columns":
        f = os.path.join(frames, rng.choice(fs))
        lines = open(f).read().splitlines()
        pad = 10 ** 5
        lines = [lines[0] + "".join(f",c{j}" for j in range(pad))] + [
            r + ",0" * pad for r in lines[1:]]
        open(f, "w").write("\n".join(lines) + "\n")
    elif what == "stdout":
        chunk = "x" * 1023 + "\n"
        for _ in range(50 * 1024):
            sys.stdout.write(chunk)
        sys.stdout.flush()
    elif what == "blank-lines":
        open(os.path.join(frames, "index.csv"), "a").write("\n" * (5 * 10 ** 6))
elif mode == "exit":
    if arg.startswith("signal"):
        os.kill(os.getpid(), int(arg.split(":")[1]))
        time.sleep(5)
    sys.exit(int(arg.split(":")[0]))
elif mode == "outside":
    victim = os.environ["FUZZ_VICTIM"]
    what = arg.split(":")[0]
    if what == "frames-link":
        for f in os.listdir(frames):
            os.remove(os.path.join(frames, f))
        os.rmdir(frames)
        os.symlink(victim, frames)
    elif what == "links":
        os.symlink(victim, os.path.join(case, "victim-dir"))
        os.symlink(os.path.join(victim, "thesis.txt"), os.path.join(case, "thesis-link"))
        os.link(os.path.join(victim, "thesis.txt"), os.path.join(case, "thesis-hard"))
        os.symlink(victim, os.path.join(frames, "sub"))
    elif what == "energy-link":
        os.remove(os.path.join(frames, "energy.csv"))
        os.symlink(os.path.join(victim, "thesis.txt"), os.path.join(frames, "energy.csv"))
    elif what == "stdout-link":
        os.remove(os.path.join(case, "stdout.txt"))
        os.symlink(os.path.join(victim, "thesis.txt"), os.path.join(case, "stdout.txt"))
    elif what == "parent":
        open(os.path.join(os.path.dirname(case), "left-by-the-adapter.txt"), "w").write("x\n")
if mode == "children":
    time.sleep(0.3)  # the children have left the group before the adapter exits
'''

# Per mode: the arguments drawn and the outcome due for each ("fail": never exit 0; "pass":
# exit 0 (the honest physics); "any": exit 0-3 without a signal or hang; "wrong": the run's
# physics is wrong but its output valid: a `run` may exit 0, a verify must not pass).
MODES = {
    "honest": [("-", "pass")],
    "blowup": [(f"{k}:{f}", "fail") for k in (0, 3, 7, 99) for f in ("1e3", "1e6", "1e15", "1e30",
                                                                     "1e150", "1e200")]
              + [("0:grow", "fail")],
    "zeros": [("energy", "fail"), ("noenergy", "fail")],
    "wrong": [("half", "wrong"), ("late-zeros", "wrong"), ("shift", "wrong")],
    "nonfinite": [(f"{v}:{c}", "fail") for v in ("nan", "inf", "-inf", "NaN", "1e400", "-1e999",
                                                 "", "nan(123)", "infinity", "0x1p99999", "1e309")
                  for c in ("vx", "ux", "sxx")],
    "steps": [("-1", "fail"), ("-1e18", "fail"), ("3.5", "fail"), ("nan", "fail"),
              ("inf", "any"), ("1e18", "any"), ("1e30", "any"), ("9223372036854775807", "any"),
              ("0", "any"), ("abc", "fail"), ("", "fail")],
    "garble": [(f"{t}:{n}", "any") for t in ("index", "frame", "energy") for n in range(20)],
    "missing": [("index", "fail"), ("index-empty", "fail"), ("index-protocol-only", "fail"),
                ("index-wrong-protocol", "fail"), ("frame", "fail"), ("frame-empty", "fail"),
                ("frame-header-only", "fail"), ("frames-dir", "fail"), ("energy", "pass"),
                ("energy-empty", "fail")],
    "special": [(f"{w}:{k}", "fail" if w in ("index", "frame", "energy") else "pass")
                for w in ("index", "frame", "energy", "stdout", "stderr")
                for k in ("fifo", "zero", "urandom", "dir", "loop")],
    "longline": [("index-1e6", "fail"), ("index-2e6", "fail"), ("digits", "any"),
                 ("energy-rows", "any"), ("columns", "any"), ("stdout", "pass"),
                 ("blank-lines", "pass")],
    "exit": [(f"{c}", "fail") for c in (1, 2, 3, 42, 127, 255)]
            + [(f"signal:{s}", "fail") for s in (6, 9, 11, 15)] + [("nothing", "fail")],
    "timeout": [("sleep", "fail"), ("ignore-term", "fail")],
    "children": [(f"{k}:x", "pass") for k in ("setsid", "double", "ignore", "exec", "forker",
                                                "pgroup")],
    "outside": [("frames-link", "fail"), ("links", "pass"), ("energy-link", "fail"),
                ("stdout-link", "pass"), ("parent", "pass")],
}
KINDS = list(MODES)
MANIFEST = """[suite]
name = "fuzz-external"
[[case]]
id = "rod-pulse/external-fz"
problem = "rod-pulse"
method = "external:fz"
nodes = [{nodes}]
[case.bands]
l2_rel_finest = [0.0, {band}]
"""
SOLVER = """[solver]
description = "a hostile adapter of the fuzz loop ({mode} {arg})"
command = {command}
problems = ["rod-pulse"]
timeout = {timeout}
"""
NODES = 25


class Ctx:
    pass


def main():
    a = arguments(__doc__, "the fixed corpus of the CTest test: 26 cases, seed 45", 26, 45,
                  extra=only_option)
    ctx = Ctx()
    ctx.mfv, ctx.timeout = os.path.abspath(a.mfv), a.timeout
    a.mfv = ctx.mfv
    with tempfile.TemporaryDirectory(prefix="mfv-fuzz-external-") as w:
        ctx.adapter = os.path.join(w, "adapter.py")
        with open(ctx.adapter, "w") as f:
            f.write(ADAPTER)
        # The honest adapter's error sets the band: a verify of it passes, and of a run whose
        # physics is wrong (the body stopped, a velocity 1000x) fails.
        ctx.band = None
        p, *_ = run_case(ctx, w, "honest", "-", "run", a.timeout)
        m = p and re.search(r"^velocity error at 2L/c\s+([0-9.eE+-]+)", p.stdout, re.M)
        if not p or p.returncode != 0 or not m:
            print("fuzz_external: the honest adapter does not run:",
                  p and (p.stdout + p.stderr)[-3000:])
            return 1
        ctx.band = max(2 * float(m.group(1)), 1e-3)
        print(f"fuzz_external: the honest adapter's velocity error at 2L/c is {m.group(1)} at "
              f"{NODES} nodes; the manifest's band [0, {ctx.band:.3g}]", flush=True)

        def runner(kind, rng, i):
            arg, due = rng.choice(MODES[kind])
            how = rng.choice(["run", "run", "verify"])
            base = os.path.join(w, f"c{i}")
            os.makedirs(base)
            try:
                p, why, tried = run_case(ctx, base, kind, arg, how, a.timeout, due)
                return tried, p, why, None
            finally:
                shutil.rmtree(base, ignore_errors=True)
        return drive(a, KINDS, runner, "fuzz_external.py")


def run_case(ctx, base, mode, arg, how, timeout, due="pass"):
    solvers, tmp, victim = (os.path.join(base, n) for n in ("solvers", "tmp", "victim"))
    for d in (solvers, tmp, victim):
        os.makedirs(d, exist_ok=True)
    with open(os.path.join(victim, "thesis.txt"), "w") as f:
        f.write("the user's own file\n")
    os.makedirs(os.path.join(victim, "chapters"), exist_ok=True)
    with open(os.path.join(victim, "chapters", "1.txt"), "w") as f:
        f.write("chapter one\n")
    solver_timeout = 1.5 if mode == "timeout" else max(10, timeout - 5)
    command = json.dumps(["python3", ctx.adapter, mode, arg])
    with open(os.path.join(solvers, "fz.toml"), "w") as f:
        f.write(SOLVER.format(mode=mode, arg=arg[:40].replace('"', "'"), command=command,
                              timeout=solver_timeout))
    if how == "verify":
        m = os.path.join(base, "suite.toml")
        with open(m, "w") as f:
            f.write(MANIFEST.format(nodes=NODES, band=ctx.band))
        argv = ["verify", m, "--no-report", "--no-history"]
    else:
        argv = ["run", "rod-pulse", "-m", "external:fz", "-n", str(NODES)]
    marker = f"MFV_FUZZ_MARK_{uuid.uuid4().hex}"
    env = dict(os.environ, MFV_SOLVERS=solvers, TMPDIR=tmp, FUZZ_FEM_ROD=FEM_ROD,
               FUZZ_VICTIM=victim, OMP_NUM_THREADS="1")
    env[marker] = "1"
    before = digest(victim)
    t0 = time.time()
    p = spawn([ctx.mfv] + argv, base, timeout, env=env,
              preexec_fn=preexec(address_space_limit(6)))
    seconds = time.time() - t0
    alive = processes_with(marker)
    if alive:
        time.sleep(0.5)  # a process that was exiting at the first look is not a survivor
        alive = processes_with(marker)
    kill_all(alive)
    tried = f"adapter {mode} {arg[:60]!r}; mfv {shown(argv)} (took {seconds:.1f} s)"
    why = crash(p, timeout)
    if not why and p.returncode == 3:
        why = "exit 3 (singular) from an external run"
    if not why and alive:
        why = f"{len(alive)} process(es) of the adapter outlived mfv: {alive[:3]}"
    left = [n for n in os.listdir(tmp) if n.startswith(("mfv-external-", "mfv-check-"))]
    if not why and left:
        why = f"mfv left {left} in $TMPDIR"
    d = changed(before, digest(victim))
    if not why and d:
        why = f"the user's files changed: {d}"
    if not why and p.returncode == 0:
        if how == "verify" and "PASS" not in p.stdout:
            why = "verify exit 0 without a PASS"
        elif how == "run" and "velocity error" not in p.stdout:
            why = "run exit 0 without its errors"
        elif due == "fail":
            why = "exit 0 for a broken, blown-up, empty or non-finite output: a false pass"
        elif due == "wrong" and how == "verify":
            why = "verify passes a run whose physics is wrong"
        elif re.search(r"-\d{6,}|-9\.2\d*e\+18", p.stdout):
            why = "exit 0 printing a huge negative count (steps?)"
    if not why and due == "pass" and p.returncode != 0:
        why = f"exit {p.returncode} for an output that is valid (honest physics)"
    if not why and mode == "timeout" and seconds > solver_timeout + 5 + 10:
        why = f"a solver past its {solver_timeout} s timeout held mfv {seconds:.1f} s"
    if mode == "zeros" and not why and how == "run" and p.returncode == 0:
        why = "exit 0 for frames of zeros"
    return p, why, tried


if __name__ == "__main__":
    sys.exit(main())
