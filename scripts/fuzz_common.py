"""What the two fuzz loops (fuzz_cases.py, fuzz_manifest.py) share: running mfv with a
timeout, the outcomes that fail whatever the input (a hang, a signal, an exit code mfv never
gives), the command line and the closing tally."""
import argparse
import subprocess


def run(mfv, argv, cwd, timeout):
    """mfv's completed process, or None when it ran past `timeout` seconds."""
    try:
        return subprocess.run([mfv] + argv, capture_output=True, text=True, cwd=cwd,
                              timeout=timeout, errors="replace")
    except subprocess.TimeoutExpired:
        return None


def crash(p, timeout):
    """The reason an outcome fails whatever the input (a hang, a signal, an exit code other
    than mfv's 0-3), or None."""
    if p is None:
        return f"timeout after {timeout} s (hang)"
    if p.returncode < 0:
        return f"killed by signal {-p.returncode}: {p.stderr.strip()[-300:]}"
    if p.returncode not in (0, 1, 2, 3):
        return f"exit {p.returncode}: {p.stderr.strip()[-300:]}"
    return None


def arguments(doc, corpus_help, corpus_count, corpus_seed, extra=None):
    """--mfv, --count, --seed, --timeout and --corpus (the CTest test's fixed corpus);
    `extra(parser)` adds a loop's own options."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("--mfv", required=True)
    ap.add_argument("--count", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=None,
                    help="seconds before a case counts as a hang (default 60; 20 with --corpus)")
    ap.add_argument("--corpus", action="store_true", help=corpus_help)
    if extra:
        extra(ap)
    a = ap.parse_args()
    if a.corpus:
        a.count, a.seed = corpus_count, corpus_seed
    if a.timeout is None:
        a.timeout = 20 if a.corpus else 60
    return a


def tally(codes, p):
    """Counts the outcome of p (its exit code, or "timeout") in `codes`."""
    code = "timeout" if p is None else p.returncode
    codes[code] = codes.get(code, 0) + 1


def outcomes(codes):
    return "outcomes: " + ", ".join(f"exit {c}: {n}" for c, n in sorted(codes.items(), key=str))


# What the loops of issue 45 (fuzz_history.py, fuzz_plugins.py, fuzz_external.py, fuzz_diff.py)
# share besides the above: a process group killed whole on a timeout, a reproducible random
# stream per case, digests of the files a case must leave alone, processes that outlived mfv,
# resource limits, and a tally per class.
import hashlib
import os
import random
import signal
import stat
import time


def case_rng(seed, i):
    """The random stream of case i of a run with `seed`: the same whatever cases ran before,
    so that `--only i` reproduces one case."""
    return random.Random(f"{seed}:{i}")


def spawn(argv, cwd, timeout, env=None, preexec_fn=None, stdin=subprocess.DEVNULL):
    """argv's completed process (text output), or None when it ran past `timeout` seconds;
    it runs in a session of its own, and the whole process group is killed on a timeout."""
    p = subprocess.Popen(argv, cwd=cwd, env=env, stdin=stdin, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, errors="replace",
                         preexec_fn=preexec_fn, start_new_session=True)
    try:
        out, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except OSError:
            pass
        p.communicate()
        return None
    return subprocess.CompletedProcess(argv, p.returncode, out, err)


def digest(path):
    """What `path` is, without following symbolic links: its type and, for a regular file its
    bytes' SHA-256, for a link its target, for a directory each entry's digest (None: absent).
    Equal digests: the case left the path byte for byte as it was."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return None
    if stat.S_ISLNK(st.st_mode):
        return ("link", os.readlink(path))
    if stat.S_ISREG(st.st_mode):
        h = hashlib.sha256()
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        return ("file", st.st_size, h.hexdigest(), stat.S_IMODE(st.st_mode))
    if stat.S_ISDIR(st.st_mode):
        return ("dir", stat.S_IMODE(st.st_mode),
                tuple((n, digest(os.path.join(path, n))) for n in sorted(os.listdir(path))))
    return ("special", stat.S_IFMT(st.st_mode), stat.S_IMODE(st.st_mode))


def changed(before, after, path=""):
    """The first difference between two digests, as text ("" when equal)."""
    if before == after:
        return ""
    if before is None or after is None or before[0] != after[0] or before[0] != "dir":
        return f"{path or '.'}: {brief(before)} -> {brief(after)}"
    b, a = dict(before[2]), dict(after[2])
    for n in sorted(set(b) | set(a)):
        why = changed(b.get(n), a.get(n), os.path.join(path, n))
        if why:
            return why
    return f"{path or '.'}: mode {before[1]:o} -> {after[1]:o}"


def brief(d):
    if d is None:
        return "absent"
    if d[0] == "file":
        return f"file of {d[1]} bytes {d[2][:12]}"
    if d[0] == "dir":
        return f"directory of {len(d[2])} entries"
    return str(d[:2])


