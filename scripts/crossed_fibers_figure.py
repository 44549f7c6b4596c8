#!/usr/bin/python3
"""Two crossed fibers pulled apart through pull-off: runs examples/crossed-fibers.yaml (arc-length path
through both limit points), draws docs/figures/crossed_fibers.png and prints the limit points that
docs/examples.md quotes.

    scripts/crossed_fibers_figure.py [--fibrane PATH] [--no-run]

The run goes to results/crossed-fibers/ (a finished run is not repeated).
Left panel: the force lifting the upper fiber's ends against their lift (the force-separation curve;
stable branches solid, the unstable one dashed, limit points marked, the jump at pull-off drawn as an
arrow). Right panel: the smallest gap between the fibers along the same path.
"""
import json

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import fibrane_runs  # noqa: E402

ROOT = fibrane_runs.ROOT
CASE = ROOT / "examples" / "crossed-fibers.yaml"


def plot_branches(ax, x, y, unstable, label):
    for i in range(1, len(x)):
        ax.plot(x[i - 1:i + 1], y[i - 1:i + 1], "--" if unstable[i] else "-", color="C0", lw=1.6)
    ax.plot([], [], "-", color="C0", label=label + " (stable)")
    ax.plot([], [], "--", color="C0", label="unstable branch")


def jump_target(u, f, unstable, x, after):
    """The force of the stable branch past index `after` at lift x: where the jump at pull-off lands."""
    for i in range(after, len(u) - 1):
        if not unstable[i + 1] and (u[i] - x) * (u[i + 1] - x) <= 0 and u[i] != u[i + 1]:
            return f[i] + (x - u[i]) / (u[i + 1] - u[i]) * (f[i + 1] - f[i])
    return None


def main():
    args = fibrane_runs.command_line(__doc__, "crossed_fibers_figure.py")
    results = ROOT / "results"
    out = results / "crossed-fibers"
    results.mkdir(parents=True, exist_ok=True)
    if not args.no_run and not fibrane_runs.is_finished(out):
        fibrane_runs.run_case(args.fibrane, "crossed-fibers", CASE.read_text(), results, out)
    h = fibrane_runs.read_csv(out / "history.csv")
    limits = json.loads((out / "summary.json").read_text()).get("limit_points", [])
    u, f, gap = h["end_z"], h["reaction_z"], h["cross_minimum_gap"]
    unstable = h["negative_eigenvalues"] > 0
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    plot_branches(axes[0], u, f, unstable, "arc-length path")
    plot_branches(axes[1], u, np.where(np.isfinite(gap), gap, np.nan), unstable, "arc-length path")
    for lp in limits:
        v = lp["values"]
        print(f"limit point ({lp['kind']} of t): t = {lp['t']:.6g}, lift = {v['end_z']:.6g}, "
              f"force = {v['reaction_z']:.6g}, minimum gap = {v['cross_minimum_gap']:.6g}, step {lp['step']}")
        axes[0].plot(v["end_z"], v["reaction_z"], "o", color="C3")
        axes[1].plot(v["end_z"], v["cross_minimum_gap"], "o", color="C3")
        if lp["kind"] == "maximum":
            target = jump_target(u, f, unstable, v["end_z"], lp["step"] + 1)
            if target is not None:
                axes[0].annotate("", xy=(v["end_z"], target), xytext=(v["end_z"], v["reaction_z"]),
                                 arrowprops=dict(arrowstyle="->", color="C3", lw=1.2))
            axes[0].annotate("pull-off", (v["end_z"], v["reaction_z"]), textcoords="offset points",
                             xytext=(-45, 6), color="C3")
    axes[0].set_ylim(-0.5, 1.15 * f.max())
    axes[0].axhline(0, color="0.6", lw=0.5)
    axes[0].set_xlabel("lift of the upper fiber's ends")
    axes[0].set_ylabel("force lifting the ends $R_z$")
    axes[0].legend(loc="upper left", fontsize=8)
    axes[1].set_xlabel("lift of the upper fiber's ends")
    axes[1].set_ylabel("smallest gap between the fibers")
    fibrane_runs.save(fig, ROOT / "docs" / "figures" / "crossed_fibers.png")


if __name__ == "__main__":
    main()
