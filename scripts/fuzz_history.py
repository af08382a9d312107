#!/usr/bin/env python3
"""Fuzz loop over the SQLite run history (`mfv verify --history FILE`, `mfv history`).

A one-case suite (linear FEM on laplace-tanh at 21 and 41 nodes) is verified twice into a
template history; each case then puts something hostile where the history is and runs
`mfv verify <suite> --history H --junit J` (with a report `-r R` or `--no-report`) or
`mfv history --history H [subject]`. Kinds:
  zero-length, one-byte, small-garbage, garbage, text  not SQLite at all
  truncated, flipped                the template cut at a random byte, or bytes flipped
  foreign-tables, foreign-empty     someone else's SQLite database (other tables, any
                                    user_version: 0, negative, 1, newer), or one without tables
  foreign-wal, foreign-hot-journal  a foreign database with a non-empty -wal, or a hot
                                    journal left by a writer that crashed
  history-wal, history-hot-journal  mfv's own history in WAL mode, or after a crashed writer
  newer-schema                      the template with a user_version above mfv's
  directory, fifo, dev-node         not a regular file
  symlink-dangling, symlink-loop, symlink-to-history, symlink-to-foreign
  missing-dir, parent-is-file       no directory to create the file in
  readonly-file, readonly-dir, readonly-dir-absent   permissions (as user nobody when root)
  inside-report                     the history inside the report directory (also through a
                                    symbolic link, `..` or the report directory itself)
  locked-short, locked-long, locked-late   another process holds a write transaction
  two-writers                       two mfv verify runs append to one history at once
  sigkill                           mfv killed (SIGKILL) at a random moment or during the
                                    append; then `mfv history` and another verify must work
  history-cmd                       `mfv history` on any of the above
Oracles: no signal, no exit code outside 0-3, no hang; exit 0 only with the run appended
(one more run in a valid history); a refusal (exit 2) leaves the history's directory byte for
byte as it was, names the history and comes before any case runs (no report, no JUnit); a
late refusal (exit 1, "not appended to the history") leaves the file as it was and the report
and JUnit written; `mfv history` never changes anything; after a SIGKILL the history is
still valid with the run either in it or not, and the next run appends and removes the
killed run's staging directory.

  scripts/fuzz_history.py --mfv build/release/apps/mfv --count 300 --seed 3
  scripts/fuzz_history.py --mfv build/release/apps/mfv --corpus   # the fixed CTest corpus
  scripts/fuzz_history.py --mfv build/release/apps/mfv --seed 3 --only 17   # one case
"""
import os
import pwd
import shutil
import signal
import sqlite3
import subprocess
import sys
import tempfile
import time
import urllib.parse

from fuzz_common import (arguments, as_user, changed, crash, digest, drive, only_option,
                         preexec, shown, spawn)

MANIFEST = """[suite]
name = "fuzz-history"
description = "one fast case for the history fuzz loop"
drift_tolerance = 0.05

[[case]]
id = "lt/fem"
problem = "laplace-tanh"
method = "fem"
nodes = [21, 41]
problem_params = { s = 2.0 }
[case.bands]
l2_rate = [1.5, 2.5]
"""
CASE_ID = "lt/fem"
FILE_KINDS = ["zero-length", "one-byte", "small-garbage", "garbage", "text", "truncated",
              "flipped", "foreign-tables", "foreign-empty", "foreign-wal", "foreign-hot-journal",
              "history-wal", "history-hot-journal", "newer-schema", "directory", "fifo",
              "dev-node", "symlink-dangling", "symlink-loop", "symlink-to-history",
              "symlink-to-foreign", "missing-dir", "parent-is-file"]
KINDS = FILE_KINDS + ["readonly-file", "readonly-dir", "readonly-dir-absent", "inside-report",
                      "locked-short", "locked-long", "locked-late", "two-writers", "sigkill",
                      "history-cmd"]
