#!/usr/bin/env python3
"""The bench's two charts, drawn with matplotlib from `humandyn bench --json FILE`:

  error_vs_time.svg/.png    every variant's largest relative error against its time per call, random states
                            and realistic motions side by side, with each set's Pareto front
  work_precision.svg/.png   each integrator's end-state angle error against its computing time per
                            simulated second, one line through its steps h, one panel per scenario

usage: python3 tools/plot_bench.py BENCH.json OUT_DIR

Points carry no labels of their own: a legend names the variants and integrators, so no text can land on
another. What the JSON reads as null (a non-finite value) is left out, and the diverged runs are listed
under their panel.
"""

import json
import math
import os
import sys

from chart_files import plt, save
from matplotlib.lines import Line2D

# the variants' families: one colour map each, so that related variants look related, and a marker
# size each, shrinking along the family: variants that compute the same thing (a scene that keeps every
# joint, the dynamic shape) land on the same point, and the later, smaller marker drawn on top leaves
# the other visible around it
FAMILIES = [
    ("inverse dynamics, double", "Blues", 110),
    ("inverse dynamics, float", "Oranges", 60),
    ("forward dynamics, double", "Greens", 60),
    ("forward dynamics, float", "Reds", 60),
    ("scenes", "Purples", 50),
    ("KDL", "Greys", 60),
]
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "<", ">", "h"]
WORKLOADS = [("random", "random states"), ("motions", "realistic motions")]
INTEGRATORS = {"semi-implicit Euler": ("#1f77b4", "o"), "RK4": ("#d62728", "s"), "implicit PD": ("#2ca02c", "^")}


def family(v):
    if v["engine"] != "humandyn":
        return v["engine"]
    if " scene " in f" {v['name']} ":
        return "scenes"
    return f"{v['problem']}, {v['scalar']}"


def finite(x):
    return isinstance(x, (int, float)) and math.isfinite(x)


def pareto_front(points):
    """The points no other beats in both time and error, by increasing time (as a staircase)."""
    front, best = [], math.inf
    for x, y in sorted(points):
        if y < best:
            front.append((x, y))
            best = y
    return front


def error_vs_time(bench, out_dir):
    variants = [v for v in bench["variants"] if finite(v.get("ns_per_call")) and v["ns_per_call"] > 0
                and finite(v.get("max_rel_error"))]
    # one colour and marker per variant name, the same in both panels
    names = []
    for v in variants:
        if v["name"] not in names:
            names.append(v["name"])
    known = [f for f, _, _ in FAMILIES]
    by_family = {}
    for n in names:
        f = family(next(v for v in variants if v["name"] == n))
        by_family.setdefault(f if f in known else "KDL", []).append(n)
    style = {}
    for z, (f, cmap_name, size) in enumerate(FAMILIES):
        members = by_family.get(f, [])
        cmap = plt.get_cmap(cmap_name)
        for i, n in enumerate(members):
            shade = 0.85 - 0.5 * i / max(1, len(members) - 1) if len(members) > 1 else 0.7
            style[n] = (cmap(shade), MARKERS[i % len(MARKERS)], size * 0.88 ** i, 3 + z)

    # an exact zero has no place on a log axis: drawn on a floor line a decade below the smallest error
    positive = [v["max_rel_error"] for v in variants if v["max_rel_error"] > 0]
    floor = 10 ** math.floor(math.log10(min(positive)) - 1) if positive else 1e-16
    exact_zero = any(v["max_rel_error"] <= 0 for v in variants)

    fig, axes = plt.subplots(1, 2, figsize=(12, 5.6), sharey=True)
    model = bench.get("model", "").split(" ")[0]
    fig.suptitle(f"Error against run time ({model} model)" if model else "Error against run time", fontsize=12)
    for ax, (workload, title) in zip(axes, WORKLOADS):
        points = []
        for v in variants:
            if v["states"] != workload:
                continue
            y = max(v["max_rel_error"], floor)
            color, marker, size, z = style[v["name"]]
            ax.scatter(v["ns_per_call"], y, s=size, color=color, marker=marker, edgecolors="black", linewidths=0.5,
                       zorder=z)
            points.append((v["ns_per_call"], y))
        front = pareto_front(points)
        if front:
            xs, ys = zip(*front)
            ax.step(list(xs) + [ax.get_xlim()[1] * 10], list(ys) + [ys[-1]], where="post", color="#555",
                    linestyle="--", linewidth=1, zorder=2)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"{title} ({len(points)} variants)")
        ax.set_xlabel("time per call (ns)")
        ax.grid(True, which="major", color="#ccc", linewidth=0.6)
        ax.grid(True, which="minor", axis="x", color="#eee", linewidth=0.4)
        if exact_zero:
            ax.axhline(floor, color="#999", linewidth=0.6, linestyle=":")
            ax.annotate("exact 0", (0.01, floor), xycoords=("axes fraction", "data"), xytext=(0, 3),
                        textcoords="offset points", fontsize=8, color="#666")
        if points:  # room for the staircase to run out to the right edge
            xmin, xmax = min(p[0] for p in points), max(p[0] for p in points)
            ax.set_xlim(xmin / 1.5, xmax * 1.5)
    axes[0].set_ylabel("max relative error vs long double full model")

    handles = []
    for f, _, _ in FAMILIES:
        for n in by_family.get(f, []):
            color, marker, size, _ = style[n]
            handles.append(Line2D([], [], linestyle="", marker=marker, markersize=size ** 0.5, markerfacecolor=color,
                                  markeredgecolor="black", markeredgewidth=0.5, label=n))
    handles.append(Line2D([], [], color="#555", linestyle="--", linewidth=1, label="Pareto front"))
    fig.legend(handles=handles, loc="center left", bbox_to_anchor=(0.995, 0.5), frameon=False, fontsize=8,
               title="variant", title_fontsize=9)
    fig.tight_layout()
    save(fig, out_dir, "error_vs_time", dpi=150, bbox_inches="tight")


