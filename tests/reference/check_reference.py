#!/usr/bin/env python3
"""Re-runs a reference script and fails when its studies differ from the recorded file.

The ledger judges findings on recorded independent studies (verify/reference_studies.hpp);
this keeps the recording honest: the script's output now must equal it, number by number,
to a relative 1e-8 (the file keeps 10 significant digits).

Usage: check_reference.py --python PY --script SCRIPT --recorded FILE [SCRIPT ARGS...]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile


def numbers(doc):
    out = {}
    for s in doc["studies"]:
        for c in s["cases"]:
            for k, v in c.items():
                out[(s["label"], c["nodes"], k)] = v
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--python", required=True)
    ap.add_argument("--script", required=True)
    ap.add_argument("--recorded", required=True)
    a, extra = ap.parse_known_args()
    with tempfile.TemporaryDirectory() as tmp:
        fresh = os.path.join(tmp, "fresh.json")
        p = subprocess.run([a.python, a.script, "--json", fresh] + extra, capture_output=True,
                           text=True)
        if p.returncode != 0:
            sys.exit(f"{a.script} failed (rc {p.returncode}):\n{p.stdout[-2000:]}{p.stderr[-2000:]}")
        now = numbers(json.load(open(fresh)))
    was = numbers(json.load(open(a.recorded)))
    bad = []
    for key in sorted(set(now) | set(was), key=str):
        x, y = now.get(key), was.get(key)
        if x is None or y is None:
            bad.append(f"{key}: {'not recorded' if y is None else 'no longer computed'}")
        elif isinstance(x, float) or isinstance(y, float):
            if abs(x - y) > 1e-8 * max(abs(x), abs(y), 1e-300):
                bad.append(f"{key}: recorded {y!r}, computed {x!r}")
        elif x != y:
            bad.append(f"{key}: recorded {y!r}, computed {x!r}")
    if bad:
        print(f"{a.recorded} differs from what {a.script} computes; re-record it with "
              f"`{a.python} {a.script} --json {a.recorded}`:")
        print("\n".join(bad))
        return 1
    print(f"{a.recorded}: {len(was)} numbers equal what {a.script} computes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
