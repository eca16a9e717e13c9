"""Chart of `crackle bench scale` (docs/benchmarks.md, "Scale").

Embedded into the crackle binary and run as
    python3 -c <this file> SCALE.csv OUT-DIR
It only draws what crackle measured: wall time and peak memory against the element count on
tiles of growing area (fixed resolution per layer thickness), and the refinement of the
preset's own tile as error (rms z against the study's reference, in its seed spreads) against wall time.
Needs matplotlib (Debian: python3-matplotlib, installed by scripts/setup).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import NullFormatter, ScalarFormatter  # noqa: E402

scale_csv, out_dir = sys.argv[1], sys.argv[2]
rows = list(csv.DictReader(open(scale_csv)))
builds = []
for r in rows:
    if r["build"] not in builds:
        builds.append(r["build"])
COLOR = {"this build": "tab:blue", "baseline": "tab:gray"}


def series(build, name):
    return [r for r in rows if r["build"] == build and r["series"] == name]


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(lx)
    if n < 2:
        return float("nan")
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


fig, (ax_t, ax_m, ax_e) = plt.subplots(1, 3, figsize=(15, 4.6))
for b in builds:
    s = series(b, "scale")
    n = [float(r["elements"]) for r in s]
    t = [float(r["wall_s"]) for r in s]
    m = [float(r["peak_memory_mib"]) for r in s]
    c = COLOR.get(b, None)
    ax_t.loglog(n, t, "o-", color=c, label=f"{b} (slope {slope(n, t):.2f})")
    ax_m.loglog(n, m, "o-", color=c, label=f"{b} (slope {slope(n, m):.2f})")
    f = series(b, "refinement")
    ax_e.plot([float(r["wall_s"]) for r in f], [float(r["rms_z"]) for r in f], "o-", color=c, label=b)
    for r in f:
        ax_e.annotate(r["elements"], (float(r["wall_s"]), float(r["rms_z"])),
                      textcoords="offset points", xytext=(4, 4), fontsize=7, color=c)
first = series(builds[0], "scale")
if first:
    n0, t0 = float(first[0]["elements"]), float(first[0]["wall_s"])
    n1 = float(first[-1]["elements"])
    for k, style in ((1.0, ":"), (1.1, "--")):
        ax_t.loglog([n0, n1], [t0, t0 * (n1 / n0) ** k], style, color="black", lw=0.8,
                    label=f"slope {k:g} from the first point")
for ax in (ax_t, ax_m):
    ax.set_xticks([float(r["elements"]) for r in first])
ax_t.set_title("Scale: tiles of growing area at 2 elements per h²")
ax_t.set_xlabel("elements")
ax_t.set_ylabel("wall time (s)")
ax_m.set_title("Scale: peak memory")
ax_m.set_xlabel("elements")
ax_m.set_ylabel("peak resident memory (MiB)")
ax_e.set_title("Refinement of the preset's tile")
ax_e.set_xscale("log")
ax_e.set_xlabel("wall time (s)")
ax_e.set_ylabel("error: rms z against the reference (its seed spreads)")
ax_e.axhline(1.0, color="black", lw=0.8, ls=":")
for ax in (ax_t, ax_m, ax_e):
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_formatter(ScalarFormatter())
        axis.set_minor_formatter(NullFormatter())
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(out_dir, "scale.png"), dpi=110)
