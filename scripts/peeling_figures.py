#!/usr/bin/python3
"""Peeling of an adhering beam from a shell (paper Sec. 6.1): run every variant, then draw Figs. 15, 17-20.

    scripts/peeling_figures.py [--jobs N] [--only NAME] [--quick] [--fibrane PATH] [--no-run]

Every variant is a text edit of examples/peeling.yaml (arc-length continuation through pull-off to the
detached beam), run into results/peeling/<variant>/ (a variant whose summary.json says "completed" is not
run again, so an interrupted call resumes). The curves show the whole path: stable stretches solid, the
unstable branch (negative eigenvalues of the tangent, history.csv; where the solver does not count them,
the stretch between the two limit points) dashed; pull-off is the first limit point
(maximum of t) of summary.json's limit_points. The PNGs go to docs/figures/, the characteristic values of
every run to results/peeling/characteristics.{json,md}.
--quick uses coarse meshes and shorter arc-length steps (a smoke test of the whole chain, runs and PNGs into
results/peeling-quick/). --only A,B runs only the variants whose name contains A or B (figures are drawn from
all finished runs).
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
# 2-core build machine (~40 min for the ~300 iterations of the path, docs/examples.md); 150 x 30 x 15 is the
# finest used here.


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
    rf1 = base + [("formulation: FF", "formulation: RF1")]
    v["formulation_RF1"] = rf1
    v["formulation_RF2"] = base + [("formulation: FF", "formulation: RF2")]
    # Fig. 19 with RF1 (as the paper): a) the shell's E_S varied, E_B = 1000 fixed (the paper's variation);
    # b) the beam's E_B varied, E_S = 1000 fixed.
    for young in ("500", "2000"):
        v[f"youngshell_{young}"] = rf1 + [("SHELL_YOUNG", young)]
        v[f"youngbeam_{young}"] = rf1 + [("BEAM_YOUNG", young)]
    for s in ("0.5", "2"):
        v[f"strength_{s}"] = base + [("strength: 1}", f"strength: {s}}}")]
    return v


# Names used by the figures for the runs that are shared with the base case.
def alias(name, quick):
    middle = "mesh_" + list(QUICK_MESHES if quick else MESHES)[1]
    return {"formulation_FF": middle, "strength_1": middle, "youngshell_1000": "formulation_RF1",
            "youngbeam_1000": "formulation_RF1"}.get(name, name)


def replace_young(text, section, young):
    """Sets the first 'young: 1000' after `section` ("shells:" or "beams:") to `young`."""
    at = text.find("young: 1000", text.find(section))
    if at < 0:
        sys.exit(f"peeling_figures: no 'young: 1000' after '{section}' in {EXAMPLE}; the example changed")
    return text[:at] + f"young: {young}" + text[at + len("young: 1000"):]


def case_text(edits, quick):
    text = EXAMPLE.read_text()
    # Let late pull-offs (strength 2, soft beam) finish: the stop rule (reaction below 0.5 % of its peak)
    # ends every run once the beam is detached. The figures need history.csv and the interaction CSVs
    # (written every step), not the VTK files.
    edits = edits + [("t_end: 0.3", "t_end: 0.6"), ("vtk_every: 5}", "vtk: false}")]
    if quick:
        edits = edits + [("ds: 0.02, ds_max: 0.5", "ds: 0.01, ds_max: 0.4")]
    for old, new in edits:
        if old in ("SHELL_YOUNG", "BEAM_YOUNG"):
            text = replace_young(text, "shells:" if old == "SHELL_YOUNG" else "beams:", new)
            continue
        if old not in text:
            sys.exit(f"peeling_figures: '{old}' not found in {EXAMPLE}; the example changed")
        text = text.replace(old, new, 1)
    return text


def is_completed(directory):
    """Finished runs: ended by the stop rule (the beam detached) or at t_end."""
    return fibrane_runs.is_finished(directory, min_steps=10)


def run_variant(name, edits, results, fibrane, quick):
    out = results / name
    if is_completed(out):
        print(f"  {name}: completed earlier, kept")
        return
    fibrane_runs.run_case(fibrane, name, case_text(edits, quick), results, out)


def read_history(directory):
    return fibrane_runs.read_csv(directory / "history.csv")


def read_limit_points(directory):
    try:
        return json.loads((directory / "summary.json").read_text()).get("limit_points", [])
    except (OSError, ValueError):
        return []


def read_interaction(directory, step):
    return fibrane_runs.read_csv(directory / "interaction" / f"adhesion_{step:06d}.csv")


def characteristic(h, limits):
    """Indices (rows of history.csv) of the characteristic states of a peeling path.

    pull-off: the pull-off limit point (the first maximum of t, from summary.json) lies between rows
    "before" and "pulloff"; "peak": the first local maximum of the total reaction (where it first drops by
    1 % below its running maximum), "min": the minimum of the reaction between the peak and pull-off;
    "lowest": the row nearest to the second limit point (the minimum of t at the end of the unstable
    branch); "detached": the first row after pull-off with a reaction below 1 % of the largest reaction of
    the path (None if the run ended before)."""
    f, t = h["reaction_total_z"], h["t"]
    rows = {int(s): i for i, s in enumerate(h["step"])}
    maxima = [lp for lp in limits if lp["kind"] == "maximum"]
    pull = rows[maxima[0]["step"]] if maxima else len(t) - 1
    running = np.maximum.accumulate(f[:pull + 1])
    drop = np.nonzero(f[:pull + 1] < 0.99 * running)[0]
    peak = int(np.argmax(f[:drop[0]])) if drop.size else int(np.argmax(f[:pull + 1]))
    minimum = peak + int(np.argmin(f[peak:max(pull, peak + 1)]))
    minima = [lp for lp in limits if lp["kind"] == "minimum" and maxima and lp["step"] > maxima[0]["step"]]
    lowest = rows[minima[0]["step"]] - 1 if minima else None
    gone = np.nonzero(f[pull:] < 0.01 * f.max())[0]
    return {"peak": peak, "min": minimum, "pulloff": pull, "before": max(pull - 1, 0), "lowest": lowest,
            "detached": pull + int(gone[0]) if gone.size else None, "limit_found": bool(maxima)}


def extremum(t, f, i):
    """Time and value of the extremum near row i (a sampled extremum of f): of the polynomial through rows
    i-2 .. i+2 (fewer at the ends), on [t[i-1], t[i+1]]. The arc-length steps are ~0.003 apart in t at the
    force peak; the parabola through three rows overestimates that asymmetric peak by ~1e-3, the quartic
    agrees with the load-stepping values (steps <= 1e-3) to ~2e-4."""
    lo, hi = max(i - 2, 0), min(i + 3, len(t))
    if hi - lo < 3:
        return t[i], f[i]
    p = np.polyfit(t[lo:hi], f[lo:hi], hi - lo - 1)
    grid = np.linspace(t[max(i - 1, 0)], t[min(i + 1, len(t) - 1)], 20001)
    values = np.polyval(p, grid)
    k = int(np.argmax(values) if f[i] >= f[lo] else np.argmin(values))
    return grid[k], values[k]


def summarize(results, names):
    table = {}
    for name in names:
        d = results / name
        if not is_completed(d):  # unfinished (interrupted) runs are not summarised
            continue
        h, limits = read_history(d), read_limit_points(d)
        c = characteristic(h, limits)
        s = json.loads((d / "summary.json").read_text())
        t_peak, f_peak = extremum(h["t"], h["reaction_total_z"], c["peak"])
        t_min, f_min = extremum(h["t"], h["reaction_total_z"], c["min"])
        pull = [lp for lp in limits if lp["kind"] == "maximum"]
        lows = [lp for lp in limits if lp["kind"] == "minimum"]
        table[name] = {
            "t_peak": t_peak, "f_peak": f_peak, "t_min": t_min, "f_min": f_min,
            "t_pulloff": pull[0]["t"] if pull else None,
            "f_pulloff": pull[0]["values"]["reaction_total_z"] if pull else None,
            "t_lowest": lows[0]["t"] if lows else None,
            "f_lowest": lows[0]["values"]["reaction_total_z"] if lows else None,
            "t_detached": h["t"][c["detached"]] if c["detached"] is not None else None,
            "f_detached_at_pulloff": jump_target(h, limits),  # where a displacement-controlled pull lands
            "final_reaction_fraction": float(h["reaction_total_z"][-1] / h["reaction_total_z"].max()),
            "unstable_steps": int(np.sum(unstable_rows(h, limits))),
            "max_end_reaction_difference": float(np.max(np.abs(h["reaction_start_z"] - h["reaction_end_z"]))),
            "steps": int(h["step"][-1]), "newton_iterations": s.get("newton_iterations"),
            "message": s.get("message"), "wall_seconds": s.get("wall_seconds"), "completed": s.get("completed"),
        }
    (results / "characteristics.json").write_text(json.dumps(table, indent=2, default=float))

    def num(x, f):
        return "-" if x is None else format(x, f)
    lines = ["| run | max force | at t | min force | at t | pull-off t | pull-off force | end of unstable branch t | "
             "reaction there | steps | Newton its | wall s |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, r in table.items():
        lines.append(f"| {name} | {r['f_peak']:.4f} | {r['t_peak']:.5f} | {r['f_min']:.4f} | {r['t_min']:.5f} | "
                     f"{num(r['t_pulloff'], '.5f')} | {num(r['f_pulloff'], '.4f')} | {num(r['t_lowest'], '.5f')} | "
                     f"{num(r['f_lowest'], '.4f')} | {r['steps']} | {r['newton_iterations']} | "
                     f"{r['wall_seconds'] or 0:.0f} |")
    (results / "characteristics.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return table


def jump_target(h, limits):
    """The reaction of the detached beam at the pull-off instant: where the stable branch after the second
    limit point (the minimum of t) passes t_pull-off, i.e. where a displacement-controlled pull lands when
    it jumps at pull-off; the last reaction of the run if it stopped before getting there (an upper bound);
    None without a second limit point."""
    pull = [lp for lp in limits if lp["kind"] == "maximum"]
    low = [lp for lp in limits if lp["kind"] == "minimum" and pull and lp["step"] > pull[0]["step"]]
    if not low:
        return None
    t, f = h["t"], h["reaction_total_z"]
    start = int(np.nonzero(h["step"] == low[0]["step"])[0][0])
    for i in range(start, len(t) - 1):
        if (t[i] - pull[0]["t"]) * (t[i + 1] - pull[0]["t"]) <= 0 and t[i] != t[i + 1]:
            w = (pull[0]["t"] - t[i]) / (t[i + 1] - t[i])
            return f[i] + w * (f[i + 1] - f[i])
    # the run stopped (reaction below 0.5 % of its peak) before the detached branch reached t_pull-off: the
    # reaction there is below the last one (it decays as the lift grows), which is drawn
    return f[-1] if t[-1] < pull[0]["t"] and t[-1] > t[start] else None


def unstable_rows(h, limits):
    """True for the rows of history.csv on an unstable branch: a negative eigenvalue of the tangent; where
    the linear solver does not count them (negative_eigenvalues = -1: the LU of RF1's unsymmetric
    tangent), the rows from the pull-off limit point (maximum of t) up to the next limit point (minimum of
    t): the tangent's determinant changes sign at each limit point."""
    neg = h["negative_eigenvalues"]
    between = np.zeros(len(neg), dtype=bool)
    steps = list(h["step"].astype(int))
    pull = [lp for lp in limits if lp["kind"] == "maximum"]
    if pull:
        low = [lp for lp in limits if lp["kind"] == "minimum" and lp["step"] > pull[0]["step"]]
        end = steps.index(low[0]["step"]) if low else len(neg)
        between[steps.index(pull[0]["step"]):end] = True
    return np.where(neg >= 0, neg > 0, between)


