#!/usr/bin/env python3
"""Fuzz loop over plugin libraries (`mfv --plugin LIB`, a manifest's `[suite] plugins`).

Each case names a hostile library to mfv and runs `mfv list`, `mfv run laplace-tanh -m fem`
or `mfv verify` of a one-case manifest (plugin given by --plugin or by [suite] plugins,
relative or absolute). The libraries, made at fuzz time in a temporary directory:
  a light plugin (no mfv headers, built with g++ in a second) whose static initializer,
  mfv_plugin_abi or mfv_plugin_register does what MFV_FUZZ_PLUGIN_MODE says (return, exit(0),
  exit(3), quick_exit(0), _exit(0), abort, SIGSEGV, SIGKILL, throw a std::exception, an int, a
  std::string or a class of its own; return a null, wrong, empty or 10 kB ABI text), and
  builds without mfv_plugin_abi or without mfv_plugin_register;
  a heavy plugin (against the repository's headers, with the build's flags from
  compile_commands.json; skipped when there is none) that registers a kernel, problem,
  method, approximation or analysis under a name from MFV_FUZZ_NAME (empty, "a,b=c",
  "external:pysph", 10 kB, a built-in's, valid ones), whose kernel hook exits or throws
  while the catalogue is built, and whose kernels' factories exit, _exit, throw an int or
  return null when a method creates them; two copies of it (a name registered twice);
  the build's own test plugins (tests/libmfv_bad_plugin_*.so, libmfv_example_plugin.so);
  and files that are no plugin: empty, one byte, random bytes, text, a plugin truncated at a
  random byte, an ELF header over random bytes, ELF header bytes flipped, a directory, a
  FIFO, /dev/null or /dev/zero, a symbolic link loop, a dangling link, a nonexistent or
  10 kB path, an empty name; and valid plugins under odd file names or named twice.
Oracles: a library that must be refused gives exit 2 with a message naming it (its path or
file name); never exit 0 for a command that then ran nothing (a list without its listing, a
run without its errors, a verify without its PASS); a valid library gives exit 0; no signal
except from a plugin that kills itself (abort, SIGSEGV, SIGKILL in its own code: tallied as
"plugin crashed"), no exit code outside 0-3, no hang.

  scripts/fuzz_plugins.py --mfv build/release/apps/mfv --count 300 --seed 3
  scripts/fuzz_plugins.py --mfv build/release/apps/mfv --corpus   # the fixed CTest corpus
  scripts/fuzz_plugins.py --mfv build/release/apps/mfv --seed 3 --only 17   # one case
"""
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

from fuzz_common import arguments, crash, drive, only_option, shown, spawn

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

LIGHT = r"""
// A plugin without mfv's headers: what it does is MFV_FUZZ_PLUGIN_MODE = "<when>:<what>",
// when = ctor | abi | register.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <unistd.h>
@ABI@
namespace {
struct NotStd { int code; };
std::string long_abi(10000, 'x');
const char* what(const char* when) {
  const char* m = std::getenv("MFV_FUZZ_PLUGIN_MODE");
  const std::size_t n = std::strlen(when);
  if (!m || std::strncmp(m, when, n) != 0 || m[n] != ':') return "";
  return m + n + 1;
}
void act(const char* when) {
  const std::string w = what(when);
  if (w == "exit0") std::exit(0);
  if (w == "exit3") std::exit(3);
  if (w == "quick_exit0") std::quick_exit(0);
  if (w == "_exit0") _exit(0);
  if (w == "abort") std::abort();
  if (w == "segv") std::raise(SIGSEGV);
  if (w == "kill9") std::raise(SIGKILL);
  if (w == "throw-std") throw std::runtime_error("the fuzz plugin's own failure");
  if (w == "throw-int") throw 42;
  if (w == "throw-string") throw std::string("a std::string, not a std::exception");
  if (w == "throw-nonstd") throw NotStd{7};
}
__attribute__((constructor)) void on_load() { act("ctor"); }
}  // namespace
#ifndef NO_ABI
extern "C" __attribute__((visibility("default"))) const char* mfv_plugin_abi() {
  act("abi");
  const std::string w = what("abi");
  if (w == "null") return nullptr;
  if (w == "wrong") return "mfv 0.0.0, gcc 1";
  if (w == "empty") return "";
  if (w == "long") return long_abi.c_str();
  return MFV_PLUGIN_ABI;
}
#endif
#ifndef NO_REGISTER
extern "C" __attribute__((visibility("default"))) void mfv_plugin_register(void*) {
  act("register");
}
#endif
"""

