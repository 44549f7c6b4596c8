#!/usr/bin/python3
"""Turn the CSV tables of `fibrane study` into PNG plots (one per figure of paper Sec. 4).

usage: /usr/bin/python3 scripts/plot_study.py DIR   (reads DIR/figN.csv, writes DIR/figN.png)
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [{k: float(v) for k, v in r.items()} for r in rows]


def curves(rows, keys):
    groups = {}
    for r in rows:
        groups.setdefault(tuple(r[k] for k in keys), []).append(r)
    return groups


def relative_error_plot(rows, title, path, column, extra=None):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for (radius, h), rs in sorted(curves(rows, ["shell_radius", "thickness"]).items()):
        g = [r["gap"] for r in rs]
        line, = ax.semilogx(g, [100 * r[column] for r in rs], label=f"R/R_D={radius:g}, h/R_D={h:g}")
        if extra and extra in rs[0]:
            ax.axhline(100 * rs[0][extra], color=line.get_color(), ls=":", lw=0.8)
    ax.set_xlabel("g / R_D")
    ax.set_ylabel("relative force error [%]")
    ax.set_title(title)
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main(directory):
    titles = {
        "fig6": ("Fig. 6: disk-sphere vs disk-spherical shell", "relative_error", None),
        "fig7": ("Fig. 7: D-PT vs disk-spherical shell (dotted: Eq. 58)", "relative_error", "eq58_limit"),
        "fig8": ("Fig. 8: D-PT vs disk-cylindrical shell, parallel", "relative_error", None),
        "fig9": ("Fig. 9: D-PT vs disk-cylindrical shell, perpendicular", "relative_error", None),
    }
    for name, (title, column, extra) in titles.items():
        path = os.path.join(directory, name + ".csv")
        if os.path.exists(path):
            relative_error_plot(read(path), title, os.path.join(directory, name + ".png"), column, extra)
    path = os.path.join(directory, "fig11.csv")
    if os.path.exists(path):
        rows = read(path)
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        g = [r["gap"] for r in rows]
        ax.semilogx(g, [r["scaling_exact"] for r in rows], "k-", label="exact (C-SS cubature)")
        ax.semilogx(g, [r["scaling_sbs"] for r in rows], "r--", label="SBS, exact D-PT law")
        ax.semilogx(g, [r["scaling_sbs_cos1"] for r in rows], "b:", label="SBS, cos a = 1")
        ax.set_xlabel("g0 / R_C")
        ax.set_ylabel("force scaling factor S")
        ax.set_title("Fig. 11: R_SS = 10, R_C = 1, h = 1")
        ax.grid(True, which="both", lw=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(directory, "fig11.png"), dpi=130)
        plt.close(fig)
    path = os.path.join(directory, "fig12.csv")
    if os.path.exists(path):
        rows = read(path)
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        for (radius, h), rs in sorted(curves(rows, ["shell_radius", "thickness"]).items()):
            g = [r["gap"] for r in rs]
            line, = ax.semilogx(g, [100 * r["error_sbs"] for r in rs], label=f"R_SS/R_C={radius:g}, h/R_C={h:g}")
            ax.semilogx(g, [100 * r["error_sbs_cos1"] for r in rs], "--", color=line.get_color())
        ax.set_xlabel("g0 / R_C")
        ax.set_ylabel("relative SBS force error [%]")
        ax.set_title("Fig. 12: solid exact D-PT, dashed cos a = 1")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(directory, "fig12.png"), dpi=130)
        plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