def plot_path(ax, h, limits, label, color, rows=None):
    """The total reaction vs t along the path: stable stretches solid, the unstable branch dashed (a segment
    with an end where the tangent has negative eigenvalues), the pull-off limit point as a circle and the
    jump of a displacement-controlled pull from there to the detached beam dotted."""
    t, f, unstable = h["t"], h["reaction_total_z"], unstable_rows(h, limits)
    rows = list(rows if rows is not None else range(len(t)))
    dashed = [False] + [bool(unstable[rows[j - 1]] or unstable[rows[j]]) for j in range(1, len(rows))]
    # segment j runs from rows[j - 1] to rows[j]; runs of segments of one style are drawn as one line
    first = 0
    for j in range(1, len(rows)):
        if j == len(rows) - 1 or dashed[j + 1] != dashed[j]:
            a, b = rows[first], rows[j]
            ax.plot(t[a:b + 1], f[a:b + 1], "--" if dashed[j] else "-", color=color, lw=1.2)
            first = j
    ax.plot([], [], "-", color=color, lw=1.2, label=label)
    pull = [lp for lp in limits if lp["kind"] == "maximum"]
    if pull:
        x, y = pull[0]["t"], pull[0]["values"]["reaction_total_z"]
        ax.plot(x, y, "o", color=color, ms=4)
        target = jump_target(h, limits)
        if target is not None:
            ax.plot([x, x], [y, target], ":", color=color, lw=1.0)


