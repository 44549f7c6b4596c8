#!/usr/bin/python3
"""Peeling of an adhering beam from a shell (paper Sec. 6.1): run every variant, then draw Figs. 15, 17-20.

    scripts/peeling_figures.py [--jobs N] [--only NAME] [--quick] [--fibrane PATH]

Every variant is a text edit of examples/peeling.yaml, run into results/peeling/<variant>/ (a variant whose
summary.json says "completed" is not run again, so an interrupted call resumes). The PNGs go to docs/figures/.
--quick uses coarse meshes and large steps (a smoke test of the whole chain, runs and PNGs into
results/peeling-quick/). --only A,B runs only the variants whose name contains A or B (figures are drawn from all finished runs).
"""
import json
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import fibrane_runs  # noqa: E402

ROOT = fibrane_runs.ROOT
EXAMPLE = ROOT / "examples" / "peeling.yaml"

# Mesh texts as they appear in the example (beam elements, shell elements [u, v]).
BASE_MESH = ("elements: 100", "elements: [20, 10]")
MESHES = {"50x10x5": (50, 10, 5), "100x20x10": (100, 20, 10), "150x30x15": (150, 30, 15)}
QUICK_MESHES = {"20x6x4": (20, 6, 4), "30x8x4": (30, 8, 4), "40x10x6": (40, 10, 6)}
# The paper's finest mesh, 200 x 40 x 20, needs ~8 s per Newton iteration with one thread on the shared
# 2-core build machine (~1 h to pull-off, docs/examples.md); 150 x 30 x 15 is the finest used here.


def mesh_edits(beam, shell_u, shell_v):
    return [(BASE_MESH[0], f"elements: {beam}"), (BASE_MESH[1], f"elements: [{shell_u}, {shell_v}]")]


def variants(quick):
    """name -> list of (old text, new text) edits of the example; the base case is the FF run at 100x20x10."""
    meshes = QUICK_MESHES if quick else MESHES
    middle = list(meshes)[1]
    v = {}
    for name, mesh in meshes.items():
        v[f"mesh_{name}"] = mesh_edits(*mesh) if name != "100x20x10" else []
    base = v[f"mesh_{middle}"]
    v["formulation_RF1"] = base + [("formulation: FF", "formulation: RF1")]
    v["formulation_RF2"] = base + [("formulation: FF", "formulation: RF2")]
    # Fig. 19: E_B / E_S with RF1 (as the paper), E_S = 1000 fixed; the beam's material line is the second one.
    for ratio, young in (("0.5", "500"), ("2", "2000")):
        v[f"youngratio_{ratio}"] = base + [("formulation: FF", "formulation: RF1"), ("BEAM_YOUNG", young)]
    for s in ("0.5", "2"):
        v[f"strength_{s}"] = base + [("strength: 1}", f"strength: {s}}}")]
    return v


# Names used by the figures for the runs that are shared with the base case.
def alias(name, quick):
    middle = "mesh_" + list(QUICK_MESHES if quick else MESHES)[1]
    return {"formulation_FF": middle, "strength_1": middle, "youngratio_1": "formulation_RF1"}.get(name, name)


def case_text(edits, quick):
    text = EXAMPLE.read_text()
    # Let late pull-offs (strength 2, stiff beam) finish: the stop condition ends every run at pull-off.
    edits = edits + [("t_end: 0.3", "t_end: 0.6"), ("vtk_every: 10", "vtk_every: 50")]
    if quick:
        edits = edits + [("dt_max: 1.0e-3", "dt_max: 4.0e-3"), ("dt: 2.0e-5", "dt: 1.0e-4")]
    for old, new in edits:
        if old == "BEAM_YOUNG":  # the second 'young: 1000' is the beam's
            at = text.find("young: 1000", text.find("beams:"))
            text = text[:at] + f"young: {new}" + text[at + len("young: 1000"):]
            continue
        if old not in text:
            sys.exit(f"peeling_figures: '{old}' not found in {EXAMPLE}; the example changed")
        text = text.replace(old, new, 1)
    return text


def is_completed(directory):
    """Finished runs: stopped by the energy condition or t_end ("completed"), or stalled at the pull-off
    limit point (see docs/examples.md)."""
    return fibrane_runs.is_finished(directory, min_steps=10)


def run_variant(name, edits, results, fibrane, quick):
    out = results / name
    if is_completed(out):
        print(f"  {name}: completed earlier, kept")
        return
    fibrane_runs.run_case(fibrane, name, case_text(edits, quick), results, out)


def read_history(directory):
    return fibrane_runs.read_csv(directory / "history.csv")


def read_interaction(directory, step):
    return fibrane_runs.read_csv(directory / "interaction" / f"adhesion_{step:06d}.csv")


