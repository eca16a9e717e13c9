"""Charts of crackle's speed-vs-accuracy study (docs/benchmarks.md).

Embedded into the crackle binary and run by `crackle bench` as
    python3 -c <this file> RUNS.csv POINTS.csv OUT-DIR
It only draws: every number (errors, seed averages, the Pareto front) comes from the CSVs
that crackle wrote. Needs matplotlib (Debian: python3-matplotlib, installed by scripts/setup).
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

runs_csv, points_csv, out_dir = sys.argv[1], sys.argv[2], sys.argv[3]

ERROR_LABEL = {
    "bar": "relative error of the first break time",
    "film": "relative error of the first-crack time",
    "film-cylinder": "relative error of the first-crack time",
    "film-sphere": "relative error of the first-crack time",
    "arrest": "|arrest height - reference| (tile heights)",
    "mud": "RMS of z over statistics (reference seed spreads)",
    "bark": "RMS of z over statistics (reference seed spreads)",
}
STAT_TITLE = {
    "crack_length_per_area": "crack length per area",
    "mean_fragment_area": "mean fragment area",
    "fragment_area_cv": "fragment area CV",
    "t_junction_fraction": "T share",
    "anisotropy": "anisotropy",
    "tortuosity": "tortuosity",
    "arrest_height": "arrest height",
}
STYLE = {
    "bar1d": ("black", "o"),
    "mass-spring-regular": ("tab:orange", "s"),
    "mass-spring-random": ("tab:brown", "D"),
    "fem-remove": ("tab:green", "^"),
    "fem-split": ("tab:blue", "o"),
    "fem-split-tip": ("tab:purple", "v"),
    "graph-fem": ("tab:red", "P"),
}
BARS = ("Bars: \u00b11 sample standard deviation over the point's seeds of each run's value (the seed spread "
        "of a single run, not the standard error of the mean); a point with one seed has none.")


def number(row, key):
    try:
        return float(row[key])
    except (KeyError, ValueError, TypeError):
        return float("nan")


def spread(row, key):
    """A point's seed spread, 0 when it has none (one seed)."""
    v = number(row, key)
    return v if math.isfinite(v) and v > 0 else 0.0


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


points = read(points_csv)
runs = read(runs_csv)
scenes = []
for p in points:
    if p["scene"] not in scenes:
        scenes.append(p["scene"])


def by_method(rows):
    out = {}
    for r in rows:
        out.setdefault(r["method"], []).append(r)
    for rs in out.values():
        rs.sort(key=lambda r: number(r, "elements"))
    return out


def elements_label(n):
    n = int(round(n))
    if n < 1000:
        return str(n)
    k = n / 1000.0
    return f"{k:.0f}k" if abs(k - round(k)) < 0.05 else f"{k:.1f}k"


def label_points(ax, xs, ys, ns, color):
    for x, y, n in zip(xs, ys, ns):
        if math.isfinite(x) and math.isfinite(y):
            ax.annotate(elements_label(n), (x, y), textcoords="offset points", xytext=(4, 3), fontsize=6,
                        color=color)


def grid(n, height=4.2):
    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(5.2 * cols, height * rows), squeeze=False)
    flat = [a for row in axes for a in row]
    for a in flat[n:]:
        a.set_visible(False)
    return fig, flat[:n]


def save(fig, name, caption):
    fig.text(0.01, 0.005, caption, fontsize=7, ha="left", va="bottom", wrap=True)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    fig.savefig(f"{out_dir}/{name}", dpi=110, metadata={"Software": None})
    plt.close(fig)


def log_bars(ys, sds):
    """Asymmetric bars for a log axis: a bar that would reach zero stops at 1 % of its point."""
    return [[min(s, 0.99 * y) if y > 0 else 0.0 for y, s in zip(ys, sds)], sds]


