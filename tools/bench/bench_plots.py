#!/usr/bin/env python3
"""Plots of a `frix bench` campaign: performance profiles (overall and per family) and
work-precision curves, as PNG and SVG in DIR/plots/.

    frix-bench-plots DIR        (run by `frix bench`; DIR holds runs.csv, profile.csv and
                                 work_precision.csv, which frix computed)

Only draws: every number comes from the CSV files. A solver keeps its colour in every
figure; a frix solver and the Siconos solver with the same id (the same algorithm) share
it, frix solid, Siconos dashed. Exits with status 3 when matplotlib is missing (Debian:
apt-get install python3-matplotlib), so that the caller can say so and go on.
"""
import csv
import math
import os
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    # `frix bench` tries the next python3 and reports itself when none has matplotlib.
    if not os.environ.get("FRIX_BENCH_PLOTS_QUIET"):
        sys.stderr.write("frix-bench-plots: matplotlib is not installed for %s\n" % sys.executable)
    sys.exit(3)

# Fixed colours for the algorithms the project compares, by solver id, so that the figures
# of two campaigns read alike; other ids take the spare colours in id order.
ID_COLOURS = {
    500: "tab:blue", 502: "tab:orange", 503: "tab:olive", 504: "tab:green",
    506: "tab:purple", 507: "tab:brown", 513: "tab:red", 520: "tab:pink",
    523: "tab:cyan", 516: "tab:gray", 508: "gold", 505: "navy", 522: "teal",
    900: "magenta",  # auto, frix's default: drawn thicker too
}
SPARE_COLOURS = ["black", "darkgoldenrod", "slateblue", "darkseagreen", "indianred",
                 "peru", "orchid", "steelblue"]


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


class Styles:
    def __init__(self, runs):
        self.order, self.ids = [], {}
        for r in runs:
            if r["solver"] not in self.ids:
                self.order.append(r["solver"])
                self.ids[r["solver"]] = int(number(r.get("solver_id")) or 0)
        spare = sorted({i for i in self.ids.values() if i not in ID_COLOURS})
        self.colour_of_id = dict(ID_COLOURS)
        for k, i in enumerate(spare):
            self.colour_of_id[i] = SPARE_COLOURS[k % len(SPARE_COLOURS)]

    def __call__(self, solver):
        siconos = solver.startswith("siconos:")
        return dict(color=self.colour_of_id[self.ids[solver]],
                    linestyle="--" if siconos else "-",
                    linewidth=1.6 if siconos else (3.2 if solver == "auto" else 2.2))

    def marker(self, solver):
        return "s" if solver.startswith("siconos:") else "o"


def save(fig, out_dir, name):
    os.makedirs(out_dir, exist_ok=True)
    fig.savefig(os.path.join(out_dir, name + ".png"), dpi=100, bbox_inches="tight")
    fig.savefig(os.path.join(out_dir, name + ".svg"), bbox_inches="tight",
                metadata={"Date": None})
    plt.close(fig)


def profile_axes(ax, steps, style, solvers, tau_max, title):
    for s in solvers:
        pts = steps.get(s, [])
        if not pts:
            continue
        xs = [p[0] for p in pts] + [tau_max]
        ys = [p[1] for p in pts] + [pts[-1][1]]
        ax.step(xs, ys, where="post", label=s, **style(s))
    ax.set_xscale("log", base=2)
    ax.set_xlim(1, tau_max)
    ax.set_ylim(-0.02, 1.02)
    ax.set_title(title, fontsize="medium")
    ax.grid(True, which="major", alpha=0.3)