def plot_reactions(ax, results, entries, quick, zoom=None, window=None, ylim=None, title=None):
    """Reaction curves of the runs `entries` (name, label); zoom: only the start up to t = zoom; window,
    ylim: (low, high) limits of t and of the force."""
    drawn = 0
    for k, (name, label) in enumerate(entries):
        d = results / alias(name, quick)
        if not (d / "history.csv").exists():
            continue
        h = read_history(d)
        rows = None
        if zoom:
            beyond = np.nonzero(h["t"] > zoom)[0]
            rows = range(0, beyond[0] + 1 if beyond.size else len(h["t"]))
        plot_path(ax, h, [] if zoom else read_limit_points(d), label, f"C{k}", rows)
        drawn += 1
    if window:
        ax.set_xlim(*window)
    if ylim:
        ax.set_ylim(*ylim)
    if zoom:
        ax.set_xlim(0, zoom)
    ax.axhline(0, color="0.6", lw=0.5)
    ax.set_xlabel("quasi-time t (end lift 4 t)")
    ax.set_ylabel("total reaction force on the beam")
    ax.grid(alpha=0.3)
    if drawn:
        if not zoom:  # the line styles, once per axes
            ax.plot([], [], "--", color="0.4", lw=1.2, label="unstable branch")
            ax.plot([], [], "o:", color="0.4", ms=4, lw=1.0, label="pull-off (limit point) and jump")
        ax.legend(fontsize=8)
    if title:
        ax.set_title(title, fontsize=10)