def characteristic(h):
    """Indices of the first maximum of the total reaction, the minimum after it and pull-off.

    Pull-off is the first step after which the |interaction energy| has collapsed (to < 1/5 within one step,
    or below 1e-3 of its peak); when the run ended at the limit point instead, its last step (the last
    equilibrium before the jump). "before" is the last equilibrium state before pull-off."""
    f, e = h["reaction_total_z"], np.abs(h["adhesion_energy"])
    # a converged jump to the detached state: |energy| falls to less than a fifth within one step (the
    # far-field tail after it decays slowly, so the 1e-3 stop condition may fire much later)
    jump = np.nonzero(e[1:] < 0.2 * e[:-1])[0]
    gone = jump + 1 if jump.size else np.nonzero(e < 1e-3 * e.max())[0]
    pull = int(gone[0]) if gone.size else len(f) - 1
    # the first local maximum: where the force first drops by 1% of its running maximum
    running = np.maximum.accumulate(f[:pull + 1])
    drop = np.nonzero(f[:pull + 1] < 0.99 * running)[0]
    peak = int(np.argmax(f[:drop[0]])) if drop.size else int(np.argmax(f[:pull + 1]))
    minimum = peak + int(np.argmin(f[peak:max(pull, peak + 1)]))
    return {"peak": peak, "min": minimum, "pulloff": pull, "before": pull - 1 if gone.size else pull,
            "pulloff_found": bool(gone.size)}


def vertex(t, f, i):
    """Time and value of the extremum of the parabola through steps i-1, i, i+1 (the steps are up to 1e-3
    apart, so the sampled extremum alone is only that accurate)."""
    if i < 1 or i + 1 >= len(t):
        return t[i], f[i]
    a, b, c = np.polyfit(t[i - 1:i + 2], f[i - 1:i + 2], 2)
    if a == 0:
        return t[i], f[i]
    tv = -b / (2 * a)
    return tv, c - b * b / (4 * a)


def summarize(results, names):
    table = {}
    for name in names:
        d = results / name
        if not is_completed(d):  # unfinished (interrupted) runs are not summarised
            continue
        h = read_history(d)
        c = characteristic(h)
        s = json.loads((d / "summary.json").read_text()) if (d / "summary.json").exists() else {}
        t_peak, f_peak = vertex(h["t"], h["reaction_total_z"], c["peak"])
        t_min, f_min = vertex(h["t"], h["reaction_total_z"], c["min"])
        table[name] = {
            "t_peak": t_peak, "f_peak": f_peak, "t_min": t_min, "f_min": f_min,
            "t_pulloff": h["t"][c["before"]],  # the last equilibrium before the jump
            "f_before_pulloff": h["reaction_total_z"][c["before"]], "energy_collapsed": c["pulloff_found"],
            "max_end_reaction_difference": float(np.max(np.abs(h["reaction_start_z"] - h["reaction_end_z"]))),
            "steps": int(h["step"][-1]), "newton_iterations": int(h["iterations"].sum()),
            "iterations_per_step": float(h["iterations"][1:].mean()), "message": s.get("message"),
            "wall_seconds": s.get("wall_seconds"), "completed": s.get("completed"),
        }
    (results / "characteristics.json").write_text(json.dumps(table, indent=2, default=float))
    lines = ["| run | max force | at t | min force | at t | pull-off t | force before pull-off | steps | Newton its "
             "(converged steps) | wall s |", "|---|---|---|---|---|---|---|---|---|---|"]
    for name, r in table.items():
        lines.append(f"| {name} | {r['f_peak']:.4f} | {r['t_peak']:.5f} | {r['f_min']:.4f} | {r['t_min']:.5f} | "
                     f"{r['t_pulloff']:.5f} | {r['f_before_pulloff']:.4f} | {r['steps']} | {r['newton_iterations']} | "
                     f"{r['wall_seconds'] or 0:.0f} |")
    (results / "characteristics.md").write_text("\n".join(lines) + "\n")
    for name, r in table.items():
        print(f"  {name:22s} peak {r['f_peak']:.4f} at t={r['t_peak']:.5f}  min {r['f_min']:.4f} at "
              f"t={r['t_min']:.5f}  pull-off t={r['t_pulloff']:.5f}{'' if r['energy_collapsed'] else ' (limit point)'}"
              f"  {r['steps']} steps, {r['newton_iterations']} its, {r['wall_seconds'] or 0:.0f} s")
    return table


