#!/usr/bin/env python3
"""auto against the best solver of each library, problem by problem (issue 8's yardstick).

    tools/bench/auto_summary.py RUNS.csv [RUNS.csv ...]

Reads `frix bench` runs.csv files (rows of several campaigns may be given together; a
problem must not appear in two of them) and prints Markdown: for each problem, auto's status
and time, the best Siconos 4.4 solver's and the best other frix solver's (chosen after the
fact, among the runs that converged), and two geometric means of auto's time over the best
Siconos time: over the problems both solved, and over all problems with a problem nobody in
Siconos solved counted at the campaign's time limit (a lower bound of Siconos's time there)."""
import csv
import math
import sys


def converged(row):
    try:
        return row["status"] == "converged" and float(row["error"]) <= float(row["tolerance"]) * (1 + 1e-9)
    except ValueError:
        return False


def best(rows, pick):
    runs = [(float(r["time"]), r["solver"]) for r in rows if pick(r["solver"]) and converged(r)]
    return min(runs) if runs else None


def geomean(xs):
    return math.exp(sum(math.log(x) for x in xs) / len(xs)) if xs else float("nan")


def main(paths):
    problems = {}
    for path in paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                problems.setdefault(row["problem"], []).append(row)
    lines = ["| problem | contacts | auto | best Siconos 4.4 | best other frix | auto / Siconos |",
             "|---|---|---|---|---|---|"]
    both, bounded = [], []
    auto_solved = 0
    for name in sorted(problems, key=lambda p: (int(problems[p][0]["contacts"]), p)):
        rows = problems[name]
        auto = [r for r in rows if r["solver"] == "auto"]
        if not auto:
            continue
        a = auto[0]
        a_ok = converged(a)
        auto_solved += a_ok
        sic = best(rows, lambda s: s.startswith("siconos:"))
        frx = best(rows, lambda s: not s.startswith("siconos:") and s != "auto")
        limit = float(a["time_limit"])
        t_auto = float(a["time"]) if a_ok else None
        ratio = ""
        if t_auto is not None and sic:
            both.append(t_auto / sic[0])
            bounded.append(t_auto / sic[0])
            ratio = "%.2f" % (t_auto / sic[0])
        elif t_auto is not None:
            bounded.append(t_auto / limit)
            ratio = "< %.2g (Siconos: none in %g s)" % (t_auto / limit, limit)
        fmt = lambda b: "%s %.3g s" % (b[1], b[0]) if b else "none"
        auto_cell = "%.3g s" % t_auto if a_ok else "%s (error %.2e)" % (a["status"], float(a["error"]))
        lines.append("| %s | %s | %s | %s | %s | %s |" % (name, a["contacts"], auto_cell, fmt(sic), fmt(frx), ratio))
    lines.append("")
    lines.append("auto converged on %d of %d problems. Geometric mean of auto's time over the best "
                 "Siconos time: **%.3f** over the %d problems both solved; **%.3f** over the %d "
                 "problems auto solved, a problem no Siconos solver solved counted at the time "
                 "limit." % (auto_solved, sum(1 for p in problems.values() if any(r["solver"] == "auto" for r in p)),
                             geomean(both), len(both), geomean(bounded), len(bounded)))
    print("\n".join(lines))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
