#!/usr/bin/python3
"""The settled-steps benchmark's tables (tools/bench/settled_steps.sh).

    settled_table.py BENCHMARKS_MD|- WORK_DIR FAMILY...

WORK_DIR/FAMILY/runs.csv and traces.csv are one `frix bench` campaign each. For every step
(problem) and solver: how the run ended, its iterations, and the time at which it first reached
1e-2, 1e-4, 1e-6 and 1e-8, taken as the bench's work-precision curves take it (the first point
of the run's trace at or below the accuracy, the run's final time for a run without a trace,
and none where the final error is above the accuracy), marked * where a later point of the
trace is above the accuracy (an iterate the solver then moved away from, a stage auto left,
or for Siconos's global solvers their own error); then, per step, auto's time to 1e-4
over the best Siconos solver's. Spliced between the settled markers of BENCHMARKS_MD after a line
naming the tool and the day (UTC), the section and its markers added at the end where they are
not there yet; or printed where BENCHMARKS_MD is '-'.
"""
import csv
import datetime
import math
import os
import sys

BEGIN, END = "<!-- settled:begin -->", "<!-- settled:end -->"
LEVELS = (1e-2, 1e-4, 1e-6, 1e-8)
TIME_FLOOR = 1e-6  # the bench's kTimeFloor: no time is taken as shorter
SECTION = """## Settled steps: piles at or near rest, from the previous step's answer

Time steps of the granular client's pours dumped at rest (with rolling resistance) or late in
the pour (Coulomb friction alone: such piles never rest), each solved from the client's previous
answer (the file's guess 1) by frix and Siconos 4.4 in the same campaign, to 1e-8 with every
run's error-against-time trace. Regenerate with `tools/bench/settled_steps.sh build`; the runs
and the work-precision plots are in [benchmarks/settled/](benchmarks/settled/).

"""
TITLES = {
    "rolling-global": "Rolling resistance, global form (H and M: what the client holds)",
    "rolling-local": "Rolling resistance, local form (W formed)",
    "coulomb-global": "Coulomb friction alone, global form",
    "coulomb-local": "Coulomb friction alone, local form",
}


def read(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def reach_time(run, trace, accuracy):
    """The bench's rule (bench_report.cpp, reach_time)."""
    final_error, t = number(run["error"]), number(run["time"])
    if math.isnan(final_error) and trace:
        final_error = trace[-1][1]
    if not final_error <= accuracy:
        return math.nan
    if math.isnan(t) and trace:
        t = trace[-1][0]
    for elapsed, error in trace:
        if error <= accuracy:
            t = min(t, elapsed)
            break
    limit = number(run.get("time_limit"))
    if math.isfinite(limit) and t > limit:
        return math.nan
    return max(t, TIME_FLOOR)


def rises_above_after(trace, accuracy, t):
    """Whether a point of the trace after time t is above the accuracy."""
    return any(elapsed > t and error > accuracy for elapsed, error in trace)


def seconds(t, mark=False):
    return "-" if math.isnan(t) else f"{t:.3g}" + ("*" if mark else "")


def family_table(work, family):
    runs = read(os.path.join(work, family, "runs.csv"))
    if not runs:
        return ""
    traces = {}
    for row in read(os.path.join(work, family, "traces.csv")):
        traces.setdefault((row["problem"], row["solver"]), []).append((number(row["elapsed"]), number(row["error"])))
    problems = list(dict.fromkeys(r["problem"] for r in runs))
    md = f"\n**{TITLES.get(family, family)}**: tolerance {number(runs[0]['tolerance']):g}, " \
         f"{number(runs[0]['time_limit']):g} s a run, from each step's warm start.\n\n"
    md += "| step | contacts | solver | status | iterations | " + \
          " | ".join(f"to 1e{round(math.log10(a))}" for a in LEVELS) + " |\n|---|---:|---|---|---:|" + "---:|" * len(LEVELS) + "\n"
    ratios = []
    marked = False
    for p in problems:
        rows = [r for r in runs if r["problem"] == p]
        at_1e4 = {}
        for r in rows:
            trace = traces.get((p, r["solver"]), [])
            times = [reach_time(r, trace, a) for a in LEVELS]
            # The marks compare the trace with the time before the floor.
            marks = [not math.isnan(t) and rises_above_after(trace, a, t if t > TIME_FLOOR else 0.0)
                     for t, a in zip(times, LEVELS)]
            marked = marked or any(marks)
            at_1e4[r["solver"]] = times[1]
            md += f"| {p.removesuffix('.hdf5')} | {r['contacts']} | {r['solver']} | {r['status'].replace('_', ' ')} | " \
                  f"{r['iterations'] or '-'} | " + \
                  " | ".join(seconds(t, m) for t, m in zip(times, marks)) + " |\n"
        siconos = [t for s, t in at_1e4.items() if s.startswith("siconos:") and not math.isnan(t)]
        auto = at_1e4.get("auto", math.nan)
        if math.isnan(auto):
            ratios.append(f"{p.removesuffix('.hdf5')}: auto did not reach 1e-4")
        elif siconos:
            ratios.append(f"{p.removesuffix('.hdf5')}: {auto / min(siconos):.3g}")
        elif any(s.startswith("siconos:") for s in at_1e4):
            ratios.append(f"{p.removesuffix('.hdf5')}: Siconos did not reach 1e-4")
    if marked:
        md += "\n\\* a later point of the run's trace is above that accuracy: the solver moved away from that " \
              "iterate (auto keeps its best), or for Siconos's global solvers the point is their own error.\n"
    if ratios:
        md += "\nauto's time to 1e-4 over the best Siconos solver's: " + "; ".join(ratios) + ".\n"
    return md


def main():
    if len(sys.argv) < 4:
        sys.exit("usage: settled_table.py BENCHMARKS_MD|- WORK_DIR FAMILY...")
    target, work, families = sys.argv[1], sys.argv[2], sys.argv[3:]
    day = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
    body = f"\nGenerated on {day} by `tools/bench/settled_steps.sh`.\n"
    body += "".join(family_table(work, f) for f in families)
    if target == "-":
        print(body)
        return
    with open(target) as f:
        text = f.read()
    if BEGIN not in text or END not in text:
        text = text.rstrip("\n") + "\n\n" + SECTION + BEGIN + "\n" + END + "\n"
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    with open(target, "w") as f:
        f.write(head + BEGIN + "\n" + body + "\n" + END + tail)
    print(f"settled_table.py: wrote the settled tables into {target}")


if __name__ == "__main__":
    main()