# === Error against wall time, one curve per method, the Pareto front marked. The y axis spans
# every point: log when the errors cover more than a decade, exact zeros drawn (hollow) on a line
# a decade below the smallest non-zero error.
fig, axes = grid(len(scenes))
zero_drawn = False
for ax, scene in zip(axes, scenes):
    rows = [p for p in points if p["scene"] == scene and math.isfinite(number(p, "error"))]
    errors = [number(p, "error") for p in rows]
    positive = [e for e in errors if e > 0]
    # Log when the errors span more than a decade, include zeros, or are in seed spreads (where
    # the line at one seed spread has to show beside errors of 100).
    use_log = bool(positive) and (max(positive) / min(positive) > 10 or len(positive) < len(errors)
                                  or scene in ("mud", "bark"))
    zero_line = min(positive) / 10 if positive else 1e-12

    def shown(e):
        return e if (e > 0 or not use_log) else zero_line

    for method, rs in by_method(rows).items():
        color, marker = STYLE.get(method, ("gray", "x"))
        xs = [number(r, "wall_seconds") for r in rs]
        ys = [shown(number(r, "error")) for r in rs]
        ysd = [spread(r, "error_sd") for r in rs]
        xsd = [spread(r, "wall_seconds_sd") for r in rs]
        ax.errorbar(xs, ys, yerr=log_bars(ys, ysd) if use_log else ysd, xerr=log_bars(xs, xsd), marker=marker,
                    color=color, label=method, linewidth=1.2, markersize=5, capsize=2, elinewidth=0.8)
        zeros = [(x, y) for x, y, r in zip(xs, ys, rs) if number(r, "error") == 0 and use_log]
        if zeros:
            zero_drawn = True
            ax.scatter([z[0] for z in zeros], [z[1] for z in zeros], s=40, facecolors="white", edgecolors=color,
                       zorder=4)
        label_points(ax, xs, ys, [number(r, "elements") for r in rs], color)
    front = sorted((number(p, "wall_seconds"), shown(number(p, "error"))) for p in rows if p["pareto"] == "1")
    if front:
        ax.step([f[0] for f in front], [f[1] for f in front], where="post", color="gray", linestyle="--",
                linewidth=1, label="Pareto front")
        ax.scatter([f[0] for f in front], [f[1] for f in front], s=110, facecolors="none", edgecolors="black",
                   linewidths=1.0, zorder=5)
    if scene in ("mud", "bark"):
        ax.axhline(1.0, color="gray", linewidth=0.8, linestyle=":", label="one seed spread")
    if use_log and len(positive) < len(errors):
        ax.axhline(zero_line, color="lightgray", linewidth=0.8, linestyle="-")
    ax.set_xscale("log")
    if use_log:
        ax.set_yscale("log")
    else:
        ax.set_ylim(bottom=0)
    ax.set_title(scene)
    ax.set_xlabel("wall time per run (s)")
    ax.set_ylabel(ERROR_LABEL.get(scene, "error"))
    ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    ax.legend(fontsize=7)
save(fig, "error_vs_time.png",
     "Error (seed average) against wall time; labels: starting element count (bar: sub-segments). " + BARS
     + (" Hollow points on the grey line: an error of exactly 0." if zero_drawn else ""))

# === Which statistic is off: z of each compared statistic against the element count, per method
# (mud, bark, arrest), symlog so that z of 0.1 and of 300 both show; the band is |z| <= 1.
stat_panels = []
for scene in scenes:
    rows = [p for p in points if p["scene"] == scene]
    for key in STAT_TITLE:
        column = f"z_{key}"
        if not rows or column not in rows[0]:
            continue
        has_z = any(math.isfinite(number(r, column)) for r in rows)
        listed = any(key in (r.get("not_comparable") or "").split(";") for r in rows)
        if has_z or listed:
            stat_panels.append((scene, key))
fig, axes = grid(max(len(stat_panels), 1), height=3.6)
legend_drawn = False
if not stat_panels:
    axes[0].text(0.5, 0.5, "no scene with a reference in this study", ha="center", va="center")
    axes[0].set_axis_off()
for ax, (scene, key) in zip(axes, stat_panels):
    rows = [p for p in points if p["scene"] == scene]
    column = f"z_{key}"
    drawn = False
    ticks = set()
    lows, highs = [-1.0], [1.0]
    for method, rs in by_method(rows).items():
        color, marker = STYLE.get(method, ("gray", "x"))
        rs = [r for r in rs if math.isfinite(number(r, column))]
        if not rs:
            continue
        drawn = True
        xs = [number(r, "elements") for r in rs]
        ys = [number(r, column) for r in rs]
        sds = [spread(r, column + "_sd") for r in rs]
        ticks.update(xs)
        lows += [y - e for y, e in zip(ys, sds)]
        highs += [y + e for y, e in zip(ys, sds)]
        ax.errorbar(xs, ys, yerr=sds, color=color, linewidth=1.0, capsize=2, elinewidth=0.8, label=method)
        within = [r.get("within_tol_" + key) == "1" for r in rs]
        ax.scatter([x for x, w in zip(xs, within) if w], [y for y, w in zip(ys, within) if w], marker=marker,
                   color=color, s=22, zorder=4)
        ax.scatter([x for x, w in zip(xs, within) if not w], [y for y, w in zip(ys, within) if not w],
                   marker=marker, facecolors="white", edgecolors=color, s=22, zorder=4)
    title = f"{scene}: {STAT_TITLE[key]}"
    if not drawn:
        ax.text(0.5, 0.5, "not comparable:\nthe reference cannot scale it\n(summary.md says why)",
                ha="center", va="center", fontsize=8, transform=ax.transAxes)
        ax.set_title(title)
        ax.set_xticks([])
        ax.set_yticks([])
        continue
    ax.axhspan(-1, 1, color="gray", alpha=0.15, linewidth=0)
    ax.axhline(0, color="gray", linewidth=0.6)
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=1.0)
    ax.set_ylim(2 * min(lows), 2 * max(highs))  # every point and bar inside, with a margin
    ax.set_xticks(sorted(ticks))
    ax.set_xticklabels([elements_label(t) for t in sorted(ticks)], fontsize=7)
    ax.minorticks_off()
    ax.set_title(title)
    ax.set_xlabel("starting elements")
    ax.set_ylabel("z = (x - mean) / seed spread")
    ax.grid(True, which="major", linewidth=0.3, alpha=0.5)
    if not legend_drawn:
        ax.legend(fontsize=6)
        legend_drawn = True