HEAVY = r"""
// A plugin against mfv's headers: MFV_FUZZ_HEAVY says what it does, MFV_FUZZ_NAME and
// MFV_FUZZ_REGISTRY the name it registers and where.
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include "apps/plugin.hpp"
namespace {
struct NotStd { int code; };
std::string env(const char* k) {
  const char* v = std::getenv(k);
  return v ? v : "";
}
template <class R>
void add_named(R& r) {
  r.add(env("MFV_FUZZ_NAME"), "an entry of the fuzz plugin", {},
        typename R::Factory([](const mfv::Params&) { return nullptr; }));
}
void kernels(mfv::KernelRegistry& r) {
  const std::string h = env("MFV_FUZZ_HEAVY");
  if (h == "hook-exit0") std::exit(0);
  if (h == "hook-_exit0") _exit(0);
  if (h == "hook-abort") std::abort();
  if (h == "hook-throw-std") throw std::runtime_error("the fuzz plugin's hook failed");
  if (h == "hook-throw-nonstd") throw NotStd{3};
  using P = std::unique_ptr<mfv::Kernel>;
  r.add("fuzz-exit", "exit(0) when created", {}, [](const mfv::Params&) -> P { std::exit(0); });
  r.add("fuzz-_exit", "_exit(0) when created", {}, [](const mfv::Params&) -> P { _exit(0); });
  r.add("fuzz-throw", "throws an int when created", {}, [](const mfv::Params&) -> P { throw 5; });
  r.add("fuzz-null", "a null kernel", {}, [](const mfv::Params&) -> P { return nullptr; });
  if (env("MFV_FUZZ_REGISTRY") == "kernel") add_named(r);
}
}  // namespace
MFV_PLUGIN(plugin) {
  plugin.kernels.push_back(kernels);
  const std::string where = env("MFV_FUZZ_REGISTRY");
  if (where == "problem")
    plugin.problems.push_back([](mfv::ProblemRegistry& r) { add_named(r); });
  if (where == "method")
    plugin.methods.push_back([](mfv::MethodRegistry& r, const mfv::MethodParts&) { add_named(r); });
  if (where == "approximation")
    plugin.approximations.push_back(
        [](mfv::ApproximationRegistry& r, const mfv::KernelRegistry&) { add_named(r); });
  if (where == "analysis")
    plugin.analyses.push_back([](mfv::AnalysisRegistry& r) { add_named(r); });
}
"""

MANIFEST = """[suite]
name = "fuzz-plugins"
plugins = [{plugins}]

[[case]]
id = "lt/fem"
problem = "laplace-tanh"
method = "fem"
nodes = [21, 41]
"""
# Light-plugin modes: (when, what) and the outcome due: "ok" (a valid plugin), "refuse"
# (exit 2 naming it), "crash" (the plugin kills itself: a signal allowed, never exit 0).
WHATS = {"return": "ok", "exit0": "refuse", "exit3": "refuse", "quick_exit0": "refuse",
         "_exit0": "refuse", "abort": "crash", "segv": "crash", "kill9": "crash",
         "throw-std": "refuse", "throw-int": "refuse", "throw-string": "refuse",
         "throw-nonstd": "refuse"}
ABI_WHATS = {"null": "refuse", "wrong": "refuse", "empty": "refuse", "long": "refuse"}
# An exception out of a static initializer has no handler above it (dlopen is C): it ends the
# process through std::terminate, the plugin's own doing.
CTOR_THROW = "crash"
NAMES = ["", "a,b=c", "external:pysph", "x" * 10000, "y" * 65, "z" * 64, "a b", "-lead",
         ".dot", "ok-name", "ok_name.v2+", "a=b", "tab\tname", "new\nline", "ünï", "9lives",
         "colon:", "semi;colon", "quote'\"", "Upper-Case"]
REGISTRIES = ["kernel", "problem", "method", "approximation", "analysis"]
BUILTIN = {"kernel": "gaussian", "problem": "laplace-tanh", "method": "fem",
           "approximation": "mls", "analysis": "transient"}
ODD_FILE_NAMES = ["a,b=c.so", "external:pysph.so", " lead space.so", "-dash.so", "ünï.so",
                  "new\nline.so", "x" * 200 + ".so", "no-extension", ".hidden.so", "q'uote.so"]
