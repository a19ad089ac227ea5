#!/usr/bin/env python3
"""Pairs frix's Newton solvers with Siconos's of the same id in `frix bench` runs.csv files.

Writes one row per (problem, pair) with both runs side by side and the time ratio
frix / Siconos where both converged, and prints per pair the number of problems solved by
each and the geometric mean of the ratio over the problems both solve (the goal of issue 3:
<= 0.5 for the Newton solvers).

    newton_summary.py RUNS.csv [RUNS.csv ...] --out PAIRS.csv
"""
import argparse
import csv
import math
import sys

PAIRS = [("nsn-ac", "siconos:NSN_AC"), ("nsn-fb", "siconos:NSN_FB"),
         ("nsn-nm", "siconos:NSN_NM"), ("prox", "siconos:PROX")]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    runs = {}
    order = []
    for path in a.runs:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                key = row["problem"]
                if key not in runs:
                    runs[key] = {}
                    order.append(key)
                runs[key][row["solver"]] = row
    fields = ["problem", "family", "contacts", "pair",
              "frix_status", "frix_iterations", "frix_error", "frix_time",
              "siconos_status", "siconos_iterations", "siconos_error", "siconos_time", "ratio"]
    summary = {p[0]: {"frix": 0, "siconos": 0, "logs": []} for p in PAIRS}
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        for prob in order:
            for fx, sc in PAIRS:
                x, s = runs[prob].get(fx), runs[prob].get(sc)
                if x is None and s is None:
                    continue
                any_row = x or s
                row = {"problem": prob, "family": any_row["family"], "contacts": any_row["contacts"],
                       "pair": fx, "ratio": ""}
                for side, r in (("frix", x), ("siconos", s)):
                    for k in ("status", "iterations", "error", "time"):
                        row[side + "_" + k] = r[k] if r else "missing"
                ok_x = x is not None and x["status"] == "converged"
                ok_s = s is not None and s["status"] == "converged"
                summary[fx]["frix"] += ok_x
                summary[fx]["siconos"] += ok_s
                if ok_x and ok_s:
                    tx = max(float(x["time"]), 1e-6)
                    ts = max(float(s["time"]), 1e-6)
                    row["ratio"] = "%.4g" % (tx / ts)
                    summary[fx]["logs"].append(math.log(tx / ts))
                w.writerow(row)
    print("pair, frix solved, siconos solved, both, geometric mean time frix/siconos")
    for fx, sc in PAIRS:
        s = summary[fx]
        n = len(s["logs"])
        gm = math.exp(sum(s["logs"]) / n) if n else float("nan")
        print("%s vs %s, %d, %d, %d, %.3g" % (fx, sc, s["frix"], s["siconos"], n, gm))
    return 0


if __name__ == "__main__":
    sys.exit(main())