def main():
    if len(sys.argv) != 2:
        sys.stderr.write("usage: frix-bench-plots DIR\n")
        return 2
    d = sys.argv[1]
    runs = read_csv(os.path.join(d, "runs.csv"))
    profile = read_csv(os.path.join(d, "profile.csv"))
    wp = read_csv(os.path.join(d, "work_precision.csv"))
    if not runs:
        sys.stderr.write("frix-bench-plots: %s/runs.csv has no runs\n" % d)
        return 1
    plt.rcParams["svg.fonttype"] = "none"  # text stays text: smaller, searchable SVG
    plt.rcParams["svg.hashsalt"] = "frix-bench"  # stable ids: regenerated files diff cleanly
    style = Styles(runs)
    solvers = style.order
    tol = number(runs[0].get("tolerance"))
    limit = number(runs[0].get("time_limit"))
    setting = "tolerance %g, time limit %g s" % (tol, limit)
    out = os.path.join(d, "plots")

    # scope -> solver -> [(tau, rho)], and the number of problems of each scope
    steps, sizes = {}, {}
    for row in profile:
        steps.setdefault(row["scope"], {}).setdefault(row["solver"], []).append(
            (number(row["tau"]), number(row["rho"])))
        sizes[row["scope"]] = int(number(row["problems"]))
    taus = [t for sc in steps.values() for pts in sc.values() for t, _ in pts]
    tau_max = max(2.0, 1.5 * max(taus)) if taus else 2.0

    fig, ax = plt.subplots(figsize=(8, 5))
    profile_axes(ax, steps.get("all", {}), style, solvers, tau_max,
                 "Performance profile, %d problems (%s)" % (sizes.get("all", 0), setting))
    ax.set_xlabel("τ: time / best time on the problem")
    ax.set_ylabel("ρ(τ): share of problems solved within τ")
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize="small")
    save(fig, out, "profile")

    families = [f for f in steps if f != "all"]
    if families:
        cols = min(4, len(families))
        rows = (len(families) + cols - 1) // cols
        fig, axes = plt.subplots(rows, cols, figsize=(3.4 * cols, 2.7 * rows), squeeze=False,
                                 sharey=True)
        for k, fam in enumerate(families):
            ax = axes[k // cols][k % cols]
            profile_axes(ax, steps[fam], style, solvers, tau_max, "%s (%d)" % (fam, sizes[fam]))
        for k in range(len(families), rows * cols):
            axes[k // cols][k % cols].set_visible(False)
        for r in range(rows):
            axes[r][0].set_ylabel("ρ(τ)")
        for c in range(cols):
            axes[rows - 1][c].set_xlabel("τ")
        handles, labels = axes[0][0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="lower center", ncol=min(7, len(labels)),
                   fontsize="small", bbox_to_anchor=(0.5, -0.02 - 0.03 * math.ceil(len(labels) / 7)))
        fig.suptitle("Performance profiles per family (%s)" % setting)
        fig.tight_layout()
        save(fig, out, "profile_families")

    # work precision: accuracy -> time to reach it (geometric mean over the problems, the
    # unreached counted at the time limit), and the share of problems that reached it
    curves = {}
    for row in wp:
        if row["scope"] != "all":
            continue
        curves.setdefault(row["solver"], []).append(
            (number(row["accuracy"]), number(row["geomean_time_penalized"]),
             int(number(row["reached"])), int(number(row["problems"]))))
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 4.8))
    for s in solvers:
        pts = sorted(curves.get(s, []), reverse=True)
        if not pts:
            continue
        acc = [p[0] for p in pts]
        st = style(s)
        left.plot(acc, [p[1] for p in pts], marker=style.marker(s), markersize=4, label=s, **st)
        right.plot(acc, [p[2] / max(p[3], 1) for p in pts], marker=style.marker(s),
                   markersize=4, label=s, **st)
    for ax in (left, right):
        ax.set_xscale("log")
        ax.invert_xaxis()
        ax.set_xlabel("accuracy reached (frix's relative error)")
        ax.grid(True, which="major", alpha=0.3)
    left.set_yscale("log")
    left.set_ylabel("time to reach it [s], geometric mean\n(not reached: the time limit)")
    left.set_title("Work-precision (%s)" % setting, fontsize="medium")
    right.set_ylim(-0.02, 1.02)
    right.set_ylabel("share of problems that reached it")
    right.set_title("Reached within the time limit", fontsize="medium")
    right.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize="small")
    fig.tight_layout()
    save(fig, out, "work_precision")
    print("frix-bench-plots: %s/{profile,profile_families,work_precision}.{png,svg}" % out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
