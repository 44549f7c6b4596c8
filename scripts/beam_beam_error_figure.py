#!/usr/bin/python3
"""The beam-beam error study as a figure (like the paper's Figs. 9-12 for beam-shell): the relative error
of the section-beam interaction potential's energy and force against the direct volume integration, over
g / R, for parallel and crossed fibers and m = 6 and 12. Runs build/bench/bench_beam_beam_errors (about
20 s of CPU) and draws docs/figures/beam_beam_errors.png.

    scripts/beam_beam_error_figure.py [--bench PATH] [--table FILE]

--table reads a table printed earlier by the bench program instead of running it.
"""
import argparse
import pathlib
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent


def read_rows(text):
    rows = {}
    for line in text.splitlines()[1:]:
        case, m, g, energy, force = line.split()
        rows.setdefault((case, int(float(m))), []).append((float(g), float(energy), float(force)))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bench", default=str(ROOT / "build" / "bench" / "bench_beam_beam_errors"))
    parser.add_argument("--table", help="a table printed by bench_beam_beam_errors")
    args = parser.parse_args()
    text = (pathlib.Path(args.table).read_text() if args.table
            else subprocess.run([args.bench], check=True, capture_output=True, text=True).stdout)
    rows = read_rows(text)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2), sharey=True)
    for ax, case in zip(axes, ("parallel", "crossed")):
        for m, colour in ((6, "C0"), (12, "C3")):
            g, energy, force = zip(*sorted(rows[(case, m)]))
            ax.loglog(g, energy, "o-", color=colour, label=f"energy, m = {m}")
            ax.loglog(g, force, "s--", color=colour, label=f"force, m = {m}")
        ax.loglog([1e-3, 0.5], [1e-3, 0.5], ":", color="grey", label="slope 1")
        ax.set_title(f"{case} fibers (R_A = 1, R_B = 0.6)")
        ax.set_xlabel("g / R_A")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("relative error of SBIP vs volume integral")
    axes[1].legend(fontsize=8)
    fig.tight_layout()
    out = ROOT / "docs" / "figures" / "beam_beam_errors.png"
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