KINDS = (["light-" + w for w in WHATS] + ["ctor-" + w for w in WHATS if w != "return"]
         + ["abi-" + w for w in list(ABI_WHATS) + ["exit0", "_exit0", "throw-std", "throw-int",
                                                     "abort"]]
         + ["no-abi", "no-register", "zero-length", "one-byte", "garbage", "text", "truncated",
            "elf-header-garbage", "elf-header-flipped", "directory", "fifo", "dev-node",
            "symlink-loop", "symlink-dangling", "nonexistent", "long-path", "empty-name",
            "odd-file-name", "symlink-to-valid", "named-twice", "prebuilt",
            "heavy-name", "heavy-builtin-name", "heavy-hook", "heavy-factory", "heavy-two-copies",
            "heavy-null-problem"])


class Ctx:
    pass


def abi_macros():
    """The lines of apps/plugin.hpp that define MFV_PLUGIN_ABI (so the light plugin states the
    same ABI text as a plugin built with MFV_PLUGIN by this compiler)."""
    text = open(os.path.join(REPO, "apps", "plugin.hpp")).read()
    start = text.index("#define MFV_API_VERSION")
    end = text.index("\n", text.index("#define MFV_PLUGIN_ABI"))
    return text[start:end] + "\n"


def build(ctx, name, source, flags):
    src = os.path.join(ctx.build, name + ".cpp")
    out = os.path.join(ctx.build, name + ".so")
    with open(src, "w") as f:
        f.write(source)
    p = subprocess.run(flags + ["-shared", "-fPIC", "-o", out, src], capture_output=True,
                       text=True, timeout=900)
    if p.returncode != 0:
        raise RuntimeError(f"cannot build {name}: {shlex.join(flags)}\n{p.stderr[-3000:]}")
    return out


def heavy_flags(mfv):
    """The compile command of tests/bad_plugins.cpp in the build's compile_commands.json,
    without its source, output and definitions (None when there is none)."""
    db = os.path.join(os.path.dirname(os.path.dirname(mfv)), "compile_commands.json")
    try:
        entries = json.load(open(db))
    except (OSError, ValueError):
        return None
    for e in entries:
        if e["file"].endswith("tests/bad_plugins.cpp"):
            argv = shlex.split(e["command"]) if "command" in e else list(e["arguments"])
            out, skip = [], False
            for x in argv:
                if skip:
                    skip = False
                    continue
                if x in ("-o", "-c"):
                    skip = True
                    continue
                if x.startswith("-DMFV_BAD_") or x.endswith("_EXPORTS") or x.startswith("-O"):
                    continue
                if x == e["file"]:
                    continue
                out.append(x)
            return out + ["-O0", "-g0", "-w"]
    return None


def prebuilt(mfv):
    """The build's test plugins: {name: path} (tests/libmfv_*plugin*.so beside apps/)."""
    d = os.path.join(os.path.dirname(os.path.dirname(mfv)), "tests")
    out = {}
    if os.path.isdir(d):
        for n in os.listdir(d):
            m = re.match(r"libmfv_(bad_plugin_(\w+)|example_plugin)\.so$", n)
            if m:
                out[m.group(2) or "example"] = os.path.join(d, n)
    return out


# What each prebuilt plugin must give on `mfv --plugin LIB list` (tests/plugin_test.py).
PREBUILT_LIST = {"example": "ok", "factory_int": "ok", "factory_exits": "ok", "factory_crash": "ok"}
# (hook_exits, like every other bad one, must be refused: exit 2 naming it.)


def command(ctx, rng, lib_args, base):
    """A command that loads the libraries `lib_args` (paths, as given), and what its success
    must show: (argv, needle in stdout on exit 0, env additions)."""
    how = rng.choice(["list", "list", "run", "verify-option", "verify-manifest"])
    pre = [x for lib in lib_args for x in ("--plugin", lib)]
    if how == "list":
        return pre + ["list", "kernels"], "cubic-spline"
    if how == "run":
        return pre + ["run", "laplace-tanh", "-m", "fem", "-n", "11"], "L2"
    m = os.path.join(base, "suite.toml")
    if how == "verify-manifest":
        given = []
        for lib in lib_args:
            rel = os.path.relpath(lib, base) if os.path.isabs(lib) and rng.random() < 0.5 else lib
            given.append(json.dumps(rel))
        with open(m, "w") as f:
            f.write(MANIFEST.format(plugins=", ".join(given)))
        return ["verify", m, "--no-report", "--no-history"], "PASS"
    with open(m, "w") as f:
        f.write(MANIFEST.format(plugins=""))
    return pre + ["verify", m, "--no-report", "--no-history"], "PASS"


