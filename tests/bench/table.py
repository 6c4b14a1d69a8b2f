#!/usr/bin/env python3
"""Prints a CSV file as aligned columns (the benches' tables, without util-linux's `column`,
which a bare machine lacks). Usage: table.py FILE.csv"""
import csv
import sys

lines = list(csv.reader(open(sys.argv[1])))
widths = [max(len(line[k]) for line in lines if k < len(line)) for k in range(len(lines[0]))]
for line in lines:
    print("  ".join(c.ljust(w) for c, w in zip(line, widths)).rstrip())
