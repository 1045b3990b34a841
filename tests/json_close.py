"""Compare two JSON documents: same keys and strings, numbers equal within a tolerance.

Usage: json_close.py EXPECTED ACTUAL [--rel 1e-6] [--abs 1e-9]
Prints every difference as a JSON path and exits 1 if there is any.
"""
import argparse
import json
import math
import sys


def differences(expected, actual, path, rel, abs_tol):
    if isinstance(expected, bool) or isinstance(actual, bool):
        if expected != actual:
            yield f"{path}: {expected!r} != {actual!r}"
    elif isinstance(expected, (int, float)) and isinstance(actual, (int, float)):
        if not math.isclose(expected, actual, rel_tol=rel, abs_tol=abs_tol):
            yield f"{path}: {expected!r} != {actual!r}"
    elif isinstance(expected, dict) and isinstance(actual, dict):
        for key in sorted(expected.keys() | actual.keys()):
            if key not in actual:
                yield f"{path}.{key}: missing"
            elif key not in expected:
                yield f"{path}.{key}: unexpected"
            else:
                yield from differences(expected[key], actual[key], f"{path}.{key}", rel, abs_tol)
    elif isinstance(expected, list) and isinstance(actual, list):
        if len(expected) != len(actual):
            yield f"{path}: {len(expected)} items != {len(actual)}"
        for i, (e, a) in enumerate(zip(expected, actual)):
            yield from differences(e, a, f"{path}[{i}]", rel, abs_tol)
    elif expected != actual:
        yield f"{path}: {expected!r} != {actual!r}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("expected")
    parser.add_argument("actual")
    parser.add_argument("--rel", type=float, default=1e-6)
    parser.add_argument("--abs", type=float, default=1e-9, dest="abs_tol")
    args = parser.parse_args()
    with open(args.expected) as f:
        expected = json.load(f)
    with open(args.actual) as f:
        actual = json.load(f)
    found = list(differences(expected, actual, "$", args.rel, args.abs_tol))
    for line in found[:20]:
        print(f"{args.actual}: {line}", file=sys.stderr)
    if len(found) > 20:
        print(f"... and {len(found) - 20} more", file=sys.stderr)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
