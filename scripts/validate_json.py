#!/usr/bin/env python3
"""Validates mfv's JSON outputs against docs/schemas/*.schema.json (python3-jsonschema).

usage: validate_json.py SCHEMA FILE...   SCHEMA: results or ledger (docs/schemas/<name>.schema.json)
Exit 0 when every FILE is valid, 1 when one is not (each error printed with its JSON path),
2 on bad usage or an unreadable file.
"""
import json
import pathlib
import sys
import warnings

try:
    import jsonschema
except ImportError:
    sys.exit("validate_json.py: python3-jsonschema is missing; run scripts/setup.sh "
             "(apt-get install python3-jsonschema)")

SCHEMAS = pathlib.Path(__file__).resolve().parent.parent / "docs" / "schemas"


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    store = {}
    for path in SCHEMAS.glob("*.schema.json"):
        schema = json.loads(path.read_text())
        store[schema["$id"]] = schema
    name = argv[1]
    path = SCHEMAS / f"{name}.schema.json"
    if not path.exists():
        print(f"validate_json.py: no schema {path}; use results or ledger", file=sys.stderr)
        return 2
    schema = json.loads(path.read_text())
    cls = jsonschema.validators.validator_for(schema)
    cls.check_schema(schema)
    # RefResolver works on Debian 12's jsonschema 4.10 and, deprecated, on later ones.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        resolver = jsonschema.RefResolver.from_schema(schema, store=store)
    validator = cls(schema, resolver=resolver)
    failed = False
    for file in argv[2:]:
        try:
            # Python's json accepts NaN and Infinity; a strict reader must refuse them.
            doc = json.loads(pathlib.Path(file).read_text(),
                             parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
        except (OSError, ValueError) as e:
            print(f"{file}: cannot read as strict JSON: {e}", file=sys.stderr)
            return 2
        errors = sorted(validator.iter_errors(doc), key=lambda e: list(e.absolute_path))
        for e in errors[:20]:
            where = "/" + "/".join(str(p) for p in e.absolute_path)
            message = e.message if len(e.message) < 300 else e.message[:300] + " …"
            print(f"{file}: {where}: {message}", file=sys.stderr)
        failed |= bool(errors)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