def processes_with(token):
    """The processes (pid, command line) whose environment holds `token`: a marker the loop
    put in mfv's environment, which every descendant inherits, setsid() or not."""
    out = []
    me = os.getpid()
    needle = token.encode()
    for name in os.listdir("/proc"):
        if not name.isdigit() or int(name) == me:
            continue
        try:
            with open(f"/proc/{name}/environ", "rb") as f:
                if needle not in f.read():
                    continue
            with open(f"/proc/{name}/stat") as f:
                if f.read().rsplit(")", 1)[-1].split()[0] == "Z":
                    continue  # a zombie is dead already; its parent reaps it
            with open(f"/proc/{name}/cmdline", "rb") as f:
                cmd = f.read().replace(b"\0", b" ").decode(errors="replace").strip()
        except OSError:
            continue
        out.append((int(name), cmd))
    return out


def kill_all(procs):
    for pid, _ in procs:
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass


def preexec(*steps):
    """A preexec_fn running each of `steps` (None ones skipped), or None."""
    steps = [s for s in steps if s]
    if not steps:
        return None

    def run_steps():
        for s in steps:
            s()
    return run_steps


def address_space_limit(gib):
    """A preexec step capping the child's address space at `gib` GiB (None under
    AddressSanitizer, whose shadow memory alone reserves terabytes)."""
    if "ASAN_OPTIONS" in os.environ:
        return None
    import resource
    cap = int(gib * (1 << 30))
    return lambda: resource.setrlimit(resource.RLIMIT_AS, (cap, cap))


def as_user(uid, gid):
    """A preexec step dropping root to uid/gid (so that file permissions apply to the child)."""
    def drop():
        os.setgroups([])
        os.setgid(gid)
        os.setuid(uid)
    return drop


class Tally:
    """Outcomes per class and kind: "exit 2", "timeout", "signal 9", and the failures."""

    def __init__(self):
        self.counts, self.failures, self.cases = {}, [], {}

    def add(self, cls, p, outcome=None):
        if outcome is None:
            outcome = ("timeout" if p is None else
                       f"signal {-p.returncode}" if p.returncode < 0 else f"exit {p.returncode}")
        c = self.counts.setdefault(cls, {})
        c[outcome] = c.get(outcome, 0) + 1

    def case(self, cls):
        self.cases[cls] = self.cases.get(cls, 0) + 1

    def fail(self, line):
        self.failures.append(line)
        print(line, flush=True)

    def print(self, script, count, seed, seconds):
        print(f"{script}: per class (cases: outcomes)")
        for cls in sorted(self.cases):
            outs = ", ".join(f"{o}: {n}" for o, n in sorted(self.counts.get(cls, {}).items()))
            bad = sum(1 for f in self.failures if f"[{cls}]" in f)
            print(f"  {cls}: {self.cases[cls]} case(s); {outs}"
                  + (f"; {bad} FAILURE(S)" if bad else ""))
        print(f"{script}: {sum(self.cases.values())} cases of {count} (seed {seed}) in "
              f"{seconds:.0f} s, {len(self.failures)} failure(s)")


def shown(argv, limit=400):
    """A command line as a shell would take it, long arguments cut."""
    import shlex
    text = " ".join(shlex.quote(a if len(a) < 200 else a[:60] + f"...({len(a)} chars)")
                    for a in argv)
    return text if len(text) <= limit else text[:limit] + " ..."


def only_option(ap):
    """--only N: run case N alone (as a failure line numbers it), with its own random stream."""
    ap.add_argument("--only", type=int, default=None,
                    help="run only case N of --seed (a failure line names it)")


def drive(a, kinds, runner, script):
    """Runs cases 0 … count−1 (or --only N): case i of kind kinds[i] for the first len(kinds),
    then a kind drawn from the case's own stream; runner(kind, rng, i) returns (what was
    tried, the process or None, the oracle failure or None, the outcome to tally or None for
    the exit code). Prints each failure reproducibly and the tally; returns the exit code."""
    t = Tally()
    t0 = time.time()
    for i in ([a.only] if a.only is not None else range(a.count)):
        rng = case_rng(a.seed, i)
        kind = kinds[i % len(kinds)] if i < len(kinds) else rng.choice(kinds)
        tried, p, why, outcome = runner(kind, rng, i)
        if tried is None:
            continue  # not possible here (a tool missing): not counted
        t.case(kind)
        t.add(kind, p, outcome)
        if why:
            out = "" if p is None else (p.stdout.strip()[-600:] + "\n" + p.stderr.strip()[-600:])
            t.fail(f"FAIL seed {a.seed} case {i} [{kind}]: {tried}\n     {why}\n"
                   f"     output: {out.strip()[-900:]!r}\n"
                   f"     reproduce: scripts/{script} --mfv {a.mfv} --seed {a.seed} --only {i}")
    t.print(script, a.count if a.only is None else 1, a.seed, time.time() - t0)
    return 1 if t.failures else 0
