#!/usr/bin/python3
"""Snap-to-contact and pull-off of a fiber above a membrane: runs examples/snap-to-contact.yaml (arc-length
path through both limit points) and examples/snap-to-contact-dynamic.yaml (the jump in, by implicit
dynamics), then draws docs/figures/snap_to_contact.png and prints the numbers docs/examples.md quotes.

    scripts/snap_figures.py [--jobs 2] [--quick] [--fibrane PATH] [--no-run]

Runs go to results/snap/<name>/ (a finished run is not repeated). --quick coarsens both cases (20 beam
elements, 6 x 3 shell elements): a smoke test of the chain.
Left panel: the support force of the beam ends against their height: the arc-length path (stable
branches solid, the unstable one dashed, limit points marked), the jumps that loading (snap-in) and
unloading (pull-off) take at the two limit points, and the dynamic run. Right panel: the dynamic run's
energy account (kinetic, strain, interaction, work of the prescribed motion) and the balance's drift.
"""
import json
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import fibrane_runs  # noqa: E402

ROOT = fibrane_runs.ROOT
CASES = {"arc_length": ROOT / "examples" / "snap-to-contact.yaml",
         "dynamic": ROOT / "examples" / "snap-to-contact-dynamic.yaml"}
QUICK_EDITS = [("elements: 50", "elements: 20"), ("elements: [10, 5]", "elements: [6, 3]")]


def case_text(path, quick):
    text = path.read_text()
    for old, new in (QUICK_EDITS if quick else []):
        if text.count(old) != 1:
            sys.exit(f"{path.name}: edit target must occur once: {old!r}")
        text = text.replace(old, new)
    return text


def run(args, results):
    def run_one(name, _):
        out = results / name
        if not fibrane_runs.is_finished(out):
            fibrane_runs.run_case(args.fibrane, name, case_text(CASES[name], args.quick), results, out)
    fibrane_runs.run_all({n: None for n in CASES}, run_one, args.jobs)


def limit_points(directory):
    return json.loads((directory / "summary.json").read_text()).get("limit_points", [])


def jump_target(path, end_z, after):
    """The reaction of the path's other stable branch at end height end_z (first crossing past index
    `after` of a stable stretch): where a quasi-static jump at a limit point lands."""
    u, f, neg = path["end_z"], path["reaction_z"], path["negative_eigenvalues"]
    for i in range(after, len(u) - 1):
        if neg[i + 1] == 0 and neg[i] <= 0 and (u[i] - end_z) * (u[i + 1] - end_z) <= 0 and u[i] != u[i + 1]:
            w = (end_z - u[i]) / (u[i + 1] - u[i])
            return f[i] + w * (f[i + 1] - f[i])
    return None


def plot_path(ax, path, limits, dynamic):
    u, f, neg = path["end_z"], path["reaction_z"], path["negative_eigenvalues"]
    unstable = neg > 0
    for i in range(1, len(u)):
        style = "--" if unstable[i] else "-"
        ax.plot(u[i - 1:i + 1], f[i - 1:i + 1], style, color="C0", lw=1.6)
    ax.plot([], [], "-", color="C0", label="arc-length path (stable)")
    ax.plot([], [], "--", color="C0", label="unstable branch")
    for k, lp in enumerate(limits):
        x, y = lp["values"]["end_z"], lp["values"]["reaction_z"]
        ax.plot(x, y, "o", color="C3")
        target = jump_target(path, x, lp["step"] + 1 if k == 0 else 0)
        if target is not None:
            ax.annotate("", xy=(x, target), xytext=(x, y), arrowprops=dict(arrowstyle="->", color="C3", lw=1.2))
        ax.annotate("snap-in" if lp["kind"] == "maximum" else "pull-off", (x, y), textcoords="offset points",
                    xytext=(6, -12 if lp["kind"] == "maximum" else 6), color="C3")
    if dynamic is not None:
        ax.plot(dynamic["end_z"], dynamic["reaction_z"], color="C1", lw=0.8, alpha=0.8, label="dynamic run (lowering)")
    # The window of the quasi-static path; the dynamic run's ends press on below z0 (forces down to ~-10).
    ax.set_xlim(u.min() - 0.05, u.max() + 0.02)
    ax.set_ylim(-1.0, 1.3 * f.max())
    ax.set_xlabel("height of the beam ends $z$ (membrane mid-surface: 0)")
    ax.set_ylabel("support force of the ends $R_z$")
    ax.axhline(0, color="0.6", lw=0.5)
    ax.legend(loc="lower left", fontsize=8)


def plot_energy(ax, h):
    t = h["t"]
    # Potential energies relative to the start; the balance is E_kin + U + Pi_int - W - W_presc (+ damping).
    ax.plot(t, h["kinetic_energy"], label="kinetic")
    ax.plot(t, h["strain_energy"] - h["strain_energy"][0], label="strain (from start)")
    ax.plot(t, h["interaction_energy"] - h["interaction_energy"][0], label="interaction (from start)")
    ax.plot(t, h["prescribed_work"], label="work of the prescribed motion")
    ax.plot(t, h["energy_balance"] - h["energy_balance"][0], "k", lw=1.2, label="balance drift")
    ax.set_xlabel("time")
    ax.set_ylabel("energy")
    ax.legend(fontsize=8)


def report(path, limits, dynamic):
    for lp in limits:
        v = lp["values"]
        print(f"limit point ({lp['kind']} of t): t = {lp['t']:.6g}, end z = {v['end_z']:.6g}, "
              f"R_z = {v['reaction_z']:.6g}, mid z = {v['mid_z']:.6g}, step {lp['step']}")
    if dynamic is not None:
        drift = np.abs(dynamic["energy_balance"] - dynamic["energy_balance"][0]).max()
        adhesion = np.abs(dynamic["interaction_energy"]).max()
        print(f"dynamic run: {len(dynamic['t']) - 1} steps to t = {dynamic['t'][-1]:.4g}; largest drift of the energy "
              f"balance {drift:.3e} = {drift / adhesion:.2e} of the largest |interaction energy| {adhesion:.4g}; "
              f"dt from {np.diff(dynamic['t']).min():.3g} to {np.diff(dynamic['t']).max():.3g}")


def main():
    args = fibrane_runs.command_line(__doc__, "snap_figures.py")
    results = ROOT / "results" / ("snap-quick" if args.quick else "snap")
    results.mkdir(parents=True, exist_ok=True)
    if not args.no_run:
        run(args, results)
    path = fibrane_runs.read_csv(results / "arc_length" / "history.csv")
    limits = limit_points(results / "arc_length")
    dynamic_file = results / "dynamic" / "history.csv"
    dynamic = fibrane_runs.read_csv(dynamic_file) if dynamic_file.exists() else None
    report(path, limits, dynamic)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    plot_path(axes[0], path, limits, dynamic)
    if dynamic is not None:
        plot_energy(axes[1], dynamic)
    name = "snap_to_contact_quick.png" if args.quick else "snap_to_contact.png"
    fibrane_runs.save(fig, (results if args.quick else ROOT / "docs" / "figures") / name)


if __name__ == "__main__":
    main()
