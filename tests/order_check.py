#!/usr/bin/env python3
"""Largest |column - reference| over the common frames of two flexsens run directories.
    order_check.py RUN_DIR REF_DIR COLUMN      (prints the number)"""
import sys

def read(d, col):
    lines = open(d + "/series.csv").read().split("\n")
    i = lines[0].split(",").index(col)
    return {round(float(l.split(",")[0]), 6): float(l.split(",")[i]) for l in lines[1:] if l}

a, b = read(sys.argv[1], sys.argv[3]), read(sys.argv[2], sys.argv[3])
common = [t for t in a if t in b]
if not common:
    sys.exit("no common frames")
print(max(abs(a[t] - b[t]) for t in common))
