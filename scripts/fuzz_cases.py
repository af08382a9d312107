#!/usr/bin/env python3
"""Fuzz loop over the command line: random problem x method x edge-parameter cases.

Each case is `mfv run`, `mfv analyse` or `mfv study` on a small resolution with one input
pushed to an edge: 0, negative, NaN, inf, huge, tiny, the wrong type, an unknown or repeated
key, or two options that contradict each other. The problems, methods and their parameters
are read from `mfv list`, so new plugins are fuzzed without editing this script.

Outcomes: exit 0, 1, 2 or 3 with a message is fine; a signal (crash, sanitizer abort), a
timeout (hang), any other exit code, exit 2 whose message does not name the input that was
pushed, or exit 1/3 without any message is a failure. Prints one line per failure and a
summary; exits 1 if any case failed.

  scripts/fuzz_cases.py --mfv build/release/apps/mfv --count 300 --seed 7
  scripts/fuzz_cases.py --mfv build/release/apps/mfv --corpus     # the fixed CTest corpus
"""
import random
import re
import os
import sys
import subprocess
import tempfile

from fuzz_common import arguments, crash, outcomes, run, tally

ANALYSES = {"dispersion", "time-step", "enriched-bar", "stretch-map"}
# Edge values: (text, kind); a number-typed parameter given a word is "wrong type".
EDGES = ["0", "-1", "-0", "nan", "inf", "-inf", "1e300", "-1e300", "1e9", "1e-300", "0.5",
         "2.5", "abc", "", "1,2", "=", "0x10", "1e", "--", "3:4"]
NODE_EDGES = ["0", "-1", "1", "2", "nan", "abc", "1e9", "2147483648", "99999999999", "-2147483649",
              "3.5", ""]
PERTURB_EDGES = ["0", "-0.1", "0.5", "0.49", "nan", "inf", "1e300", "abc", ""]
# Small first resolutions per problem keep a case to seconds.
NODES = {"cantilever": 3, "elastic-patch": 5, "rod-pulse": 25, "stretch-map": 5, "dispersion": 5,
         "time-step": 11, "enriched-bar": 5, "rubber-ring": 120, "steel-ring": 150,
         "notched-beam": 10, "hydrostatic-column": 4, "dam-break": 4}


def parse_list(mfv):
    """{"methods": {name: [param, ...]}, "problems": {...}} from `mfv list`."""
    text = subprocess.run([mfv, "list"], capture_output=True, text=True, check=True).stdout
    out, section, name = {}, None, None
    for line in text.splitlines():
        if re.match(r"^[a-z]+s:$", line):
            section = line[:-1]
            out[section] = {}
        elif re.match(r"^  \S", line):
            name = line.split()[0]
            out[section][name] = []
        elif re.match(r"^      \S+=", line):
            out[section][name].append(line.split("=")[0].strip())
    return out


def named(key, value):
    """What a message about key=value must name: the key, or, when the value's comma splits
    it into a second item, that item."""
    return [key] + ([f"'{v}'" for v in value.split(",")[1:]] if "," in value else [])


def base_case(rng, catalogue):
    problems = sorted(catalogue["problems"])
    methods = sorted(catalogue["methods"])
    problem, method = rng.choice(problems), rng.choice(methods)
    n = NODES.get(problem, 11)
    if problem in ANALYSES:
        cmd = ["analyse", problem, "-m", method, "-n", str(n), "--no-report"]
        if problem == "stretch-map":
            cmd += ["--problem-params", "grid=2,points=5,angles=0:45,frames=lagrangian"]
        if problem == "enriched-bar":
            cmd += ["--problem-params", "positions=3"]
    elif rng.random() < 0.3:
        cmd = ["study", problem, "-m", method, "-n", f"{n},{2 * n - 1}"]
    else:
        cmd = ["run", problem, "-m", method, "-n", str(n)]
    return cmd, problem, method