# Kinds after which a valid history with one more run is the only right outcome.
MUST_APPEND = {"history-wal", "history-hot-journal", "symlink-to-history", "two-writers"}
# Kinds that must be refused (exit 2) before any case runs.
MUST_REFUSE = {"zero-length", "one-byte", "small-garbage", "garbage", "text", "foreign-tables",
               "foreign-empty", "foreign-wal", "foreign-hot-journal", "newer-schema",
               "directory", "fifo", "dev-node", "symlink-loop", "symlink-to-foreign",
               "missing-dir", "parent-is-file", "readonly-file", "readonly-dir-absent",
               "inside-report", "locked-long"}
SUBJECTS = [[], [CASE_ID], [CASE_ID + "/L2 rate (least squares)"], ["lt/fem/no such quantity"],
            ["no/such/case"], [""], ["lt"], [CASE_ID, "L2 rate (least squares)"],
            ["--last", "1"], ["--last", "1000000"], [CASE_ID, "--last", "2"], ["'; DROP TABLE runs; --"],
            ["x" * 5000], ["lt/fem/%"], ["lt/fem/L2 relative error at 41 nodes"]]
TEXTS = [b"[suite]\nname = \"mine\"\n", b"id,value\n1,2\n", b"SQLite format 3\x00",
         b"SQLite format 3\x00" + b"\x10\x00\x01\x01\x00\x40\x20\x20" + b"\x00" * 80,
         b"my thesis, chapter 1\n" * 400, "ünïcödé\n".encode() * 100]


class Ctx:
    pass


def history_state(path):
    """("ok", runs) when `path` is a history as mfv writes one (SQLite, user_version 1, the
    runs table, quick_check ok), else ("bad", why). Read only."""
    if not os.path.isfile(path):
        return ("bad", "not a regular file")
    try:
        c = sqlite3.connect(f"file:{urllib.parse.quote(path)}?mode=ro", uri=True, timeout=1)
        try:
            v = c.execute("PRAGMA user_version").fetchone()[0]
            if v != 1:
                return ("bad", f"user_version {v}")
            q = c.execute("PRAGMA quick_check").fetchone()[0]
            if q != "ok":
                return ("bad", f"quick_check: {q[:100]}")
            return ("ok", c.execute("SELECT count(*) FROM runs").fetchone()[0])
        finally:
            c.close()
    except sqlite3.Error as e:
        return ("bad", str(e))


def write(path, data):
    with open(path, "wb") as f:
        f.write(data)


def foreign_db(path, rng, version=None, tables=True, wal=False):
    c = sqlite3.connect(path, isolation_level=None)
    if wal:
        c.execute("PRAGMA journal_mode=WAL")
    if not tables:
        # A database file without tables (a page of header): made by a table dropped again.
        c.execute("CREATE TABLE t(x)")
        c.execute("DROP TABLE t")
    else:
        c.execute(rng.choice(["CREATE TABLE notes(id INTEGER PRIMARY KEY, text TEXT)",
                              "CREATE TABLE runs(id INTEGER PRIMARY KEY, mine TEXT)",
                              "CREATE TABLE runs(id, generated_utc, suite)",
                              "CREATE TABLE quantities(x); CREATE TABLE vals(y)"]
                             ).split(";")[0])
        c.execute("CREATE TABLE IF NOT EXISTS stuff(k TEXT, v BLOB)")
        for k in range(rng.randint(1, 200)):
            c.execute("INSERT INTO stuff VALUES(?, ?)", (f"key{k}", os.urandom(rng.randint(0, 300))))
    if version is not None:
        c.execute(f"PRAGMA user_version = {version}")
    c.close()