def judge(ctx, p, due, libs, needle):
    """The oracle: due is "ok", "refuse", "crash" or "not-zero"."""
    if p is None:
        return f"timeout after {ctx.timeout} s (hang)"
    if p.returncode < 0:
        if due == "crash":
            return None
        return f"killed by signal {-p.returncode} (mfv's own code: the plugin does not crash)"
    why = crash(p, ctx.timeout)
    if why:
        return why
    if p.returncode == 0:
        if needle not in p.stdout:
            return (f"exit 0 but the command ran nothing (no '{needle}' in its output): a false "
                    f"pass")
        if due != "ok":
            return f"exit 0, expected {'exit 2' if due == 'refuse' else 'a failure'}"
        return None
    if due == "ok":
        return f"exit {p.returncode} for a valid plugin"
    if due == "refuse":
        if p.returncode != 2:
            return f"exit {p.returncode}, expected 2 (refused)"
        names = [x for lib in libs for x in (lib, os.path.basename(lib.rstrip("/")))
                 if x]
        if names and not any(n in p.stderr for n in names):
            return "refused without naming the library"
    return None


def light_case(ctx, kind, rng, i, base):
    if kind.startswith("light-"):
        when, what = "register", kind[len("light-"):]
        due = WHATS[what]
    elif kind.startswith("ctor-"):
        when, what = "ctor", kind[len("ctor-"):]
        due = CTOR_THROW if what.startswith("throw") else WHATS[what]
    else:
        when, what = "abi", kind[len("abi-"):]
        due = ABI_WHATS.get(what) or WHATS[what]
    lib = ctx.light
    argv, needle = command(ctx, rng, [lib], base)
    env = dict(ctx.env, MFV_FUZZ_PLUGIN_MODE=f"{when}:{what}")
    p = spawn([ctx.mfv] + argv, base, ctx.timeout, env=env)
    why = judge(ctx, p, due, [lib], needle)
    outcome = "plugin crashed" if p is not None and p.returncode < 0 and not why else None
    return (f"MFV_FUZZ_PLUGIN_MODE={when}:{what} mfv {shown(argv)}"), p, why, outcome


