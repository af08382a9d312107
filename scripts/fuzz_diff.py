#!/usr/bin/env python3
"""Fuzz loop over `mfv diff A B`: two verification runs, as report directories, results.json
files or history run ids.

Three real reports are made first (a two-case suite verified twice, and a suite of another
name) with a history of two runs. Each case then diffs a pair built from them:
  identical        a report against itself, its copy or its re-run: exit 0, nothing worse
  worse, better, within, lost, verdict   one number of B moved beyond the tolerance the wrong
                   way (exit 1), the right way (exit 0), within it (exit 0), a number measured
                   in A lost in B (exit 1), a regression verdict PASS -> FAIL (exit 1) or back
  ledger           a ledger verdict that got worse (exit 1) or better (exit 0)
  vanished         every case of B gone, or of A, or of both, or B's cases renamed
  removed          one case of two gone (exit 0 or 1: a removed case is named, not worse)
  suites           two runs of different suites: exit 2
  mutated          a node of results.json replaced: wrong type, null, huge or tiny number,
                   deep nesting (10^3 … 10^6), a long string
  bytes            byte mutations and truncations of results.json
  nan-text         NaN, Infinity or -Infinity as a number's text (not JSON)
  big              a 300 MB results.json (sparse), a valid one padded to 20 MB
  special          a FIFO, /dev/zero, /dev/null, a directory without results.json, a
                   results.json that is a directory, a link loop, a dangling link, an empty
                   file, a nonexistent path, a path of digits (a run id without --history)
  ids              run ids of a history (good, out of range, zero, huge; the history damaged)
  tolerance        --tolerance 0, negative, nan, inf, 1e-16, 1e7, text
Oracles: exit 0, 1 or 2 as documented (exit 1 when something got worse, or when every case
of the earlier run is missing; 2 for bad input, naming the file); never exit 0 when the two
runs have no case and no ledger row in common (nothing compared); the inputs untouched; no
signal, no hang.

  scripts/fuzz_diff.py --mfv build/release/apps/mfv --count 300 --seed 3
  scripts/fuzz_diff.py --mfv build/release/apps/mfv --corpus   # the fixed CTest corpus
  scripts/fuzz_diff.py --mfv build/release/apps/mfv --seed 3 --only 17   # one case
"""
import copy
import json
import os
import shutil
import sys
import tempfile

from fuzz_common import arguments, changed, crash, digest, drive, only_option, shown, spawn

MANIFEST = """[suite]
name = "{name}"
[[case]]
id = "lt/fem"
problem = "laplace-tanh"
method = "fem"
nodes = [21, 41]
[[case]]
id = "lt/efg"
problem = "laplace-tanh"
method = "efg"
nodes = [21, 41]
"""
KINDS = ["identical", "worse", "better", "within", "lost", "verdict", "ledger", "vanished",
         "removed", "suites", "mutated", "bytes", "nan-text", "big", "special", "ids",
         "tolerance"]
LEDGER_VERDICTS = ["reproduced", "reproduced under a stated reading", "partly",
                   "not reproduced", "not reached", "not run", "not yet built"]


class Ctx:
    pass


def load(path):
    return json.load(open(os.path.join(path, "results.json")))


def save(doc, path, text=None):
    with open(path, "w") as f:
        f.write(text if text is not None else json.dumps(doc, indent=1))
    return path


def cases_with_studies(doc):
    return [c for c in doc["cases"] if c.get("study") is not None]


def error_nodes(doc):
    """(case, resolution, norm) of every relative error on the common rule."""
    out = []
    for c in cases_with_studies(doc):
        s = doc["studies"][c["study"]]
        for r in s.get("resolutions", []):
            for norm, e in r.get("errors", {}).get("common", {}).items():
                if isinstance(e, dict) and isinstance(e.get("relative"), (int, float)) and \
                        abs(e["relative"]) > 1e-9:
                    out.append((c["id"], r, norm))
    return out


