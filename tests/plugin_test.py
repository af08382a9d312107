#!/usr/bin/env python3
"""Runs mfv with plugins (apps/plugin.hpp): the example plugin's kernel and problem are listed,
run, studied into a report and verified from a manifest's [suite] plugins; every plugin mfv
must refuse exits 2 naming the file and the cause. Usage (tests/CMakeLists.txt):
  plugin_test.py --mfv MFV --example LIB --bad STALE CLASH UNDEFINED NO_ENTRY THROWS THROWS_INT
    HOOK_INT FACTORY_INT EXITS NAME EXTERNAL --work DIR
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

FAILS = []


def run(mfv, args, env=None, timeout=300):
    p = subprocess.run([mfv] + args, capture_output=True, text=True, timeout=timeout,
                       env=env)
    return p.returncode, p.stdout, p.stderr


def check(what, ok, detail=""):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        FAILS.append(what)
        if detail:
            print("      " + detail.replace("\n", "\n      ")[:2000])


def expect(mfv, what, args, code, needles, stream="stderr", cwd_env=None):
    rc, out, err = run(mfv, args, env=cwd_env)
    text = err if stream == "stderr" else out
    missing = [n for n in needles if n not in text]
    check(what, rc == code and not missing,
          f"exit {rc} (wanted {code}); missing {missing}\nstdout: {out[-800:]}\nstderr: {err[-800:]}")
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mfv", required=True)
    ap.add_argument("--example", required=True)
    ap.add_argument("--bad", nargs=14, required=True,
                    metavar=("STALE", "CLASH", "UNDEFINED", "NO_ENTRY", "THROWS", "THROWS_INT",
                             "HOOK_INT", "FACTORY_INT", "EXITS", "NAME", "EXTERNAL",
                             "FACTORY_EXITS", "FACTORY_CRASH", "HOOK_EXITS"))
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    mfv, ex = a.mfv, a.example
    (stale, clash, undefined, no_entry, throws, throws_int, hook_int, factory_int, exits,
     bad_name, external, factory_exits, factory_crash, hook_exits) = a.bad
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)

    # 1. What the plugin adds is in every registry.
    expect(mfv, "list kernels names the plugin's kernel", ["--plugin", ex, "list", "kernels"], 0,
           ["johnson-quadratic", "cubic-spline"], "stdout")
    expect(mfv, "list problems names the plugin's problem", ["--plugin", ex, "list", "problems"],
           0, ["sine-bar", "rod-pulse"], "stdout")
    expect(mfv, "the plugin kernel is a choice of efg", ["--plugin", ex, "list", "efg"], 0,
           ["johnson-quadratic"], "stdout")
    expect(mfv, "a library named twice is loaded once",
           ["--plugin", ex, "--plugin", ex, "list", "kernels"], 0, ["johnson-quadratic"], "stdout")
    expect(mfv, "without the plugin its kernel is unknown",
           ["run", "sine-bar", "-m", "efg", "-n", "11"], 2, ["unknown problem 'sine-bar'"])

    # 2. It runs like a built-in: errors, a study, a report.
    expect(mfv, "run sine-bar with efg on the plugin kernel",
                 ["--plugin", ex, "run", "sine-bar", "-m", "efg", "-p", "kernel=johnson-quadratic",
                  "-n", "21"], 0, ["sine-bar"], "stdout")
    report = os.path.join(a.work, "report")
    expect(mfv, "study into a report",
           ["--plugin", ex, "study", "sine-bar", "-m", "efg", "-p", "kernel=johnson-quadratic",
            "-n", "11", "-n", "21", "-n", "41", "-r", report], 0, [], "stdout")
    index = os.path.join(report, "index.md")
    check("the report has an index naming the problem",
          os.path.isfile(index) and "sine-bar" in open(index, encoding="utf-8").read())
    results = os.path.join(report, "results.json")
    plugins = json.load(open(results))["run"]["plugins"] if os.path.isfile(results) else []
    check("results.json names the plugin it ran with",
          [os.path.basename(p) for p in plugins] == [os.path.basename(ex)], f"plugins: {plugins}")

    # 3. A manifest's [suite] plugins, relative to the manifest.
    suite = os.path.join(a.work, "suite")
    os.makedirs(suite)
    shutil.copy(ex, os.path.join(suite, "libexample.so"))
    with open(os.path.join(suite, "plugin.toml"), "w") as f:
        f.write('[suite]\nname = "plugin"\nplugins = ["libexample.so"]\n\n'
                '[[case]]\nid = "sine-bar/efg-johnson"\nproblem = "sine-bar"\nmethod = "efg"\n'
                'method_params = { kernel = "johnson-quadratic" }\nnodes = [11, 21, 41]\n'
                '[case.bands]\nl2_rate = [1.5, 3.5]\n')
    expect(mfv, "verify loads [suite] plugins and judges the case",
           ["verify", os.path.join(suite, "plugin.toml"), "-r", os.path.join(a.work, "runs")],
           0, [], "stdout")
    runs_index = os.path.join(a.work, "runs", "index.md")
    check("the verify report's summary names the plugin",
          os.path.isfile(runs_index) and "libexample.so" in open(runs_index, encoding="utf-8").read())
    with open(os.path.join(suite, "missing.toml"), "w") as f:
        f.write('[suite]\nname = "missing"\nplugins = ["libnothere.so"]\n\n'
                '[[case]]\nid = "x"\nproblem = "sine-bar"\nmethod = "efg"\nnodes = [11, 21]\n')
    expect(mfv, "a manifest naming a missing plugin", ["verify",
           os.path.join(suite, "missing.toml"), "--no-report"], 2,
           ["libnothere.so", "no such file"])
    with open(os.path.join(suite, "typed.toml"), "w") as f:
        f.write('[suite]\nname = "typed"\nplugins = "libexample.so"\n')
    expect(mfv, "plugins must be an array", ["verify", os.path.join(suite, "typed.toml"),
           "--no-report"], 2, ["'plugins' must be an array"])

    # 4. Refusals: exit 2, the file and the cause named, nothing run.
    expect(mfv, "a missing file", ["--plugin", os.path.join(a.work, "nope.so"), "list"], 2,
           ["nope.so", "no such file"])
    expect(mfv, "a directory", ["--plugin", a.work, "list"], 2, ["not a regular file (a directory)"])
    expect(mfv, "a special file", ["--plugin", "/dev/null", "list"], 2,
           ["not a regular file (a special file)"])
    expect(mfv, "an empty name", ["--plugin", "", "list"], 2, ["names no file"])
    text = os.path.join(a.work, "text.so")
    with open(text, "w") as f:
        f.write("not a library\n")
    expect(mfv, "a file that is no library", ["--plugin", text, "list"], 2,
           ["cannot be loaded", "text.so"])
    expect(mfv, "a library without MFV_PLUGIN", ["--plugin", no_entry, "list"], 2,
           ["is not an mfv plugin", "mfv_plugin_abi"])
    expect(mfv, "a plugin built for another mfv", ["--plugin", stale, "list"], 2,
           ["was built for mfv 0.0.1, gcc 9", "this program is mfv ", "find_package(mfv CONFIG)"])
    expect(mfv, "a plugin needing a symbol mfv lacks", ["--plugin", undefined, "list"], 2,
           ["cannot be loaded", "undefined symbol"])
    expect(mfv, "a plugin re-registering a built-in kernel", ["--plugin", clash, "list"], 2,
           ["plugin 'libmfv_bad_plugin_clash.so'", "kernel 'gaussian' registered twice"])
    expect(mfv, "a plugin whose entry point throws", ["--plugin", throws, "list"], 2,
           ["failed in mfv_plugin_register", "cannot find my data file"])

    # Issue 45: plugins that fail name themselves.
    expect(mfv, "an entry point that throws an int", ["--plugin", throws_int, "list"], 2,
           ["failed in mfv_plugin_register", "not a std::exception"])
    expect(mfv, "a kernel hook that throws an int", ["--plugin", hook_int, "list"], 2,
           ["libmfv_bad_plugin_hook_int.so", "kernel registration threw something that is not"])
    expect(mfv, "a kernel factory that throws an int when efg creates it",
           ["--plugin", factory_int, "run", "mms-poisson-1d", "-m", "efg", "-p", "kernel=throws-int",
            "-n", "11"], 1, ["not a std::exception was thrown", "plugin"])
    expect(mfv, "an entry point that calls exit(0)", ["--plugin", exits, "list"], 2,
           ["called exit() while it was being loaded", "libmfv_bad_plugin_exits.so"])
    suite_exits = os.path.join(a.work, "exits.toml")
    with open(suite_exits, "w") as f:
        f.write(f'[suite]\nname = "exits"\nplugins = ["{exits}"]\n[[case]]\nid = "sine-bar/fem"\n'
                'problem = "sine-bar"\nmethod = "fem"\nnodes = [11, 21]\n')
    expect(mfv, "verify of a manifest whose plugin calls exit(0) is not a pass",
           ["verify", suite_exits, "--no-report", "--no-history"], 2,
           ["called exit() while it was being loaded"])
    # A plugin's code that ends the process while a case runs: the command runs in a
    # supervised child (apps/supervise.hpp), so _exit(0) is exit 1, never a pass, and a crash
    # is named and still a crash.
    ends = ["run", "mms-poisson-1d", "-m", "efg", "-p", "kernel=ends-the-process", "-n", "11"]
    expect(mfv, "a kernel factory that calls _exit(0) while a case runs",
           ["--plugin", factory_exits] + ends, 1,
           ["ended with status 0 before it finished", "libmfv_bad_plugin_factory_exits.so"])
    suite_ends = os.path.join(a.work, "ends.toml")
    with open(suite_ends, "w") as f:
        f.write(f'[suite]\nname = "ends"\nplugins = ["{factory_exits}"]\n[[case]]\n'
                'id = "mms/efg-ends"\nproblem = "mms-poisson-1d"\nmethod = "efg"\n'
                'method_params = { kernel = "ends-the-process" }\nnodes = [11, 21]\n')
    expect(mfv, "verify of a case whose plugin kernel calls _exit(0) is not a pass",
           ["verify", suite_ends, "--no-report", "--no-history"], 1,
           ["before it finished", "libmfv_bad_plugin_factory_exits.so"])
    expect(mfv, "a kernel hook that calls _exit(0) is a refused plugin (exit 2)",
           ["--plugin", hook_exits, "list", "kernels"], 2,
           ["while the plugins were being registered", "libmfv_bad_plugin_hook_exits.so"])
    expect(mfv, "a kernel factory that dies of SIGSEGV is named and still a crash",
           ["--plugin", factory_crash] + ends, -11,
           ["killed by signal 11", "libmfv_bad_plugin_factory_crash.so"])
    expect(mfv, "a kernel named 'a,b=c'", ["--plugin", bad_name, "list"], 2,
           ["the kernel name 'a,b=c' is not a valid name"])
    expect(mfv, "a kernel named 'external:pysph'", ["--plugin", external, "list"], 2,
           ["the kernel name 'external:pysph' is not a valid name", "reserved for external:"])
    cut = os.path.join(a.work, "truncated.so")
    with open(ex, "rb") as f:
        whole = f.read()
    with open(cut, "wb") as f:
        f.write(whole[: len(whole) // 2])
    expect(mfv, "a truncated library", ["--plugin", cut, "list"], 2,
           ["is a truncated or damaged library", "truncated.so"])

    print(f"{len(FAILS)} failed" if FAILS else "all passed")
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