def file_case(ctx, kind, rng, i, base):
    """A file or path that is no plugin (or a valid plugin under an odd name)."""
    src = open(ctx.light, "rb").read()
    lib = os.path.join(base, "libfuzz.so")
    due = "refuse"
    what = kind
    if kind == "no-abi":
        lib = ctx.light_no_abi
    elif kind == "no-register":
        lib = ctx.light_no_register
    elif kind == "zero-length":
        open(lib, "wb").close()
    elif kind == "one-byte":
        open(lib, "wb").write(bytes([rng.randrange(256)]))
    elif kind == "garbage":
        n = rng.randint(16, 65536)
        open(lib, "wb").write(os.urandom(n))
        what = f"{n} random bytes"
    elif kind == "text":
        open(lib, "w").write(rng.choice(["not a library\n", "#!/bin/sh\nexit 0\n",
                                         "INPUT(libm.so)\n", "GROUP ( /lib/libc.so.6 )\n"]))
    elif kind == "truncated":
        cut = rng.randrange(1, len(src))
        open(lib, "wb").write(src[:cut])
        what = f"the light plugin cut at byte {cut} of {len(src)}"
    elif kind == "elf-header-garbage":
        keep = rng.choice([16, 52, 64])
        open(lib, "wb").write(src[:keep] + os.urandom(len(src) - keep))
        what = f"the light plugin's first {keep} bytes, then random bytes"
    elif kind == "elf-header-flipped":
        data = bytearray(src)
        flips = [(rng.randrange(4, 64), rng.randrange(8)) for _ in range(rng.randint(1, 4))]
        for b, bit in flips:
            data[b] ^= 1 << bit
        open(lib, "wb").write(bytes(data))
        what = f"the light plugin with ELF header bits flipped at (byte, bit) {flips}"
        # A flip may leave a loadable library (a field the loader ignores): then it is the
        # plugin, valid; anything else must be refused.
        due = "refuse-or-ok"
    elif kind == "directory":
        os.mkdir(lib)
    elif kind == "fifo":
        os.mkfifo(lib)
    elif kind == "dev-node":
        lib = rng.choice(["/dev/null", "/dev/zero", "/dev/urandom"])
    elif kind == "symlink-loop":
        os.symlink(lib + ".2", lib)
        os.symlink(lib, lib + ".2")
    elif kind == "symlink-dangling":
        os.symlink("gone.so", lib)
    elif kind == "nonexistent":
        lib = os.path.join(base, rng.choice(["nothere.so", "sub/nothere.so", "nothere.so/"]))
    elif kind == "long-path":
        lib = os.path.join(base, *(["d" * 200] * 50)) + ".so"
        what = f"a path of {len(lib)} characters"
    elif kind == "empty-name":
        lib = ""
    elif kind == "odd-file-name":
        lib = os.path.join(base, rng.choice(ODD_FILE_NAMES))
        shutil.copy(ctx.light, lib)
        due = "ok"
        what = f"the valid light plugin named {os.path.basename(lib)!r}"
    elif kind == "symlink-to-valid":
        os.symlink(ctx.light, lib)
        due = "ok"
        what = "a symbolic link to the valid light plugin"
    elif kind == "named-twice":
        os.symlink(ctx.light, lib)
        argv, needle = command(ctx, rng, [lib, ctx.light, lib], base)
        p = spawn([ctx.mfv] + argv, base, ctx.timeout, env=ctx.env)
        return (f"the valid light plugin named three times (through a link); mfv {shown(argv)}",
                p, judge(ctx, p, "ok", [lib], needle), None)
    elif kind == "prebuilt":
        if not ctx.prebuilt:
            return None, None, None, None
        name = rng.choice(sorted(ctx.prebuilt))
        lib = ctx.prebuilt[name]
        argv = ["--plugin", lib, "list", "kernels"]
        p = spawn([ctx.mfv] + argv, base, ctx.timeout, env=ctx.env)
        due = PREBUILT_LIST.get(name, "refuse")
        return f"mfv {shown(argv)}", p, judge(ctx, p, due, [lib], "cubic-spline"), None
    argv, needle = command(ctx, rng, [lib], base)
    p = spawn([ctx.mfv] + argv, base, ctx.timeout, env=ctx.env)
    if due == "refuse-or-ok":
        due = "ok" if p is not None and p.returncode == 0 else "refuse"
    why = judge(ctx, p, due, [lib], needle)
    return f"plugin = {what}; mfv {shown(argv)}", p, why, None


def valid_name(n):
    """apps/plugins.cpp's rule: letters, digits and - _ . + (at most 64), beginning with a
    letter or digit."""
    return (0 < len(n) <= 64 and n[0].isascii() and n[0].isalnum()
            and all((c.isascii() and c.isalnum()) or c in "-_.+" for c in n))


def heavy_case(ctx, kind, rng, i, base):
    if not ctx.heavy:
        return None, None, None, None
    env = dict(ctx.env)
    lib = ctx.heavy
    libs = [lib]
    if kind in ("heavy-name", "heavy-builtin-name"):
        where = rng.choice(REGISTRIES)
        name = rng.choice(NAMES) if kind == "heavy-name" else BUILTIN[where]
        env.update(MFV_FUZZ_REGISTRY=where, MFV_FUZZ_NAME=name)
        argv = ["--plugin", lib, "list"]
        due = "ok" if valid_name(name) and kind == "heavy-name" else "refuse"
        p = spawn([ctx.mfv] + argv, base, ctx.timeout, env=env)
        why = judge(ctx, p, due, libs, "cubic-spline")
        if not why and p.returncode == 0 and f"  {name}" not in p.stdout:
            why = f"exit 0 but the {where} '{name}' is not listed"
        return (f"the heavy plugin registers the {where} {name[:80]!r} ({len(name)} chars); "
                f"mfv {shown(argv)}"), p, why, None
    if kind == "heavy-hook":
        h = rng.choice(["hook-exit0", "hook-_exit0", "hook-abort", "hook-throw-std",
                        "hook-throw-nonstd"])
        env["MFV_FUZZ_HEAVY"] = h
        argv, needle = command(ctx, rng, libs, base)
        due = "crash" if h == "hook-abort" else "refuse"
        p = spawn([ctx.mfv] + argv, base, ctx.timeout, env=env)
        why = judge(ctx, p, due, libs, needle)
        return f"MFV_FUZZ_HEAVY={h} mfv {shown(argv)}", p, why, None
    if kind == "heavy-factory":
        k = rng.choice(["fuzz-exit", "fuzz-_exit", "fuzz-throw", "fuzz-null"])
        method = rng.choice(["efg", "rkpm", "sph-galerkin"])
        argv = ["--plugin", lib, "run", "laplace-tanh", "-m", method, "-p", f"kernel={k}",
                "-n", "11"]
        p = spawn([ctx.mfv] + argv, base, ctx.timeout, env=env)
        # A failing factory fails the run (exit 1 or 2, not a signal in mfv's code, never 0).
        why = judge(ctx, p, "not-zero", libs, "L2")
        return f"a kernel factory that does {k}; mfv {shown(argv)}", p, why, None
    if kind == "heavy-two-copies":
        copy = os.path.join(base, rng.choice(["libcopy.so", "sub/libheavy.so"]))
        os.makedirs(os.path.dirname(copy), exist_ok=True)
        shutil.copy(lib, copy)
        argv, needle = command(ctx, rng, [lib, copy], base)
        p = spawn([ctx.mfv] + argv, base, ctx.timeout, env=env)
        why = judge(ctx, p, "refuse", [copy], needle)
        if not why and "registered twice" not in p.stderr:
            why = "refused without saying what was registered twice"
        return f"two copies of the heavy plugin; mfv {shown(argv)}", p, why, None
    if kind == "heavy-null-problem":
        env.update(MFV_FUZZ_REGISTRY="problem", MFV_FUZZ_NAME="fuzz-null-problem")
        argv = ["--plugin", lib] + rng.choice([["list", "problems"], ["list", "fuzz-null-problem"],
                                               ["run", "fuzz-null-problem", "-m", "fem", "-n", "5"]])
        p = spawn([ctx.mfv] + argv, base, ctx.timeout, env=env)
        why = judge(ctx, p, "not-zero", libs, "")
        return (f"a problem whose factory returns null; mfv {shown(argv)}"), p, why, None
    raise ValueError(kind)


