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


def arguments(doc, corpus_help, corpus_count, corpus_seed):
    """--mfv, --count, --seed, --timeout and --corpus (the CTest test's fixed corpus)."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("--mfv", required=True)
    ap.add_argument("--count", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=None,
                    help="seconds before a case counts as a hang (default 60; 20 with --corpus)")
    ap.add_argument("--corpus", action="store_true", help=corpus_help)
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