save(fig, "stat_errors.png",
     "Per-statistic error z of the seed average, in the reference's seed spreads (symmetric log axis, linear "
     "within +-1; grey band: |z| <= 1). Filled: within the statistic's tolerance, hollow: outside. " + BARS)

# === Cost against element count, with the fitted slope per method
cost_scenes = [s for s in scenes if s != "bar"] or scenes
fig, axes = grid(len(cost_scenes))
for ax, scene in zip(axes, cost_scenes):
    rows = [p for p in points if p["scene"] == scene]
    ticks = set()
    for method, rs in by_method(rows).items():
        color, marker = STYLE.get(method, ("gray", "x"))
        xs = [number(r, "elements") for r in rs]
        ys = [number(r, "wall_seconds") for r in rs]
        ok = [(x, y) for x, y in zip(xs, ys) if x > 0 and y > 0]
        label = method
        if len(ok) >= 2:
            lx = [math.log(x) for x, _ in ok]
            ly = [math.log(y) for _, y in ok]
            mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
            sxx = sum((x - mx) ** 2 for x in lx)
            if sxx > 0:
                slope = sum((x - mx) * (y - my) for x, y in zip(lx, ly)) / sxx
                label = f"{method} (slope {slope:.2f})"
        sds = [spread(r, "wall_seconds_sd") for r, x, y in zip(rs, xs, ys) if x > 0 and y > 0]
        ax.errorbar([x for x, _ in ok], [y for _, y in ok], yerr=log_bars([y for _, y in ok], sds), marker=marker,
                    color=color, label=label, linewidth=1.2, markersize=5, capsize=2, elinewidth=0.8)
        ticks.update(x for x, _ in ok)
    ax.set_xscale("log")
    ax.set_yscale("log")
    if ticks:
        ax.set_xticks(sorted(ticks))
        ax.set_xticklabels([elements_label(t) for t in sorted(ticks)], fontsize=7)
        ax.minorticks_off()
    ax.set_title(scene)
    ax.set_xlabel("elements (mass-spring: one mass per two)")
    ax.set_ylabel("wall time per run (s)")
    ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    ax.legend(fontsize=7)
save(fig, "cost_vs_elements.png", "Wall time per run (seed average) against the starting element count, with the "
     "least-squares slope of log(wall) on log(elements). " + BARS)

# === Time shares by phase, per method, at each scene's largest resolution every method ran
share_scenes = [s for s in scenes if s not in ("bar",)]
fig, axes = grid(len(share_scenes) or 1)
PHASES = [("solve_seconds", "solve", "tab:blue"), ("stress_seconds", "stress", "tab:orange"),
          ("topology_seconds", "topology", "tab:green"), ("other", "other fracture", "tab:gray"),
          ("setup", "set-up (mesh, assembly)", "tab:olive")]
for ax, scene in zip(axes, share_scenes):
    rows = [p for p in points if p["scene"] == scene]
    methods = by_method(rows)
    common = None
    for rs in methods.values():
        sizes = {int(r["elements"]) for r in rs if number(r, "wall_seconds") > 0}
        common = sizes if common is None else common & sizes
    size = max(common) if common else None
    names, bottoms = [], []
    for i, (method, rs) in enumerate(methods.items()):
        r = next((r for r in rs if int(r["elements"]) == size), None)
        if r is None:
            continue
        wall = number(r, "wall_seconds")
        fracture = number(r, "fracture_seconds")
        parts = {k: number(r, k) for k, _, _ in PHASES[:3]}
        parts = {k: (v if math.isfinite(v) else 0.0) for k, v in parts.items()}
        parts["other"] = max((fracture if math.isfinite(fracture) else 0.0) - sum(parts.values()), 0.0)
        parts["setup"] = max(wall - (fracture if math.isfinite(fracture) else 0.0), 0.0)
        bottom = 0.0
        for key, label, color in PHASES:
            share = 100.0 * parts[key] / wall if wall > 0 else 0.0
            ax.bar(i, share, bottom=bottom, color=color, label=label if not names else None)
            bottom += share
        names.append(method)
    ax.set_xticks(range(len(names)))
    ax.set_xticklabels(names, rotation=30, ha="right", fontsize=7)
    ax.set_ylabel("share of wall time (%)")
    ax.set_title(f"{scene} at {size} elements" if size else scene)
    ax.set_ylim(0, 100)
    if names:
        ax.legend(fontsize=7)
save(fig, "time_shares.png", "Share of the seed-average wall time by phase, at the largest element count every "
     "method of the scene ran (no bars: a breakdown of one mean).")

print(f"charts from {len(runs)} runs, {len(points)} points")
