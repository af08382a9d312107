#!/usr/bin/env python3
"""Fuzz loop over `mfv verify`: byte mutations of a tiny manifest and of its baseline.

A one-case suite (linear FEM on laplace-tanh at 21 and 41 nodes, about 0.1 s) and its
baseline are written to a temporary directory; the baseline is recorded once with
`--update-baseline`. Each mutation then flips, inserts, deletes or duplicates bytes (or
swaps in a token such as nan, inf, a huge or negative number, a quote or a bracket) in one of
the two files, and runs `mfv verify <manifest> --no-report` under a timeout.

Outcomes: exit 0, 1, 2 or 3 with a message is fine; a signal, a timeout, another exit code,
exit 2 whose message names neither file nor a case, or exit 1/3 without a message is a
failure. Prints one line per failure and a summary; exits 1 if any mutation failed.

  scripts/fuzz_manifest.py --mfv build/release/apps/mfv --count 300 --seed 3
  scripts/fuzz_manifest.py --mfv build/release/apps/mfv --corpus   # the fixed CTest corpus
"""
import os
import random
import sys
import tempfile

from fuzz_common import arguments, crash, outcomes, run, tally

MANIFEST = """[suite]
name = "fuzz"
description = "one fast case for the fuzz loop"
baseline = "baseline.toml"
drift_tolerance = 0.05

[[case]]
id = "lt/fem"
problem = "laplace-tanh"
method = "fem"
nodes = [21, 41]
problem_params = { s = 2.0 }
labels = ["fast"]
[case.bands]
l2_rate = [1.5, 2.5]
"""
TOKENS = [b"nan", b"inf", b"-inf", b"1e300", b"-1", b"0", b"1e-300", b"99999999999", b'"',
          b"[", b"]", b"{", b"}", b"=", b"\n", b"#", b"\x00", b"\xff", b"[[case]]", b"'''",
          b"2147483648", b"-2147483649", b"true", b"..", b"../victim", b"\\"]


def mutate(rng, data):
    data = bytearray(data)
    for _ in range(rng.randint(1, 3)):
        op = rng.choice(["flip", "insert", "delete", "token", "duplicate", "truncate"])
        i = rng.randrange(len(data) + 1) if data else 0
        if op == "flip" and data:
            j = min(i, len(data) - 1)
            data[j] ^= 1 << rng.randrange(8)
        elif op == "insert":
            data[i:i] = bytes([rng.randrange(256)])
        elif op == "delete" and data:
            del data[i:i + rng.randint(1, 8)]
        elif op == "token":
            data[i:i + rng.randint(0, 4)] = rng.choice(TOKENS)
        elif op == "duplicate" and data:
            lines = bytes(data).split(b"\n")
            k = rng.randrange(len(lines))
            lines.insert(k, lines[k])
            data = bytearray(b"\n".join(lines))
        elif op == "truncate":
            del data[i:]
    return bytes(data)


def classify(p, timeout):
    why = crash(p, timeout)
    if why:
        return why
    text = p.stdout + p.stderr
    if p.returncode == 2 and not any(w in text for w in ("suite.toml", "baseline.toml", "lt/fem",
                                                          "case")):
        return f"exit 2 naming neither file nor case: {p.stderr.strip()[-300:]}"
    if p.returncode in (1, 3) and not text.strip():
        return f"exit {p.returncode} without a message"
    return None


def main():
    a = arguments(__doc__, "the fixed corpus of the CTest test: 60 mutations, seed 5, 20 s each",
                  60, 5)
    mfv = os.path.abspath(a.mfv)
    rng = random.Random(a.seed)
    failures, codes = 0, {}
    with tempfile.TemporaryDirectory(prefix="mfv-fuzz-manifest-") as d:
        manifest, baseline = os.path.join(d, "suite.toml"), os.path.join(d, "baseline.toml")
        with open(manifest, "w") as f:
            f.write(MANIFEST)
        p = run(mfv, ["verify", manifest, "--update-baseline", "--no-report"], d, a.timeout)
        if p is None or p.returncode != 0:
            print("fuzz_manifest: the unmutated suite does not pass:",
                  p.stdout + p.stderr if p else "timeout")
            return 1
        good = {manifest: MANIFEST.encode(), baseline: open(baseline, "rb").read()}
        for i in range(a.count):
            target = rng.choice([manifest, baseline])
            mutated = mutate(rng, good[target])
            for path, data in good.items():
                with open(path, "wb") as f:
                    f.write(mutated if path == target else data)
            p = run(mfv, ["verify", manifest, "--no-report"], d, a.timeout)
            tally(codes, p)
            why = classify(p, a.timeout)
            if why:
                failures += 1
                name = os.path.basename(target)
                print(f"FAIL {i}: mutated {name}: {why}\n----\n"
                      f"{mutated.decode('utf-8', 'replace')}\n----", flush=True)
    print(outcomes(codes))
    print(f"fuzz_manifest: {a.count} mutations (seed {a.seed}), {failures} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
