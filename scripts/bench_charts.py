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
    "mud": "distance to reference (seed spreads)",
    "bark": "distance to reference (seed spreads)",
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
FLOOR = 1e-7  # errors of exactly zero, drawn on a log axis


def number(row, key):
    try:
        return float(row[key])
    except (KeyError, ValueError):
        return float("nan")


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


def grid(n):
    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(5.2 * cols, 4.2 * rows), squeeze=False)
    flat = [a for row in axes for a in row]
    for a in flat[n:]:
        a.set_visible(False)
    return fig, flat[:n]


def save(fig, name):
    fig.tight_layout()
    fig.savefig(f"{out_dir}/{name}", dpi=110, metadata={"Software": None})
    plt.close(fig)


# === Error against wall time, one curve per method, the Pareto front marked
fig, axes = grid(len(scenes))
for ax, scene in zip(axes, scenes):
    rows = [p for p in points if p["scene"] == scene and math.isfinite(number(p, "error"))]
    for method, rs in by_method(rows).items():
        color, marker = STYLE.get(method, ("gray", "x"))
        xs = [number(r, "wall_seconds") for r in rs]
        ys = [max(number(r, "error"), FLOOR) for r in rs]
        ax.plot(xs, ys, marker=marker, color=color, label=method, linewidth=1.2, markersize=5)
    front = sorted((number(p, "wall_seconds"), max(number(p, "error"), FLOOR)) for p in rows if p["pareto"] == "1")
    if front:
        ax.step([f[0] for f in front], [f[1] for f in front], where="post", color="gray", linestyle="--",
                linewidth=1, label="Pareto front")
        ax.scatter([f[0] for f in front], [f[1] for f in front], s=110, facecolors="none", edgecolors="black",
                   linewidths=1.0, zorder=5)
    if scene in ("mud", "bark"):
        ax.axhline(1.0, color="gray", linewidth=0.8, linestyle=":")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_title(scene)
    ax.set_xlabel("wall time per run (s)")
    ax.set_ylabel(ERROR_LABEL.get(scene, "error"))
    ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    ax.legend(fontsize=7)
save(fig, "error_vs_time.png")

# === Cost against element count, with the fitted slope per method
cost_scenes = [s for s in scenes if s != "bar"] or scenes
fig, axes = grid(len(cost_scenes))
for ax, scene in zip(axes, cost_scenes):
    rows = [p for p in points if p["scene"] == scene]
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
        ax.plot([x for x, _ in ok], [y for _, y in ok], marker=marker, color=color, label=label, linewidth=1.2,
                markersize=5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_title(scene)
    ax.set_xlabel("elements (mass-spring: one mass per two)")
    ax.set_ylabel("wall time per run (s)")
    ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    ax.legend(fontsize=7)
save(fig, "cost_vs_elements.png")

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
save(fig, "time_shares.png")

print(f"charts from {len(runs)} runs, {len(points)} points")