def main():
    a = arguments(__doc__, "the fixed corpus of the CTest test: every kind once, seed 45",
                  len(KINDS), 45, extra=lambda ap: (only_option(ap), ap.add_argument(
                      "--no-heavy", action="store_true",
                      help="skip the plugin built against mfv's headers (its compile takes a "
                           "minute on a loaded 2-core machine)")))
    ctx = Ctx()
    ctx.mfv, ctx.timeout = os.path.abspath(a.mfv), a.timeout
    a.mfv = ctx.mfv
    ctx.env = dict(os.environ, OMP_NUM_THREADS="1")
    with tempfile.TemporaryDirectory(prefix="mfv-fuzz-plugins-") as w:
        ctx.build = os.path.join(w, "build")
        os.mkdir(ctx.build)
        cxx = [os.environ.get("CXX", "g++"), "-std=c++17", "-O0", "-w"]
        source = LIGHT.replace("@ABI@", abi_macros())
        ctx.light = build(ctx, "liblight", source, cxx)
        ctx.light_no_abi = build(ctx, "liblight-no-abi", source, cxx + ["-DNO_ABI"])
        ctx.light_no_register = build(ctx, "liblight-no-register", source, cxx + ["-DNO_REGISTER"])
        ctx.prebuilt = prebuilt(ctx.mfv)
        ctx.heavy = None
        flags = None if a.no_heavy else heavy_flags(ctx.mfv)
        if flags:
            ctx.heavy = build(ctx, "libheavy", HEAVY, flags)
        p = spawn([ctx.mfv, "--plugin", ctx.light, "list", "kernels"], w, a.timeout, env=ctx.env)
        if p is None or p.returncode != 0:
            print("fuzz_plugins: mfv refuses the valid light plugin:",
                  p and (p.stdout + p.stderr)[-2000:])
            return 1
        print(f"fuzz_plugins: light plugin built; heavy plugin "
              f"{'built' if ctx.heavy else 'skipped (no compile_commands.json or --no-heavy)'}; "
              f"{len(ctx.prebuilt)} prebuilt test plugin(s)", flush=True)
        runners = {}
        for k in KINDS:
            runners[k] = (light_case if k.startswith(("light-", "ctor-", "abi-")) else
                          heavy_case if k.startswith("heavy-") else file_case)

        def runner(kind, rng, i):
            base = os.path.join(w, f"c{i}")
            os.makedirs(base)
            try:
                return runners[kind](ctx, kind, rng, i, base)
            finally:
                shutil.rmtree(base, ignore_errors=True)
        return drive(a, KINDS, runner, "fuzz_plugins.py")


if __name__ == "__main__":
    sys.exit(main())