CRASHED_WRITER = r"""
import os, sqlite3, sys
path, mode, table = sys.argv[1], sys.argv[2], sys.argv[3]
c = sqlite3.connect(path, isolation_level=None)
c.execute("PRAGMA cache_size = 2")  # small: the writes spill into the file before a commit
if mode == "wal":
    c.execute("PRAGMA journal_mode=WAL")
    c.execute("PRAGMA wal_autocheckpoint = 0")
    c.execute("CREATE TABLE IF NOT EXISTS later(v BLOB)")
    c.execute("INSERT INTO later VALUES(randomblob(20000))")
    os._exit(0)  # committed in the -wal, never checkpointed: the -wal stays beside the file
c.execute("BEGIN IMMEDIATE")
if table == "runs":
    for k in range(400):
        c.execute("INSERT INTO runs(generated_utc, suite, manifest, full, commit_id, dirty, status, "
                  "failed, cases, provenance) VALUES('x', 'crashed', 'm', 0, 'c', 0, 'PASS', 0, 1, "
                  "hex(randomblob(400)))")
else:
    c.execute("CREATE TABLE IF NOT EXISTS later(v BLOB)")
    for k in range(400):
        c.execute("INSERT INTO later VALUES(randomblob(1000))")
os._exit(0)  # in the middle of the transaction: a hot journal
"""


def crashed_writer(ctx, path, mode, table):
    subprocess.run([sys.executable, "-c", CRASHED_WRITER, path, mode, table], check=True,
                   timeout=60)