def work_precision(bench, out_dir):
    runs = bench.get("work_precision", [])
    if not runs:
        return False
    scenarios = []
    for r in runs:
        if r["scenario"] not in scenarios:
            scenarios.append(r["scenario"])
    integrators = list(INTEGRATORS) + sorted({r["integrator"] for r in runs} - set(INTEGRATORS))

    # a run that ended where the reference did (an exact 0, e.g. a body at rest without gravity) is drawn on
    # a floor line a decade below the smallest error, as in the error-against-run-time chart
    def drawn(r):
        return r.get("ok") and finite(r.get("q_error")) and r["q_error"] >= 0 and finite(r.get("ms_per_sim_second"))
    positive = [r["q_error"] for r in runs if drawn(r) and r["q_error"] > 0]
    floor = 10 ** math.floor(math.log10(min(positive)) - 1) if positive else 1e-16

    fig, axes = plt.subplots(1, len(scenarios), figsize=(6 * len(scenarios), 5.4), sharey=True, squeeze=False)
    axes = axes[0]
    fig.suptitle("Integration work-precision", fontsize=12)
    exact_zero = any(drawn(r) and r["q_error"] == 0 for r in runs)
    for ax, scenario in zip(axes, scenarios):
        diverged = []
        for integrator in integrators:
            color, marker = INTEGRATORS.get(integrator, ("#7f7f7f", "D"))
            mine = [r for r in runs if r["scenario"] == scenario and r["integrator"] == integrator]
            good = sorted((r for r in mine if drawn(r)), key=lambda r: r["ms_per_sim_second"])
            bad = sorted(r["h"] for r in mine if r not in good)
            if bad:
                diverged.append(f"{integrator}: h = " + ", ".join(f"{h * 1e3:.3g}" for h in bad) + " ms")
            if not good:
                continue
            xs = [r["ms_per_sim_second"] for r in good]
            ys = [max(r["q_error"], floor) for r in good]
            steps = sorted(r["h"] for r in good)
            span = f"h = {steps[0] * 1e3:.3g} ms" if len(steps) == 1 else \
                f"h = {steps[0] * 1e3:.3g} to {steps[-1] * 1e3:.3g} ms"
            ax.plot(xs, ys, color=color, marker=marker, markersize=5, linewidth=1.4, label=f"{integrator}, {span}",
                    zorder=3)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(scenario)
        ax.set_xlabel("computing time per simulated second (ms)")
        if exact_zero:
            ax.axhline(floor, color="#999", linewidth=0.6, linestyle=":")
            ax.annotate("exact 0", (0.01, floor), xycoords=("axes fraction", "data"), xytext=(0, 3),
                        textcoords="offset points", fontsize=8, color="#666")
        ax.grid(True, which="major", color="#ccc", linewidth=0.6)
        ax.grid(True, which="minor", color="#eee", linewidth=0.4)
        # the legend and the notes under the panel, where they cannot cover a line
        handles, _ = ax.get_legend_handles_labels()
        notes = ["one point per step h, the largest on the left"]
        notes += [f"diverged, not drawn: {d}" for d in diverged]
        handles += [Line2D([], [], linestyle="", label=n) for n in notes]
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(-0.02, -0.15), frameon=False, fontsize=8,
                  handlelength=2.5)
    axes[0].set_ylabel("end-state angle error (rad)")
    fig.tight_layout()
    save(fig, out_dir, "work_precision", dpi=150, bbox_inches="tight")
    return True


def main(argv):
    if len(argv) != 3:
        sys.stderr.write("usage: python3 tools/plot_bench.py BENCH.json OUT_DIR\n")
        return 2
    path, out_dir = argv[1], argv[2]
    try:
        with open(path, encoding="utf-8") as f:
            bench = json.load(f)
    except (OSError, ValueError) as e:
        sys.stderr.write(f"plot_bench: {path}: {e}\n")
        return 1
    os.makedirs(out_dir, exist_ok=True)
    error_vs_time(bench, out_dir)
    written = ["error_vs_time"] + (["work_precision"] if work_precision(bench, out_dir) else [])
    print("plot_bench: " + ", ".join(os.path.join(out_dir, f"{w}.svg/.png") for w in written))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
