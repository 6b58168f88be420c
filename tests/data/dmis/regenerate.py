#!/usr/bin/env python3
"""Rewrites turning_sample.dmo and turning_sample_xyzijk.txt from samples/turning/cmm_points.csv:
the same header lines, then one line per point with the CSV's number text copied unchanged
(labels <feature>_<k>, k counting the feature's points from 1); and the three tables of
../tables/ (a ';' table with decimal commas, a tab table, a table under its own column names).
Run from anywhere."""
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


def rewrite(name, keep_prefix, body):
    path = os.path.join(here, name)
    with open(path) as f:
        head = [l for l in f.read().splitlines(True) if keep_prefix(l)]
    with open(path, "w") as f:
        f.write("".join(head) + "".join(body))


counts = {}
dmo = []
for feature, numbers in rows:
    counts[feature] = counts.get(feature, 0) + 1
    dmo.append("FA(%s_%d)=FEAT/POINT,CART,%s\n" % (feature, counts[feature], ",".join(numbers)))
rewrite("turning_sample.dmo", lambda l: not l.startswith("FA(") and not l.startswith("ENDFIL"), dmo + ["ENDFIL\n"])
rewrite("turning_sample_xyzijk.txt", lambda l: l.strip() in ("XYZIJK", "METRIC"),
        ["%s,%s\n" % (feature, ",".join(numbers)) for feature, numbers in rows])

tables = os.path.join(here, "..", "tables")
with open(os.path.join(tables, "turning_sample_semicolon.csv"), "w", newline="") as f:
    f.write("Name;X;Y;Z;I;J;K;Probe\r\n")
    for k, (feature, numbers) in enumerate(rows):
        f.write("%s;%s;T%d\r\n" % (feature, ";".join(n.replace(".", ",") for n in numbers), 1 + k % 2))
with open(os.path.join(tables, "turning_sample_tab.tsv"), "w") as f:
    f.write("feature name\tx\ty\tz\tnx\tny\tnz\n")
    for feature, numbers in rows:
        f.write("%s\t%s\n" % (feature, "\t".join(numbers)))
with open(os.path.join(tables, "turning_sample_own_names.csv"), "w") as f:
    f.write("Pt ID,Meas X,Meas Y,Meas Z,Vec I,Vec J,Vec K\n")
    for feature, numbers in rows:
        f.write("%s,%s\n" % (feature, ",".join(numbers)))
