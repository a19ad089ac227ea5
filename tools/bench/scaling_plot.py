#!/usr/bin/python3
"""The scaling benchmark's plot and tables (tools/bench/granular_scaling.sh).

    scaling_plot.py OUT_DIR BENCHMARKS_MD RUNS_CSV...

Each runs.csv is one campaign (one tolerance) of `frix bench` over piles of the granular
client. Writes OUT_DIR/scaling.png and .svg: solve time against contacts, log-log, one panel
per tolerance, each solver's converged runs with the slope of a least-squares line through
them in the legend. Splices a table per tolerance (time or status per pile, and the slope)
between the scaling markers of BENCHMARKS_MD, after a line naming the tool and the day (UTC).
"""
import csv
import datetime
import math
import os
import sys

BEGIN, END = "<!-- scaling:begin -->", "<!-- scaling:end -->"


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def slope(points):
    """Least-squares slope of log10(time) against log10(contacts); None below 2 points."""
    if len(points) < 2:
        return None
    xs = [math.log10(c) for c, _ in points]
    ys = [math.log10(t) for _, t in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    if sxx == 0.0:
        return None
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx


def campaign(rows):
    tol = rows[0]["tolerance"]
    solvers = list(dict.fromkeys(r["solver"] for r in rows))
    sizes = sorted({int(r["contacts"]) for r in rows})
    cell = {(r["solver"], int(r["contacts"])): r for r in rows}
    return tol, solvers, sizes, cell


def table(tol, solvers, sizes, cell):
    head = "| solver | " + " | ".join(f"{n} contacts" for n in sizes) + " | slope |\n"
    md = f"\nTolerance {float(tol):g}: seconds to converge (or how the run ended), and the slope of log time against log contacts over the converged runs.\n\n"
    md += head + "|---|" + "---:|" * (len(sizes) + 1) + "\n"
    for s in solvers:
        cells, points = [], []
        for n in sizes:
            r = cell.get((s, n))
            if r is None:
                cells.append("-")
            elif r["status"] == "converged":
                t = float(r["time"])
                points.append((n, t))
                cells.append(f"{t:.3g}")
            else:
                cells.append(r["status"].replace("_", " "))
        k = slope(points)
        md += f"| {s} | " + " | ".join(cells) + f" | {'-' if k is None else f'{k:.2f}'} |\n"
    return md


def plot(out_dir, campaigns):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("scaling_plot.py: no matplotlib: plot skipped", file=sys.stderr)
        return
    fig, axes = plt.subplots(1, len(campaigns), figsize=(6.5 * len(campaigns), 4.8), squeeze=False)
    for ax, (tol, solvers, sizes, cell) in zip(axes[0], campaigns):
        for s in solvers:
            points = [(n, float(cell[(s, n)]["time"])) for n in sizes
                      if (s, n) in cell and cell[(s, n)]["status"] == "converged"]
            if not points:
                continue
            k = slope(points)
            label = s if k is None else f"{s} (slope {k:.2f})"
            ax.loglog([p[0] for p in points], [p[1] for p in points], marker="o", label=label)
        ax.set_xlabel("contacts")
        ax.set_ylabel("seconds to converge")
        ax.set_title(f"granular piles, tolerance {float(tol):g}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(out_dir, f"scaling.{ext}"))
    print(f"scaling_plot.py: {out_dir}/scaling.{{png,svg}}")


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    out_dir, md_path, csvs = sys.argv[1], sys.argv[2], sys.argv[3:]
    campaigns = [campaign(read(p)) for p in csvs]
    os.makedirs(out_dir, exist_ok=True)
    plot(out_dir, campaigns)
    day = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
    body = f"\nGenerated on {day} by `tools/bench/granular_scaling.sh`.\n"
    body += "".join(table(*c) for c in campaigns)
    text = open(md_path).read()
    if BEGIN not in text or END not in text:
        sys.exit(f"scaling_plot.py: {md_path} has no {BEGIN} ... {END} markers")
    start, end = text.index(BEGIN) + len(BEGIN), text.index(END)
    with open(md_path, "w") as f:
        f.write(text[:start] + "\n" + body + "\n" + text[end:])
    print(f"scaling_plot.py: tables spliced into {md_path}")


if __name__ == "__main__":
    main()
