#!/usr/bin/env python3
"""Compares the series.csv files of two output trees (two binaries' runs of the same scenes,
e.g. `bench/series_identical.sh OLD NEW --keep DIR` then `series_close.py DIR/old DIR/new`)
numerically, for changes that move round-off but nothing more (a rewritten kernel).

For each column of each series.csv: max |new - old| over the rows, relative to the column's
largest |old| (the column's own scale: a sensitivity of 1e-7 m/Pa is held to its own digits).
Columns whose values are all below --floor (absolute) in both runs count as zero. Prints the
worst column of each file (--verbose: every column, with its scale); exit 0 when every column
is within --rtol, 1 otherwise. A column that is a small difference of large terms (a total
energy, its derivative) or zero up to round-off (a sensitivity the motion does not have) is
held to its own small scale here: read it with --verbose.

  series_close.py OLD_DIR NEW_DIR [--rtol 1e-8] [--floor 1e-300] [--verbose]
"""
import argparse
import csv
import os
import sys


def read(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], [[float(x) for x in r] for r in rows[1:] if r]


def compare(old_path, new_path, floor, verbose=False):
    """Worst (relative difference, column) of two series, or None when their shapes differ."""
    head_o, rows_o = read(old_path)
    head_n, rows_n = read(new_path)
    if head_o != head_n or len(rows_o) != len(rows_n):
        return None
    worst = (0.0, "")
    for c, name in enumerate(head_o):
        col_o = [r[c] for r in rows_o]
        col_n = [r[c] for r in rows_n]
        scale = max(abs(x) for x in col_o + col_n)
        if scale <= floor:
            continue
        diff = max(abs(a - b) for a, b in zip(col_o, col_n)) / scale
        if verbose:
            print(f"    {name:24s} scale {scale:.3e}  max |new - old| {diff * scale:.3e}  relative {diff:.2e}")
        worst = max(worst, (diff, name))
    return worst


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--rtol", type=float, default=1e-8)
    ap.add_argument("--floor", type=float, default=1e-300)
    ap.add_argument("--verbose", action="store_true")
    a = ap.parse_args()
    status, count = 0, 0
    for root, _, files in sorted(os.walk(a.old)):
        if "series.csv" not in files:
            continue
        rel = os.path.relpath(root, a.old)
        new_path = os.path.join(a.new, rel, "series.csv")
        if not os.path.exists(new_path):
            print(f"MISSING in new: {rel}")
            status = 1
            continue
        if a.verbose:
            print(f"{rel}:")
        worst = compare(os.path.join(root, "series.csv"), new_path, a.floor, a.verbose)
        count += 1
        if worst is None:
            print(f"SHAPE differs: {rel}")
            status = 1
            continue
        flag = "" if worst[0] <= a.rtol else "  ABOVE rtol"
        print(f"{rel}: max relative difference {worst[0]:.2e} ({worst[1] or '-'}){flag}")
        if worst[0] > a.rtol:
            status = 1
    print(f"{count} series compared, rtol {a.rtol:g}: {'all within' if status == 0 else 'differences above'}")
    return status


if __name__ == "__main__":
    sys.exit(main())