def mutate_case(rng, catalogue, cmd, problem, method):
    mparams = catalogue["methods"][method]
    pparams = catalogue["problems"][problem]
    what = rng.choice(["method", "method", "problem", "problem", "nodes", "perturb", "duplicate",
                       "unknown", "conflict"])
    if what == "method" and mparams:
        key, value = rng.choice(mparams), rng.choice(EDGES)
        return cmd + ["-p", f"{key}={value}"], named(key, value)
    if what == "problem" and pparams:
        key, value = rng.choice(pparams), rng.choice(EDGES)
        # Replace a fixed problem parameter rather than repeat it.
        if "--problem-params" in cmd:
            i = cmd.index("--problem-params")
            kept = [kv for kv in cmd[i + 1].split(",") if not kv.startswith(key + "=")]
            cmd = cmd[:i] + cmd[i + 2:]
            return cmd + ["--problem-params", ",".join(kept + [f"{key}={value}"])], named(key, value)
        return cmd + ["--problem-params", f"{key}={value}"], named(key, value)
    if what == "nodes":
        value = rng.choice(NODE_EDGES)
        i = cmd.index("-n")
        return cmd[:i] + ["-n", value] + cmd[i + 2:], ["--nodes", "-n", value or "nodes"]
    if what == "perturb" and cmd[0] != "analyse":
        value = rng.choice(PERTURB_EDGES)
        return cmd + ["--perturb", value], ["--perturb", value or "perturb"]
    if what == "duplicate" and mparams:
        key = rng.choice(mparams)
        return cmd + ["-p", f"{key}=1,{key}=2"], [key]
    if what == "conflict":
        if cmd[0] == "study":
            return cmd + ["--full"], ["--full", "--nodes"]
        if cmd[0] == "analyse":
            return cmd + ["-r", "x"], ["--no-report", "--report"]
        return cmd + ["-n", "5"], ["--nodes", "-n"]
    return cmd + ["-p", "zzz=1"], ["zzz"]


def classify(p, words, timeout):
    """None when the outcome is fine, else the reason it is a failure."""
    why = crash(p, timeout)
    if why:
        return why
    text = p.stdout + p.stderr
    if p.returncode == 2 and not any(w and w in text for w in words):
        return f"exit 2 without naming the input {words}: {p.stderr.strip()[-300:]}"
    if p.returncode in (1, 3) and not p.stderr.strip() and "could not run" not in text:
        return f"exit {p.returncode} without a message"
    return None


def main():
    a = arguments(__doc__, "the fixed corpus of the CTest test: 40 cases, seed 12, 20 s each",
                  40, 12)
    a.mfv = os.path.abspath(a.mfv)
    catalogue = parse_list(a.mfv)
    rng = random.Random(a.seed)
    failures, codes, base_refused = [], {}, {}
    with tempfile.TemporaryDirectory(prefix="mfv-fuzz-") as cwd:
        for i in range(a.count):
            # Mostly pairs that run as they stand, so the mutation is what is tested; a pair
            # refused as it stands may be refused for that reason whatever was mutated: then
            # naming the problem or the method names the input.
            for _ in range(6):
                base, problem, method = base_case(rng, catalogue)
                key = tuple(base)
                if key not in base_refused:
                    b = run(a.mfv, base, cwd, a.timeout)
                    base_refused[key] = b is not None and b.returncode == 2
                if not base_refused[key]:
                    break
            argv, words = mutate_case(rng, catalogue, base, problem, method)
            if base_refused[key]:
                words = words + [problem, method]
            p = run(a.mfv, argv, cwd, a.timeout)
            tally(codes, p)
            why = classify(p, words, a.timeout)
            if why:
                failures.append((argv, why))
                print(f"FAIL {i}: mfv {' '.join(argv)}\n     {why}", flush=True)
    print(outcomes(codes))
    print(f"fuzz_cases: {a.count} cases (seed {a.seed}), {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
