#!/usr/bin/env python3
"""Rewrites the two tables of this folder from samples/turning/cmm_points.csv, the CSV's number
text copied (in the semicolon table with its '.' turned into a decimal comma). Run from anywhere."""
import os

here = os.path.dirname(os.path.abspath(__file__))
csv = os.path.join(here, "..", "..", "..", "samples", "turning", "cmm_points.csv")
rows = []
with open(csv) as f:
    for line in f:
        if line.startswith("#") or line.startswith("feature,") or not line.strip():
            continue
        cells = line.rstrip("\n").split(",")
        rows.append((cells[0], cells[1:7]))

with open(os.path.join(here, "turning_sample_semicolon.csv"), "w", newline="") as f:
    f.write("Name;X;Y;Z;I;J;K;Probe\r\n")
    for k, (feature, numbers) in enumerate(rows):
        f.write("%s;%s;T%d\r\n" % (feature, ";".join(n.replace(".", ",") for n in numbers), 1 + k % 2))
with open(os.path.join(here, "turning_sample_tab.tsv"), "w") as f:
    f.write("feature name\tx\ty\tz\tnx\tny\tnz\n")
    for feature, numbers in rows:
        f.write("%s\t%s\n" % (feature, "\t".join(numbers)))
