#!/usr/bin/env python3
"""Every command of README.md's "Using it" block runs (issue 42, item 4).

Each line of the block's ```sh code is a command (a trailing backslash continues it); a line
whose comment says "(measured: <time>...)" states its time instead and is not run here (the
full suite, the paper-size rod runs, PySPH, ctest, the install into ~). Every other line runs
from a scratch directory that looks like the repository root (suites/, solvers/, examples/
and build/release linked in), after a set-up that leaves what the history and diff lines read:
two verification runs of two quick cases into runs/default (the first kept as runs/yesterday).
A command fails the test when it exits non-zero or takes more than --timeout seconds.

Usage: readme_commands_test.py --source DIR --build DIR --work DIR [--timeout S]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import time


def using_it_commands(readme):
    text = open(readme, encoding="utf-8").read()
    at = text.index("## Using it")
    block = re.search(r"```sh\n(.*?)```", text[at:], re.S)
    if not block:
        sys.exit("README.md: no ```sh block under '## Using it'")
    commands, pending = [], ""
    for line in block.group(1).splitlines():
        if pending:
            line = pending + " " + line.strip()
            pending = ""
        if line.rstrip().endswith("\\"):
            pending = line.rstrip()[:-1]
            continue
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        commands.append(line)
    return commands


def split_comment(line):
    """The command and its comment: the comment starts at the first ' #' outside quotes."""
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "#" and i > 0 and line[i - 1] == " ":
            return line[:i].rstrip(), line[i + 1:].strip()
    return line.rstrip(), ""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source", required=True)
    ap.add_argument("--build", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--timeout", type=float, default=120)
    a = ap.parse_args()
    source, build = os.path.abspath(a.source), os.path.abspath(a.build)
    work = os.path.abspath(a.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(os.path.join(work, "build"))
    for d in ("suites", "solvers", "examples", "scripts", "docs", "README.md"):
        os.symlink(os.path.join(source, d), os.path.join(work, d))
    os.symlink(build, os.path.join(work, "build", "release"))
    env = dict(os.environ, OMP_WAIT_POLICY="passive")
    mfv = "build/release/apps/mfv"

    def run(cmd):
        t0 = time.time()
        try:
            p = subprocess.run(["bash", "-c", f"set -o pipefail; M={mfv}; {cmd}"], cwd=work,
                               env=env, capture_output=True, text=True, timeout=a.timeout)
            return p.returncode, time.time() - t0, p.stdout + p.stderr
        except subprocess.TimeoutExpired:
            return None, time.time() - t0, f"timed out after {a.timeout:.0f} s"

    # Set-up: what `mfv history` and `mfv diff` read, as a nightly leaves it.
    quick = "--case laplace-tanh/fem --case laplace-tanh/efg"
    for step in (f"$M verify suites/default.toml {quick}",
                 "cp -r runs/default runs/yesterday",
                 f"$M verify suites/default.toml {quick}"):
        rc, _, out = run(step)
        if rc != 0:
            sys.exit(f"set-up '{step}' failed (rc {rc}):\n{out[-2000:]}")

    failures, ran, skipped = [], 0, 0
    for line in using_it_commands(os.path.join(source, "README.md")):
        cmd, comment = split_comment(line)
        if cmd.startswith("M="):
            continue
        if "(measured:" in comment:
            skipped += 1
            print(f"skip (its time is stated: {comment[comment.index('(measured:'):]}): {cmd}")
            continue
        rc, seconds, out = run(cmd)
        ran += 1
        print(f"{seconds:6.1f} s rc={rc}  {cmd}")
        if rc != 0:
            failures.append(f"{cmd}\n  rc {rc}: {out[-1500:]}")
    print(f"{ran} README command(s) ran, {skipped} state their measured time")
    if failures:
        print("FAILED:\n" + "\n".join(failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