def save(fig, path):
    fibrane_runs.save(fig, path, dpi=90)


def figures(results, figdir, quick, table):
    figdir.mkdir(parents=True, exist_ok=True)
    meshes = list(QUICK_MESHES if quick else MESHES)
    base = "mesh_" + meshes[1]

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    entries = [(f"mesh_{m}", m.replace("x", " x ")) for m in meshes]
    plot_reactions(axes[0], results, entries, quick, title="a) complete path")
    plot_reactions(axes[1], results, entries, quick, zoom=0.005, title="b) t in (0, 0.005)")
    save(fig, figdir / "peeling_fig15_meshes.png")

    if (results / base / "history.csv").exists():
        h = read_history(results / base)
        c = characteristic(h, read_limit_points(results / base))
        instants = [("peak", c["peak"]), ("minimum", c["min"]), ("mid-way", (c["min"] + c["pulloff"]) // 2),
                    ("at pull-off", c["before"])]
        if c["lowest"] is not None:
            instants.append(("unstable branch, mid-way", (c["pulloff"] + c["lowest"]) // 2))
        fig, ax = plt.subplots(figsize=(6.5, 4))
        for label, row in instants:
            a = read_interaction(results / base, int(h["step"][row]))
            ax.plot(a["xi"], a["force_magnitude"], label=f"{label}, t = {h['t'][row]:.4f}", lw=1.2,
                    ls="--" if h["negative_eigenvalues"][row] > 0 else "-")
        ax.set_xlabel("beam parameter xi")
        ax.set_ylabel("|interaction force| per unit length")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2)
        save(fig, figdir / "peeling_fig17_force_along_beam.png")

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    formulations = [("formulation_FF", "FF"), ("formulation_RF1", "RF1"), ("formulation_RF2", "RF2")]
    plot_reactions(axes[0], results, formulations, quick, title="a) complete path")
    pulls = [table[alias(n, quick)] for n, _ in formulations if table.get(alias(n, quick), {}).get("t_pulloff")]
    if pulls:
        t_pull, f_pull = pulls[0]["t_pulloff"], [r["f_pulloff"] for r in pulls]
        plot_reactions(axes[1], results, formulations, quick, window=(0.9 * t_pull, 1.02 * t_pull),
                       ylim=(0.9 * min(f_pull), 1.01 * max(f_pull)), title="b) near pull-off")
    save(fig, figdir / "peeling_fig18_formulations.png")

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    plot_reactions(axes[0], results, [("youngshell_500", "E_S = 500 (E_B/E_S = 2)"),
                                      ("youngshell_1000", "E_S = 1000 (E_B/E_S = 1)"),
                                      ("youngshell_2000", "E_S = 2000 (E_B/E_S = 0.5)")], quick,
                   title="a) RF1, E_B = 1000, E_S varied (as the paper)")
    plot_reactions(axes[1], results, [("youngbeam_500", "E_B = 500 (E_B/E_S = 0.5)"),
                                      ("youngbeam_1000", "E_B = 1000 (E_B/E_S = 1)"),
                                      ("youngbeam_2000", "E_B = 2000 (E_B/E_S = 2)")], quick,
                   title="b) RF1, E_S = 1000, E_B varied")
    save(fig, figdir / "peeling_fig19_young_ratio.png")

    fig, ax = plt.subplots(figsize=(6.5, 4))
    strengths = [("strength_0.5", 0.5), ("strength_1", 1.0), ("strength_2", 2.0)]
    peaks = [(s, table[alias(n, quick)]["f_peak"]) for n, s in strengths if alias(n, quick) in table]
    title = "FF"
    if len(peaks) == 3:
        k, c = np.polyfit(np.log([p[0] for p in peaks]), np.log([p[1] for p in peaks]), 1)
        title = f"FF; fitted peak force f_p ~ s^{k:.3f} (paper: s^0.678)"
        (results / "strength_exponent.json").write_text(json.dumps({"k": k, "log_c": c, "peaks": peaks}, indent=2))
        print(f"  fitted exponent of the peak force: k = {k:.4f}")
    plot_reactions(ax, results, [(n, f"s = {s:g}") for n, s in strengths], quick, title=title)
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