def common_subjects(a, b):
    """Whether the two documents have a case id or a ledger row in common (something to
    compare); None when either is not a verify run's layout."""
    try:
        ids = lambda d: {c.get("id") for c in d["cases"] if isinstance(c, dict)}
        rows = lambda d: ({r.get("id") for r in d["ledger"]["rows"] if isinstance(r, dict)}
                          if isinstance(d.get("ledger"), dict) else set())
        return bool((ids(a) & ids(b)) - {None}) or bool((rows(a) & rows(b)) - {None})
    except (KeyError, TypeError, AttributeError):
        return None


def paths(doc, prefix=()):
    """Every path of the document (lists and objects), to replace a node at."""
    yield prefix
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from paths(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield from paths(v, prefix + (i,))


def replace(doc, path, value):
    if not path:
        return value
    node = doc
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value
    return doc


def judge(ctx, p, A, B, dA, dB, expect=None, nothing=False, names=()):
    """expect: an exit code, a set of them, or None (0, 1 or 2)."""
    why = crash(p, ctx.timeout)
    if why:
        return why
    if p.returncode not in (0, 1, 2):
        return f"exit {p.returncode} (diff exits 0, 1 or 2)"
    for path, d in ((A, dA), (B, dB)):
        if d is not None:
            c = changed(d, digest(path))
            if c:
                return f"diff changed its input {path}: {c}"
    if p.returncode == 0 and nothing:
        return "exit 0 though the runs have no case or ledger row in common: nothing compared"
    if expect is not None and p.returncode not in (expect if isinstance(expect, set) else {expect}):
        return f"exit {p.returncode}, expected {expect}"
    if p.returncode == 2 and names and not any(n in p.stderr for n in names):
        return f"exit 2 without naming the input ({names[0]})"
    return None


def diff(ctx, base, a, b, extra=(), expect=None, nothing=False, what="", names=None):
    """`names`: what an exit 2 must name (default: either input; a bad option names itself)."""
    argv = ["diff", a, b] + list(extra)
    # The inputs' digests (paths relative to the case's directory, where mfv runs).
    fa, fb = os.path.join(base, a), os.path.join(base, b)
    da = digest(fa) if os.path.lexists(fa) and not fa.startswith("/dev/") else None
    db = digest(fb) if os.path.lexists(fb) and not fb.startswith("/dev/") else None
    p = spawn([ctx.mfv] + argv, base, ctx.timeout)
    why = judge(ctx, p, fa, fb, da, db, expect, nothing,
                names or [x for x in (a, b, os.path.basename(a), os.path.basename(b)) if x])
    return f"{what}; mfv {shown(argv)}", p, why, None


def pair(ctx, rng, base, fn, what, expect=None):
    """A as it is, B a copy of A changed by fn(doc) (in place or returned)."""
    doc = copy.deepcopy(ctx.docA)
    new = fn(doc)
    doc = doc if new is None else new
    bfile = save(doc, os.path.join(base, "B.json"))
    a = ctx.A if rng.random() < 0.5 else os.path.join(ctx.A, "results.json")
    nothing = common_subjects(ctx.docA, doc) is False
    if rng.random() < 0.3:  # the same change seen the other way round
        return diff(ctx, base, bfile, a, expect=None, nothing=nothing, what=what + " (B before A)")
    return diff(ctx, base, a, bfile, expect=expect, nothing=nothing, what=what)


def scale_error(rng, factor):
    def fn(doc):
        nodes = error_nodes(doc)
        cid, r, norm = rng.choice(nodes)
        r["errors"]["common"][norm]["relative"] *= factor
        fn.what = f"{cid}'s {norm} relative error at {r['nodes']} nodes ×{factor}"
    return fn


def kind_case(ctx, kind, rng, i, base):
    if kind == "identical":
        c = rng.choice(["self", "copy", "rerun", "file"])
        if c == "copy":
            b = os.path.join(base, "copy")
            shutil.copytree(ctx.A, b)
        b = {"self": ctx.A, "copy": os.path.join(base, "copy"), "rerun": ctx.B,
             "file": os.path.join(ctx.B, "results.json")}[c]
        return diff(ctx, base, ctx.A, b, expect=0, what=f"identical runs ({c})")
    if kind in ("worse", "better", "within"):
        factor = {"worse": rng.choice([1.06, 1.5, 10.0, 1e6]),
                  "better": rng.choice([0.9, 0.5, 1e-3]),
                  "within": rng.choice([1.04, 0.97, 1.0])}[kind]
        fn = scale_error(rng, factor)
        r = pair(ctx, rng, base, fn, "", expect=1 if kind == "worse" else 0)
        return (f"B = A with {fn.what}" + r[0],) + r[1:]
    if kind == "lost":
        def fn(doc):
            cid, r, norm = rng.choice(error_nodes(doc))
            r["errors"]["common"][norm]["relative"] = None
            fn.what = f"{cid}'s {norm} error at {r['nodes']} nodes null (not measured)"
        r = pair(ctx, rng, base, fn, "", expect=1)
        return (f"B = A with {fn.what}" + r[0],) + r[1:]
    if kind == "verdict":
        to = rng.choice(["FAIL", "PASS", "could not run", "new"])
        frm = rng.choice(["PASS", "FAIL"])
        k = rng.randrange(2)

        def fn(doc):
            doc["cases"][k]["verdict"] = to
        base_doc = copy.deepcopy(ctx.docA)
        base_doc["cases"][k]["verdict"] = frm
        a = save(base_doc, os.path.join(base, "A.json"))
        doc = copy.deepcopy(base_doc)
        fn(doc)
        b = save(doc, os.path.join(base, "B.json"))
        expect = 1 if (to == "FAIL" and frm != "FAIL") else {0, 1} if to not in ("PASS", "FAIL") \
            else 0
        return diff(ctx, base, a, b, expect=expect, what=f"case {k}'s verdict {frm} -> {to}")
    if kind == "ledger":
        ra, rb = rng.sample(LEDGER_VERDICTS[:4], 2)
        da, db = copy.deepcopy(ctx.docA), copy.deepcopy(ctx.docA)
        da["ledger"] = {"rows": [{"id": "fuzz-row", "verdict": ra}]}
        db["ledger"] = {"rows": [{"id": "fuzz-row", "verdict": rb}]}
        if rng.random() < 0.3:
            da["cases"], db["cases"] = [], []  # only the ledger row to compare
        a, b = save(da, os.path.join(base, "A.json")), save(db, os.path.join(base, "B.json"))
        worse = LEDGER_VERDICTS.index(rb) > LEDGER_VERDICTS.index(ra)
        return diff(ctx, base, a, b, expect=1 if worse else 0,
                    what=f"a ledger row {ra!r} -> {rb!r}{' (no cases)' if not da['cases'] else ''}")
    if kind == "vanished":
        c = rng.choice(["B", "A", "both", "renamed"])
        da, db = copy.deepcopy(ctx.docA), copy.deepcopy(ctx.docA)
        if c in ("B", "both"):
            db["cases"] = []
        if c in ("A", "both"):
            da["cases"] = []
        if c == "renamed":
            for x in db["cases"]:
                x["id"] += "-renamed"
        a, b = save(da, os.path.join(base, "A.json")), save(db, os.path.join(base, "B.json"))
        return diff(ctx, base, a, b, expect={1, 2} if c != "A" else None, nothing=True,
                    what=f"every case gone ({c})")
    if kind == "removed":
        k = rng.randrange(2)

        def fn(doc):
            del doc["cases"][k]
        return pair(ctx, rng, base, fn, f"B = A without case {k}", expect={0, 1})
    if kind == "suites":
        a, b = rng.sample([ctx.A, ctx.C], 2)
        return diff(ctx, base, a, b, expect=2, what="two suites")
    if kind == "mutated":
        doc = copy.deepcopy(ctx.docA)
        where = rng.choice(list(paths(doc)))
        value = rng.choice([None, True, "text", "", [], {}, 0, -1, 1e308, -1e308, 5e-324,
                            2 ** 63, -2 ** 63, 2 ** 64 + 1, "NaN", [1, 2], {"x": 1},
                            "x" * 100000, "@@DEEP@@", "@@BIG@@"])
        doc = replace(doc, where, value)
        text = json.dumps(doc)
        if value == "@@DEEP@@":
            depth = rng.choice([1000, 10 ** 4, 10 ** 5, 10 ** 6])
            shape = rng.choice(["[]", "{}"])
            deep = ("[" * depth + "]" * depth) if shape == "[]" else ('{"a":' * depth + "1" +
                                                                      "}" * depth)
            text = text.replace('"@@DEEP@@"', deep)
            value = f"{shape[0]} nested {depth} deep"
        if value == "@@BIG@@":
            text = text.replace('"@@BIG@@"', rng.choice(["1e309", "-1e309", "1e-400",
                                                         "123456789012345678901234567890",
                                                         "-0", "1E+308", "0.0e0"]))
        b = save(None, os.path.join(base, "B.json"), text)
        nothing = None
        try:
            nothing = common_subjects(ctx.docA, json.loads(text)) is False
        except (ValueError, RecursionError):
            pass
        order = rng.random() < 0.5
        a = ctx.A
        return diff(ctx, base, b if order else a, a if order else b, nothing=bool(nothing),
                    what=f"B's node {'/'.join(map(str, where))[:120] or '(root)'} = "
                         f"{str(value)[:60]!r}")
    if kind == "bytes":
        data = bytearray(open(os.path.join(ctx.A, "results.json"), "rb").read())
        ops = []
        for _ in range(rng.randint(1, 5)):
            op = rng.choice(["flip", "truncate", "delete", "insert"])
            j = rng.randrange(len(data) + 1) if data else 0
            ops.append((op, j))
            if op == "flip" and data:
                data[min(j, len(data) - 1)] ^= 1 << rng.randrange(8)
            elif op == "truncate":
                del data[j:]
            elif op == "delete":
                del data[j:j + rng.randint(1, 50)]
            else:
                data[j:j] = bytes([rng.randrange(256)])
        b = os.path.join(base, "B.json")
        open(b, "wb").write(bytes(data))
        nothing = None
        try:
            nothing = common_subjects(ctx.docA, json.loads(bytes(data))) is False
        except ValueError:
            pass
        return diff(ctx, base, ctx.A, b, nothing=bool(nothing),
                    what=f"results.json with byte mutations {ops}")
    if kind == "nan-text":
        def fn(doc):
            cid, r, norm = rng.choice(error_nodes(doc))
            r["errors"]["common"][norm]["relative"] = rng.choice([float("nan"), float("inf"),
                                                                  -float("inf")])
        doc = copy.deepcopy(ctx.docA)
        fn(doc)
        b = save(None, os.path.join(base, "B.json"), json.dumps(doc))  # NaN, Infinity: not JSON
        return diff(ctx, base, ctx.A, b, expect=2, what="a number written as NaN/Infinity")
    if kind == "big":
        b = os.path.join(base, "B.json")
        if rng.random() < 0.5:
            with open(b, "wb") as f:
                f.truncate(300 * 1024 * 1024)  # sparse: no disk
            return diff(ctx, base, ctx.A, b, expect=2, what="a 300 MB results.json (zeros)")
        doc = copy.deepcopy(ctx.docA)
        doc["padding"] = "p" * (20 * 1024 * 1024)
        save(doc, b)
        return diff(ctx, base, ctx.A, b, expect=0, what="results.json padded to 20 MB")
    if kind == "special":
        c = rng.choice(["fifo", "fifo-in-dir", "dev-zero", "dev-null", "empty-dir",
                        "results-dir", "loop", "dangling", "empty-file", "nonexistent",
                        "digits", "digits-dir"])
        s = os.path.join(base, "special")
        if c == "fifo":
            os.mkfifo(s)
        elif c == "fifo-in-dir":
            os.mkdir(s)
            os.mkfifo(os.path.join(s, "results.json"))
        elif c in ("dev-zero", "dev-null"):
            s = "/dev/zero" if c == "dev-zero" else "/dev/null"
        elif c == "empty-dir":
            os.mkdir(s)
        elif c == "results-dir":
            os.makedirs(os.path.join(s, "results.json"))
        elif c == "loop":
            os.symlink(s + "2", s)
            os.symlink(s, s + "2")
        elif c == "dangling":
            os.symlink("gone", s)
        elif c == "empty-file":
            open(s, "w").close()
        elif c == "digits":
            s = "12"
        elif c == "digits-dir":
            s = "7"
            shutil.copytree(ctx.A, os.path.join(base, s))  # a directory named like a run id
            return diff(ctx, base, ctx.A, s, expect=0, what="a report directory named '7'")
        order = rng.random() < 0.5
        return diff(ctx, base, s if order else ctx.A, ctx.A if order else s, expect=2,
                    what=f"{c} as a run")
    if kind == "ids":
        hist = ctx.H
        c = rng.choice(["good", "good", "range", "zero", "huge", "negative", "damaged",
                        "no-history", "mixed"])
        x, y = "1", "2"
        extra = ["--history", hist]
        expect = {0, 1}
        if c == "range":
            y = rng.choice(["3", "999", "2147483648", "999999999999999"])
            expect = 2
        elif c == "zero":
            x = "0"
            expect = 2
        elif c == "huge":
            y = rng.choice(["9" * 16, "9" * 40, "18446744073709551616"])
            expect = 2
        elif c == "negative":
            x = "-1"
            expect = 2
        elif c == "damaged":
            hist = os.path.join(base, "h.sqlite")
            data = bytearray(open(ctx.H, "rb").read())
            cut = rng.randrange(1, len(data))
            open(hist, "wb").write(bytes(data[:cut]) if rng.random() < 0.5 else os.urandom(cut))
            extra = ["--history", hist]
            expect = 2
        elif c == "no-history":
            extra = ["--history", os.path.join(base, "none.sqlite")] if rng.random() < 0.5 else []
            expect = 2
        elif c == "mixed":
            y = ctx.B
        dh = digest(hist)
        # An exit 2 names a run id or the history (a damaged one is the history's fault).
        given = extra[1] if extra else hist
        r = diff(ctx, base, x, y, extra, expect=expect, what=f"run ids ({c})",
                 names=[x, y, given, os.path.basename(given)])
        if not r[2] and changed(dh, digest(hist)):
            return r[0], r[1], f"diff changed the history: {changed(dh, digest(hist))}", None
        return r
    if kind == "tolerance":
        t = rng.choice(["0", "-1", "nan", "inf", "-inf", "1e-16", "1e7", "abc", "", "0.05",
                        "1e-15", "1e6", "0.5"])
        valid = t in ("0.05", "1e-15", "1e6", "0.5")
        return diff(ctx, base, ctx.A, ctx.B, ["--tolerance", t], expect={0, 1} if valid else 2,
                    what=f"--tolerance {t!r}", names=["--tolerance"])
    raise ValueError(kind)


def main():
    a = arguments(__doc__, "the fixed corpus of the CTest test: 60 cases, seed 45", 60, 45,
                  extra=only_option)
    ctx = Ctx()
    ctx.mfv, ctx.timeout = os.path.abspath(a.mfv), a.timeout
    a.mfv = ctx.mfv
    with tempfile.TemporaryDirectory(prefix="mfv-fuzz-diff-") as w:
        ctx.A, ctx.B, ctx.C = (os.path.join(w, n) for n in ("A", "B", "C"))
        ctx.H = os.path.join(w, "h.sqlite")
        for name, rep in (("fuzz-diff", ctx.A), ("fuzz-diff", ctx.B), ("fuzz-other", ctx.C)):
            m = os.path.join(w, name + ".toml")
            with open(m, "w") as f:
                f.write(MANIFEST.format(name=name))
            argv = ["verify", m, "-r", rep, "--history", ctx.H if name == "fuzz-diff" else
                    os.path.join(w, "other.sqlite")]
            p = spawn([ctx.mfv] + argv, w, max(120, a.timeout))
            if p is None or p.returncode != 0:
                print("fuzz_diff: a report run fails:", shown(argv),
                      p and (p.stdout + p.stderr)[-2000:])
                return 1
        ctx.docA = load(ctx.A)
        if len(cases_with_studies(ctx.docA)) < 2 or not error_nodes(ctx.docA):
            print("fuzz_diff: results.json has not the layout this loop expects")
            return 1

        def runner(kind, rng, i):
            base = os.path.join(w, f"c{i}")
            os.makedirs(base)
            try:
                return kind_case(ctx, kind, rng, i, base)
            finally:
                shutil.rmtree(base, ignore_errors=True)
        return drive(a, KINDS, runner, "fuzz_diff.py")


if __name__ == "__main__":
    sys.exit(main())