def make_history(ctx, rng, kind, h):
    """Puts kind's file at h/history.sqlite (or elsewhere); returns (the path given to mfv,
    what was done, the runs it holds when it is a history mfv may append to, else None)."""
    H = os.path.join(h, "history.sqlite")
    tmpl = ctx.template
    size = len(tmpl)
    if kind == "zero-length":
        write(H, b"")
        return H, "an empty file", None
    if kind == "one-byte":
        b = bytes([rng.randrange(256)])
        write(H, b)
        return H, f"one byte {b!r}", None
    if kind == "small-garbage":
        n = rng.randint(2, 600)
        write(H, os.urandom(n))
        return H, f"{n} random bytes", None
    if kind == "garbage":
        n = rng.randint(512, 65536)
        head = rng.choice([b"", b"SQLite format 3\x00", tmpl[:100], tmpl[:4096]])
        write(H, head + os.urandom(n))
        return H, f"{len(head)} header bytes + {n} random bytes", None
    if kind == "text":
        t = rng.choice(TEXTS)
        write(H, t)
        return H, f"a text file of {len(t)} bytes ({t[:20]!r}...)", None
    if kind == "truncated":
        cut = rng.choice([rng.randrange(1, size), 4096 * rng.randrange(1, size // 4096 + 1) - 1,
                          4096 * rng.randrange(1, max(2, size // 4096)), 100, 512, 511])
        cut = max(1, min(cut, size - 1))
        write(H, tmpl[:cut])
        return H, f"the template history cut at byte {cut} of {size}", None
    if kind == "flipped":
        data = bytearray(tmpl)
        where = rng.choice(["header", "anywhere", "page1"])
        flips = []
        for _ in range(rng.randint(1, 8)):
            i = rng.randrange(100 if where == "header" else 4096 if where == "page1" else size)
            bit = rng.randrange(8)
            data[i] ^= 1 << bit
            flips.append((i, bit))
        write(H, bytes(data))
        return H, f"the template with bits flipped at (byte, bit) {flips}", ctx.runs
    if kind == "foreign-tables":
        v = rng.choice([0, 0, -1, -2147483648, 1, 2, 99, 2147483647])
        foreign_db(H, rng, v)
        # user_version 1 is mfv's by the documented rule (verify/history.hpp): refused when
        # the append fails, after the run (exit 1), or before it.
        ctx.expect = None if v == 1 else 2
        return H, f"someone else's SQLite database with tables, user_version {v}", None
    if kind == "foreign-empty":
        v = rng.choice([0, -7, 2, 1])
        foreign_db(H, rng, v, tables=False)
        ctx.expect = None if v == 1 else 2
        return H, f"a SQLite database without tables, user_version {v}", None
    if kind == "foreign-wal":
        foreign_db(H, rng, rng.choice([0, 5]), wal=True)
        crashed_writer(ctx, H, "wal", "later")
        return H, "someone else's WAL database with a non-empty -wal beside it", None
    if kind == "foreign-hot-journal":
        foreign_db(H, rng, rng.choice([0, 3]))
        crashed_writer(ctx, H, "journal", "later")
        return H, "someone else's database with a hot journal (a writer crashed)", None
    if kind == "history-wal":
        write(H, tmpl)
        c = sqlite3.connect(H, isolation_level=None)
        c.execute("PRAGMA journal_mode=WAL")
        c.close()
        return H, "the template history switched to WAL mode", ctx.runs
    if kind == "history-hot-journal":
        write(H, tmpl)
        crashed_writer(ctx, H, "journal", "runs")
        return H, "the template history with a hot journal (a writer crashed mid-append)", ctx.runs
    if kind == "newer-schema":
        write(H, tmpl)
        v = rng.choice([2, 3, 1000, 2147483647])
        c = sqlite3.connect(H, isolation_level=None)
        c.execute(f"PRAGMA user_version = {v}")
        c.close()
        return H, f"the template history with user_version {v}", None
    if kind == "directory":
        os.mkdir(H)
        if rng.random() < 0.5:
            write(os.path.join(H, "keep.txt"), b"mine\n")
        return H, "a directory", None
    if kind == "fifo":
        os.mkfifo(H)
        return H, "a FIFO (no writer)", None
    if kind == "dev-node":
        dev = rng.choice(["/dev/null", "/dev/zero", "/dev/urandom"])
        os.symlink(dev, H)
        return H, f"a symbolic link to {dev}", None
    if kind == "symlink-dangling":
        target = rng.choice(["gone.sqlite", os.path.join(h, "sub-gone", "x.sqlite")])
        os.symlink(target, H)
        return H, f"a dangling symbolic link to {target}", None
    if kind == "symlink-loop":
        other = os.path.join(h, "other.sqlite")
        os.symlink(H, other)
        os.symlink(other, H)
        return H, "a loop of two symbolic links", None
    if kind == "symlink-to-history":
        target = os.path.join(h, "real.sqlite")
        write(target, tmpl)
        os.symlink("real.sqlite", H)
        return H, "a symbolic link to a copy of the template history", ctx.runs
    if kind == "symlink-to-foreign":
        target = os.path.join(h, "thesis.sqlite")
        if rng.random() < 0.5:
            foreign_db(target, rng, 0)
        else:
            write(target, rng.choice(TEXTS))
        os.symlink("thesis.sqlite", H)
        return H, "a symbolic link to someone else's file", None
    if kind == "missing-dir":
        return os.path.join(h, "no", "such", "dir", "history.sqlite"), "a path in no directory", None
    if kind == "parent-is-file":
        write(os.path.join(h, "plain"), b"a file\n")
        return os.path.join(h, "plain", "history.sqlite"), "a path under a regular file", None
    raise ValueError(kind)


def verify_argv(ctx, H, out, report):
    argv = ["verify", ctx.manifest, "--history", H, "--junit", os.path.join(out, "junit.xml")]
    return argv + (["-r", os.path.join(out, "report")] if report else ["--no-report"])


def judge_verify(ctx, kind, p, H, h_before, h, out, report, runs_before, expect=None):
    """The oracle of a verify run (None: fine)."""
    why = crash(p, ctx.timeout)
    if why:
        return why
    if p.returncode == 3:
        return "exit 3 (singular) from a history problem"
    text = p.stdout + p.stderr
    junit = os.path.join(out, "junit.xml")
    rep = os.path.join(out, "report")
    leftovers = [n for n in os.listdir(h) if n.endswith(("-journal", "-wal", "-shm"))
                 and not any(n == e for e in ctx.names_before)]
    if p.returncode == 0:
        if expect == 2:
            return "exit 0, expected a refusal (exit 2)"
        target = os.path.realpath(H)
        st = history_state(target)
        want = (runs_before or 0) + 1
        if st != ("ok", want):
            return (f"exit 0 but the history is {st}, expected a valid history with {want} "
                    f"run(s): a false PASS")
        if "appended to" not in p.stdout:
            return "exit 0 without 'history: run N appended'"
        if not os.path.isfile(junit) or (report and not os.path.isfile(os.path.join(rep, "index.md"))):
            return "exit 0 without the JUnit file or the report"
        if leftovers and kind not in ("history-wal", "foreign-wal"):
            return f"exit 0 leaving {leftovers} beside the history"
        return None
    if expect == 0:
        return f"exit {p.returncode}, expected 0 (the history appended)"
    if p.returncode == 2:
        d = changed(h_before, digest(h))
        if d:
            return f"refused (exit 2), but the history's directory changed: {d}"
        names = [H, os.path.basename(H)]
        if not any(n in p.stderr for n in names):
            return "refused (exit 2) without naming the history"
        if os.listdir(out):
            return f"refused (exit 2), but left {sorted(os.listdir(out))} in the output directory"
        if CASE_ID in p.stdout:
            return "refused (exit 2) after running the case"
        return None
    if p.returncode == 1:
        if expect == 2:
            return "exit 1, expected a refusal before the case (exit 2)"
        if "not appended to the history" not in text:
            return "exit 1 that is not the history's (the case passes)"
        d = changed(h_before, digest(h))
        if d:
            return f"not appended (exit 1), but the history's directory changed: {d}"
        if not os.path.isfile(junit):
            return "not appended (exit 1) and the JUnit file not written"
        if report and not os.path.isfile(os.path.join(rep, "results.json")):
            return "not appended (exit 1) and the report not written: a lost run"
        return None
    return f"exit {p.returncode}"


def nobody_ids():
    try:
        pw = pwd.getpwnam("nobody")
        return pw.pw_uid, pw.pw_gid
    except KeyError:
        return None


def run_mfv(ctx, argv, cwd, user=None, timeout=None):
    env = dict(os.environ, OMP_NUM_THREADS="1", HOME=cwd)
    pre = as_user(*user) if user else None
    return spawn([ctx.mfv] + argv, cwd, timeout or ctx.timeout, env=env, preexec_fn=preexec(pre))


def file_case(ctx, kind, rng, i, base):
    h, out = os.path.join(base, "h"), os.path.join(base, "out")
    os.makedirs(h)
    os.makedirs(out)
    ctx.expect = 0 if kind in MUST_APPEND else 2 if kind in MUST_REFUSE else None
    H, what, runs = make_history(ctx, rng, kind, h)
    expect = ctx.expect
    ctx.names_before = os.listdir(h)
    report = rng.random() < 0.5
    argv = verify_argv(ctx, H, out, report)
    before = digest(h)
    p = run_mfv(ctx, argv, out)
    why = judge_verify(ctx, kind, p, H, before, h, out, report, runs, expect)
    return f"history = {what}; mfv {shown(argv)}", p, why, None


def readonly_case(ctx, kind, rng, i, base):
    h, out = os.path.join(base, "h"), os.path.join(base, "out")
    os.makedirs(h)
    os.makedirs(out)
    user = None
    if os.geteuid() == 0:
        user = nobody_ids()
        if user is None:
            return None, None, None, None
        os.chmod(base, 0o755)
        os.chown(out, *user)
    H = os.path.join(h, "history.sqlite")
    runs = None
    if kind == "readonly-file":
        write(H, ctx.template)
        os.chmod(H, 0o444)
        runs = ctx.runs
        what = "the template history, read-only"
    elif kind == "readonly-dir":
        write(H, ctx.template)
        if user:
            os.chown(H, *user)
        os.chmod(H, 0o644)
        runs = ctx.runs
        what = "the template history, writable, in a read-only directory"
    else:
        what = "no file, in a read-only directory"
    os.chmod(h, 0o555)
    ctx.names_before = os.listdir(h)
    report = rng.random() < 0.5
    argv = verify_argv(ctx, H, out, report)
    before = digest(h)
    p = run_mfv(ctx, argv, out, user)
    expect = 2 if kind in MUST_REFUSE else None
    # Judged with the directory's mode as the case left it (the digest holds the mode).
    why = judge_verify(ctx, kind, p, H, before, h, out, report, runs, expect)
    os.chmod(h, 0o755)
    who = " as nobody" if user else ""
    return f"history = {what}; mfv {shown(argv)}{who}", p, why, None


def inside_report_case(ctx, kind, rng, i, base):
    out = os.path.join(base, "out")
    os.makedirs(out)
    rep = os.path.join(out, "report")
    shutil.copytree(ctx.pristine_report, rep, symlinks=True)
    link = os.path.join(out, "link.sqlite")
    choice = rng.choice(["file", "sub", "dir", "index", "link", "dotdot", "dot", "trailing"])
    H = {"file": os.path.join(rep, "history.sqlite"),
         "sub": os.path.join(rep, "problems", "history.sqlite"),
         "dir": rep, "index": os.path.join(rep, "index.md"), "link": link,
         "dotdot": os.path.join(rep, "..", "report", "history.sqlite"),
         "dot": os.path.join(rep, ".", "h.sqlite"), "trailing": rep + "/"}[choice]
    if choice == "link":
        os.symlink(os.path.join(rep, "x.sqlite"), link)
    argv = ["verify", ctx.manifest, "-r", rep + ("/" if rng.random() < 0.3 else ""),
            "--history", H, "--junit", os.path.join(out, "junit.xml")]
    before = digest(out)
    p = run_mfv(ctx, argv, out)
    why = crash(p, ctx.timeout)
    if not why and p.returncode != 2:
        why = f"exit {p.returncode}, expected 2 (a history inside the report directory)"
    if not why and "inside the report directory" not in p.stderr:
        why = "refused, but not for a history inside the report directory"
    if not why:
        d = changed(before, digest(out))
        if d:
            why = f"refused, but something changed: {d}"
    return f"history inside the report ({choice}); mfv {shown(argv)}", p, why, None


LOCKER = r"""
import sqlite3, sys, time
path, how, hold, delay = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
time.sleep(delay)
c = sqlite3.connect(path, timeout=30, isolation_level=None)
c.execute("BEGIN " + how)
print("locked", flush=True)
time.sleep(hold)
c.execute("ROLLBACK")
c.close()
"""


def locked_case(ctx, kind, rng, i, base):
    h, out = os.path.join(base, "h"), os.path.join(base, "out")
    os.makedirs(h)
    os.makedirs(out)
    H = os.path.join(h, "history.sqlite")
    write(H, ctx.template)
    ctx.names_before = os.listdir(h)
    how = rng.choice(["IMMEDIATE", "EXCLUSIVE"])
    if kind == "locked-short":
        hold, delay, expect = round(rng.uniform(0.2, 4.0), 2), 0.0, 0
    elif kind == "locked-long":
        hold, delay, expect = 3600.0, 0.0, 2
    else:
        hold, delay, expect = round(rng.uniform(2, 15), 2), round(rng.uniform(0, 2.5), 2), None
    locker = subprocess.Popen([sys.executable, "-c", LOCKER, H, how, str(hold), str(delay)],
                              stdout=subprocess.PIPE, text=True)
    if delay == 0:
        locker.stdout.readline()  # the lock is held when mfv starts
    report = rng.random() < 0.5
    argv = verify_argv(ctx, H, out, report)
    before = digest(h)
    p = run_mfv(ctx, argv, out)
    if kind == "locked-long":
        locker.kill()
    locker.wait()
    why = judge_verify(ctx, kind, p, H, before, h, out, report, ctx.runs, expect)
    return (f"another process holds BEGIN {how} for {hold} s from {delay} s; "
            f"mfv {shown(argv)}"), p, why, None


def two_writers_case(ctx, kind, rng, i, base):
    h = os.path.join(base, "h")
    os.makedirs(h)
    H = os.path.join(h, "history.sqlite")
    fresh = rng.random() < 0.3
    if not fresh:
        write(H, ctx.template)
    procs, outs = [], []
    for k in range(2):
        out = os.path.join(base, f"out{k}")
        os.makedirs(out)
        argv = verify_argv(ctx, H, out, rng.random() < 0.5)
        env = dict(os.environ, OMP_NUM_THREADS="1")
        procs.append(subprocess.Popen([ctx.mfv] + argv, cwd=out, env=env, text=True,
                                      stdout=subprocess.PIPE, stderr=subprocess.PIPE))
        outs.append(argv)
    results, why = [], None
    for q in procs:
        try:
            o, e = q.communicate(timeout=ctx.timeout)
            results.append(subprocess.CompletedProcess(q.args, q.returncode, o, e))
        except subprocess.TimeoutExpired:
            q.kill()
            q.communicate()
            results.append(None)
    for r in results:
        why = why or crash(r, ctx.timeout) or (None if r.returncode == 0 else
                                              f"a writer exited {r.returncode}, expected 0")
    want = (0 if fresh else ctx.runs) + 2
    if not why and history_state(H) != ("ok", want):
        why = f"after two writers the history is {history_state(H)}, expected {want} runs"
    first = next((r for r in results if r is None or r.returncode != 0), results[0])
    return (f"two at once{' on a new file' if fresh else ''}: mfv {shown(outs[0])} and "
            f"mfv {shown(outs[1])}"), first, why, None


def sigkill_case(ctx, kind, rng, i, base):
    h, out = os.path.join(base, "h"), os.path.join(base, "out")
    os.makedirs(h)
    os.makedirs(out)
    H = os.path.join(h, "history.sqlite")
    fresh = rng.random() < 0.2
    if not fresh:
        write(H, ctx.template)
    runs = 0 if fresh else ctx.runs
    report = rng.random() < 0.7
    argv = verify_argv(ctx, H, out, report)
    when = rng.choice(["time", "time", "journal"])
    at = round(rng.uniform(0, 1.3 * ctx.verify_seconds), 3)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    q = subprocess.Popen([ctx.mfv] + argv, cwd=out, env=env, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)
    t0 = time.time()
    journal = H + "-journal"
    killed = False
    while q.poll() is None and time.time() - t0 < ctx.timeout:
        if (when == "time" and time.time() - t0 >= at) or (when == "journal" and
                                                            os.path.exists(journal)):
            q.send_signal(signal.SIGKILL)
            killed = True
            break
        time.sleep(0.0005 if when == "journal" else 0.005)
    q.wait()
    how = (f"SIGKILL at {at} s" if when == "time" else "SIGKILL when the -journal appeared")
    how += "" if killed else " (mfv had finished first)"
    tried = f"{how} of mfv {shown(argv)}{' on a new file' if fresh else ''}"
    # Then: the history is listed, holds the run or not, and the next run appends to it.
    if os.path.exists(H):
        p = run_mfv(ctx, ["history", "--history", H], out)
        why = crash(p, ctx.timeout)
        if why:
            return tried + "; then mfv history", p, why, None
        st = history_state(H)
        ok_runs = {runs, runs + 1} if killed else {runs + 1}
        if p.returncode != 0 or st[0] != "ok" or st[1] not in ok_runs:
            return (tried + "; then mfv history", p,
                    f"after the kill `mfv history` exits {p.returncode} and the history is {st}, "
                    f"expected a valid history of {sorted(ok_runs)} run(s)", None)
        runs = st[1]
    elif not fresh:
        return tried, None, "the history file is gone after the kill", None
    else:
        runs = 0
    p = run_mfv(ctx, argv, out)
    why = crash(p, ctx.timeout)
    if not why and p.returncode != 0:
        why = f"the run after the kill exits {p.returncode}, expected 0"
    if not why and history_state(H) != ("ok", runs + 1):
        why = f"the run after the kill left the history {history_state(H)}, expected {runs + 1} runs"
    if not why:
        stale = [n for n in os.listdir(out) if ".staging-" in n or n.endswith(".mfv-lock")]
        if stale:
            why = f"the run after the kill left the killed run's {stale}"
    return tried + "; then the same verify again", p, why, "killed" if killed and not why else None


def history_cmd_case(ctx, kind, rng, i, base):
    h = os.path.join(base, "h")
    os.makedirs(h)
    fk = rng.choice(FILE_KINDS + ["good"] * 4)
    if fk == "good":
        H = os.path.join(h, "history.sqlite")
        write(H, ctx.template)
        what = "the template history"
    else:
        H, what, _ = make_history(ctx, rng, fk, h)
    sub = rng.choice(SUBJECTS)
    argv = ["history"] + sub + ["--history", H]
    before = digest(h)
    p = run_mfv(ctx, argv, base)
    why = crash(p, ctx.timeout)
    after = digest(h)
    if not why and p.returncode not in (0, 2):
        why = f"exit {p.returncode} (history reads: 0 or 2)"
    d = changed(before, after)
    # The only change `mfv history` may make is SQLite's own recovery of a crashed writer's
    # hot journal in mfv's own history (the committed state is restored, nothing is lost).
    if not why and d and fk not in ("history-hot-journal", "history-wal"):
        why = f"mfv history changed the history's directory: {d}"
    if not why and p.returncode == 2 and not any(n in p.stderr for n in (H, os.path.basename(H))):
        why = "exit 2 without naming the history"
    if not why and p.returncode == 0:
        st = history_state(os.path.realpath(H))
        if st[0] != "ok":
            why = f"exit 0 on a history Python's sqlite3 finds {st}"
    return f"history = {what}; mfv {shown(argv)}", p, why, None


def main():
    a = arguments(__doc__, "the fixed corpus of the CTest test: every kind once (33 cases), "
                  "seed 45", len(KINDS), 45, extra=only_option)
    ctx = Ctx()
    ctx.mfv, ctx.timeout = os.path.abspath(a.mfv), a.timeout
    a.mfv = ctx.mfv
    with tempfile.TemporaryDirectory(prefix="mfv-fuzz-history-") as w:
        os.chmod(w, 0o755)
        ctx.manifest = os.path.join(w, "suite.toml")
        with open(ctx.manifest, "w") as f:
            f.write(MANIFEST)
        tmpl = os.path.join(w, "template.sqlite")
        ctx.pristine_report = os.path.join(w, "pristine-report")
        t0 = time.time()
        for argv in (["verify", ctx.manifest, "--history", tmpl, "-r", ctx.pristine_report],
                     ["verify", ctx.manifest, "--history", tmpl, "--no-report"]):
            p = run_mfv(ctx, argv, w, timeout=max(120, a.timeout))
            if p is None or p.returncode != 0:
                print("fuzz_history: the template run fails:", shown(argv),
                      p and (p.stdout + p.stderr)[-2000:])
                return 1
        ctx.verify_seconds = (time.time() - t0) / 2
        ctx.template = open(tmpl, "rb").read()
        ctx.runs = history_state(tmpl)[1]
        print(f"fuzz_history: template history of {len(ctx.template)} bytes, {ctx.runs} runs; "
              f"a verify takes {ctx.verify_seconds:.2f} s", flush=True)
        runners = {k: file_case for k in FILE_KINDS}
        runners.update({"readonly-file": readonly_case, "readonly-dir": readonly_case,
                        "readonly-dir-absent": readonly_case, "inside-report": inside_report_case,
                        "locked-short": locked_case, "locked-long": locked_case,
                        "locked-late": locked_case, "two-writers": two_writers_case,
                        "sigkill": sigkill_case, "history-cmd": history_cmd_case})

        def runner(kind, rng, i):
            base = os.path.join(w, f"c{i}")
            os.makedirs(base)
            try:
                return runners[kind](ctx, kind, rng, i, base)
            finally:
                for root, dirs, _ in os.walk(base):
                    for d in dirs:
                        try:
                            os.chmod(os.path.join(root, d), 0o755)
                        except OSError:
                            pass
                shutil.rmtree(base, ignore_errors=True)
        return drive(a, KINDS, runner, "fuzz_history.py")


if __name__ == "__main__":
    sys.exit(main())
