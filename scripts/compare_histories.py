#!/usr/bin/python3
"""Compares two history.csv files (or two output directories holding one) column by column.

    compare_histories.py REFERENCE NEW [--tolerance 1e-10] [--ignore COLUMN ...]

Rows must agree in number; the columns both files have are compared, each entry within
tolerance x (largest magnitude of that column in the reference) -- a per-column scale, because entries
that are zero up to round-off (a force component of 1e-15 next to components of 1) have no relative
accuracy of their own. Counts (step, iterations) must be equal. Columns only one file has are listed.
Exit code 0 when everything agrees, 1 otherwise, 2 on bad input."""
import argparse
import csv
import sys
from pathlib import Path

COUNTS = {"step", "iterations"}


def read(path):
    p = Path(path)
    if p.is_dir():
        p = p / "history.csv"
    try:
        with open(p, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        print(f"compare_histories: cannot read {p}: {e}", file=sys.stderr)
        sys.exit(2)
    if not rows:
        print(f"compare_histories: {p} is empty", file=sys.stderr)
        sys.exit(2)
    header, data = rows[0], rows[1:]
    return p, header, [[float(x) for x in r] for r in data]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("reference")
    ap.add_argument("new")
    ap.add_argument("--tolerance", type=float, default=1e-10)
    ap.add_argument("--ignore", nargs="*", default=[], help="columns not to compare (e.g. wall times)")
    a = ap.parse_args()
    ref_path, ref_head, ref = read(a.reference)
    new_path, new_head, new = read(a.new)
    ok = True
    if len(ref) != len(new):
        print(f"rows: {len(ref)} in {ref_path}, {len(new)} in {new_path}")
        ok = False
    only = sorted(set(ref_head) ^ set(new_head))
    if only:
        print("columns in one file only (not compared):", ", ".join(only))
    worst = (0.0, None)
    for name in ref_head:
        if name not in new_head or name in a.ignore:
            continue
        i, j = ref_head.index(name), new_head.index(name)
        scale = max((abs(r[i]) for r in ref), default=0.0)
        for k, (r, n) in enumerate(zip(ref, new)):
            diff = abs(r[i] - n[j])
            if name in COUNTS:
                bad = diff != 0
            else:
                bad = diff > a.tolerance * scale
                if scale > 0 and diff / scale > worst[0]:
                    worst = (diff / scale, f"{name} row {k + 1}")
            if bad:
                print(f"{name} row {k + 1}: {r[i]!r} vs {n[j]!r} (difference {diff:.3g}, column scale {scale:.3g})")
                ok = False
    print(f"{'agree' if ok else 'DIFFER'}: {ref_path} vs {new_path}; largest difference "
          f"{worst[0]:.3g} of the column scale ({worst[1]})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
