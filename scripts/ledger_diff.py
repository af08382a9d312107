#!/usr/bin/env python3
"""What changed between two ledgers (runs/<name>/ledger.json): counts by verdict, every row whose
verdict changed (with the new row's why), rows added and removed, and the rows whose paper value
now falls inside ours ± discretization uncertainty + tolerance and did not fall inside ours ±
tolerance before (and the reverse). Issue 44's closing-note table.

Usage: scripts/ledger_diff.py BEFORE/ledger.json AFTER/ledger.json [--markdown]
"""
import json
import sys


def load(path):
    with open(path) as f:
        d = json.load(f)
    return {r["id"]: r for r in d["rows"]}, d.get("counts", {})


def inside_before(r):
    """Paper inside ours ± tolerance at every compared value (no uncertainty existed then)."""
    if r.get("kind") not in ("published", "measure"):
        return None
    return r.get("verdict", "").startswith("reproduced")


def inside_after(r):
    """Paper inside ours ± (U + tolerance) at every value; None when ours has no U for one
    (null in paper_inside, or false beside an unknown uncertainty in ledgers before the null)."""
    pi = r.get("paper_inside")
    if not pi:
        return None
    us = r.get("uncertainty") or []
    for i, x in enumerate(pi):
        if x is None or (i < len(us) and "uncertainty" not in us[i]):
            return None
    return all(pi)


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    before, cb = load(argv[1])
    after, ca = load(argv[2])
    print("## Counts\n")
    keys = sorted(set(cb) | set(ca))
    print("| verdict | before | after |\n|:--|--:|--:|")
    for k in keys:
        print(f"| {k} | {cb.get(k, 0)} | {ca.get(k, 0)} |")
    print(f"| rows | {len(before)} | {len(after)} |")
    roles = {}
    for r in after.values():
        roles[r.get("role", "claim")] = roles.get(r.get("role", "claim"), 0) + 1
    print(f"\nAfter: {roles.get('claim', 0)} claims of the papers, {roles.get('cost', 0)} claims "
          f"about CPU time (counted apart), {roles.get('check', 0)} of our own checks. "
          f"The counts above are each ledger's own (role claim only, where the ledger has roles).\n")
    print("## Removed rows\n")
    for i in sorted(set(before) - set(after)):
        print(f"- `{i}` (was {before[i]['verdict']})")
    print("\n## Added rows\n")
    for i in sorted(set(after) - set(before)):
        print(f"- `{i}`: {after[i]['verdict']}")
    print("\n## Verdicts that changed\n")
    print("| row | before | after | why (after) |\n|:--|:--|:--|:--|")
    for i in sorted(set(before) & set(after)):
        b, a = before[i]["verdict"], after[i]["verdict"]
        if b != a:
            why = (after[i].get("why") or after[i].get("ours_text") or "").replace(
                "|", "\\|").replace("\n", " ")
            print(f"| `{i}` | {b} | {a} | {why[:300]} |")
    print("\n## Paper value inside ours ± uncertainty (+ tolerance) now, not inside ours ± "
          "tolerance before; and the reverse\n")
    for i in sorted(set(before) & set(after)):
        ib, ia = inside_before(before[i]), inside_after(after[i])
        if ib is None or ia is None or ib == ia:
            continue
        arrow = "now inside" if ia else "no longer inside"
        print(f"- `{i}`: {arrow} ({before[i]['verdict']} → {after[i]['verdict']})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