def plot_reactions(ax, results, entries, zoom=None, window=None):
    for name, label in entries:
        d = results / alias(name, results.name.endswith("quick"))
        if not (d / "history.csv").exists():
            continue
        h = read_history(d)
        keep = h["t"] <= zoom if zoom else slice(None)
        if window:
            keep = (h["t"] >= window[0]) & (h["t"] <= window[1])
        line, = ax.plot(h["t"][keep], h["reaction_total_z"][keep], label=label, lw=1.2)
        if not zoom:  # the last equilibrium before pull-off
            b = characteristic(h)["before"]
            ax.plot(h["t"][b], h["reaction_total_z"][b], "x", color=line.get_color())
    ax.set_xlabel("quasi-time t")
    ax.set_ylabel("total reaction force on the beam")
    ax.grid(alpha=0.3)
    ax.legend()


def save(fig, path):
    fibrane_runs.save(fig, path, dpi=90)


def figures(results, figdir, quick, table):
    figdir.mkdir(parents=True, exist_ok=True)
    meshes = list(QUICK_MESHES if quick else MESHES)
    base = "mesh_" + meshes[1]

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    entries = [(f"mesh_{m}", m.replace("x", " x ")) for m in meshes]
    plot_reactions(axes[0], results, entries)
    axes[0].set_title("a) complete response")
    plot_reactions(axes[1], results, entries, zoom=0.005)
    axes[1].set_title("b) t in (0, 0.005)")
    save(fig, figdir / "peeling_fig15_meshes.png")

    if (results / base / "history.csv").exists():
        h = read_history(results / base)
        c = characteristic(h)
        instants = [("peak", c["peak"]), ("minimum", c["min"]), ("mid-way", (c["min"] + c["pulloff"]) // 2),
                    ("before pull-off", c["before"])]
        fig, ax = plt.subplots(figsize=(6.5, 4))
        for label, step in instants:
            a = read_interaction(results / base, int(h["step"][step]))
            ax.plot(a["xi"], a["force_magnitude"], label=f"{label}, t = {h['t'][step]:.4f}", lw=1.2)
        ax.set_xlabel("beam parameter xi")
        ax.set_ylabel("|interaction force| per unit length")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2)
        save(fig, figdir / "peeling_fig17_force_along_beam.png")

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    formulations = [("formulation_FF", "FF"), ("formulation_RF1", "RF1"), ("formulation_RF2", "RF2")]
    plot_reactions(axes[0], results, formulations)
    axes[0].set_title("a) complete response")
    plot_reactions(axes[1], results, formulations, window=(0.11, 1.0))
    axes[1].set_title("b) near pull-off (x: last equilibrium)")
    save(fig, figdir / "peeling_fig18_formulations.png")

    fig, ax = plt.subplots(figsize=(6.5, 4))
    plot_reactions(ax, results, [("youngratio_0.5", "E_B/E_S = 0.5"), ("youngratio_1", "E_B/E_S = 1"),
                                 ("youngratio_2", "E_B/E_S = 2")])
    ax.set_title("RF1")
    save(fig, figdir / "peeling_fig19_young_ratio.png")

    fig, ax = plt.subplots(figsize=(6.5, 4))
    strengths = [("strength_0.5", 0.5), ("strength_1", 1.0), ("strength_2", 2.0)]
    plot_reactions(ax, results, [(n, f"s = {s:g}") for n, s in strengths])
    peaks = [(s, table[alias(n, quick)]["f_peak"]) for n, s in strengths if alias(n, quick) in table]
    if len(peaks) == 3:
        k, c = np.polyfit(np.log([p[0] for p in peaks]), np.log([p[1] for p in peaks]), 1)
        ax.set_title(f"FF; fitted peak force f_p ~ s^{k:.3f} (paper: s^0.678)", fontsize=10)
        (results / "strength_exponent.json").write_text(json.dumps({"k": k, "log_c": c, "peaks": peaks}, indent=2))
        print(f"  fitted exponent of the peak force: k = {k:.4f}")
    save(fig, figdir / "peeling_fig20_strength.png")


def main():
    args = fibrane_runs.command_line(__doc__, "peeling_figures")
    results = ROOT / ("results/peeling-quick" if args.quick else "results/peeling")
    figdir = results / "figures" if args.quick else ROOT / "docs" / "figures"
    results.mkdir(parents=True, exist_ok=True)
    todo = fibrane_runs.selected(variants(args.quick), args.only)
    if not args.no_run:
        print(f"running {len(todo)} variants with {args.fibrane} ({args.jobs} at a time) into {results}")
        fibrane_runs.run_all(todo, lambda n, e: run_variant(n, e, results, args.fibrane, args.quick), args.jobs)
    table = summarize(results, variants(args.quick))
    figures(results, figdir, args.quick, table)


if __name__ == "__main__":
    main()
