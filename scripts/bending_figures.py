#!/usr/bin/python3
"""Shell bending by an adhering fiber (paper Sec. 6.2): run the variants, then draw Figs. 23-26.

    scripts/bending_figures.py [--jobs N] [--only NAME] [--quick] [--fibrane PATH] [--no-run]

Every variant is a text edit of examples/bending.yaml, run into results/bending/<variant>/ (a variant whose
summary.json says "completed", or that ended at a limit point, is not run again, so an interrupted call
resumes). The paper's mesh is the example itself; its run is taken from results/bending-paper/ when that
holds a finished run. PNGs go to docs/figures/ (with --quick, which uses coarse meshes
into results/bending-quick/ as a smoke test of the whole chain, to results/bending-quick/figures/).
"""
import re
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import fibrane_runs  # noqa: E402

ROOT = fibrane_runs.ROOT
EXAMPLE = ROOT / "examples" / "bending.yaml"
BASE_MESH = ("elements: 400", "elements: [100, 100]")  # beam, shell (u, v) as written in the example
MESHES = {"40x10x10": (40, 10), "100x25x25": (100, 25), "200x50x50": (200, 50), "400x100x100": (400, 100)}
QUICK_MESHES = {"20x5x5": (20, 5), "40x10x10": (40, 10), "60x15x15": (60, 15), "80x20x20": (80, 20)}
STRENGTHS = ("0.5", "1", "2")


def variants(quick):
    """name -> list of (old text, new text) edits; strengths are run on the second mesh (100x25x25: three more paper-mesh runs would take half an hour each)."""
    meshes = QUICK_MESHES if quick else MESHES
    v = {}
    for name, (beam, shell) in meshes.items():
        v[f"mesh_{name}"] = [(BASE_MESH[0], f"elements: {beam}"), (BASE_MESH[1], f"elements: [{shell}, {shell}]")]
    strength_mesh = v[f"mesh_{list(meshes)[1]}"]
    for s in STRENGTHS:
        if s != "1":
            v[f"strength_{s}"] = strength_mesh + [("strength: STRENGTH", None, s)]
    return v


def strength_of(text):
    at = text.find("strength:", text.find("lennard_jones"))
    end = text.find("}", at)
    return float(text[at + len("strength:"):end])


def case_text(edits, quick):
    text = EXAMPLE.read_text()
    if quick:
        edits = edits + [("vtk_every: 5", "vtk_every: 100")]
    for edit in edits:
        if edit[0] == "strength: STRENGTH":  # relative to the example's strength
            at = text.find("strength:", text.find("lennard_jones"))
            end = text.find("}", at)
            text = text[:at] + f"strength: {strength_of(text) * float(edit[2]):g}" + text[end:]
            continue
        old, new = edit
        if old not in text:
            sys.exit(f"bending_figures: '{old}' not found in {EXAMPLE}; the example changed")
        text = text.replace(old, new, 1)
    return text


def is_finished(directory):
    return fibrane_runs.is_finished(directory)


def run_dir(results, name, quick, started=False):
    """A variant's folder; the paper's mesh is results/bending-paper/ (where the example is run by hand) once
    that holds a finished run, or, with started=True (for the figures), any run that wrote a history there
    (its curves then end where it stopped)."""
    paper = ROOT / "results" / "bending-paper"
    use_paper = (paper / "history.csv").exists() if started else is_finished(paper)
    if not quick and name == "mesh_400x100x100" and use_paper:
        return paper
    return results / name


def run_variant(name, edits, results, fibrane, quick):
    out = run_dir(results, name, quick)
    if is_finished(out):
        print(f"  {name}: finished earlier, kept ({out})")
        return
    fibrane_runs.run_case(fibrane, name, case_text(edits, quick), results, out)


read_csv = fibrane_runs.read_csv


# RF2 equilibrium distance = the example's z0 (the beam's height): the law attracts beyond it, repels inside it.
D_EQUILIBRIUM = float(re.search(r"line: \{from: \[0, 0, ([0-9.eE+-]+)\]", EXAMPLE.read_text()).group(1))
HALF_LENGTH = 4.0  # the modelled half beam; the paper's xi runs over the whole beam (length 8) from an end
INSTANTS = (0.25, 0.5, 0.75, 0.87, 1.0)


def normal_force(points):
    """Interaction force per length on the beam, signed: + repulsive, - attractive (RF2: along the normal)."""
    return np.where(points["distance"] < D_EQUILIBRIUM, 1.0, -1.0) * points["force_magnitude"]


def end_force(directory, steps):
    """Signed interaction force per length at the Gauss point nearest the beam end, per step."""
    out = []
    for k in steps:
        f = directory / "interaction" / f"adhesion_{int(k):06d}.csv"
        out.append(normal_force(read_csv(f))[-1] if f.exists() else np.nan)
    return np.array(out)


def save(fig, path):
    fibrane_runs.save(fig, path, dpi=130)


def plot_end_distributions(curves, near, path, clip):
    """Signed interaction force near the beam end over the paper's xi (whole beam from the end): panel a) up to
    `near`, panel b) up to 0.025 with the peaks clipped at +-clip. curves: (interaction CSV columns, label)."""
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    for p, label in curves:
        xi = (HALF_LENGTH - p["s"]) / (2 * HALF_LENGTH)
        for a, lim in zip(ax, (near, 0.025)):
            sel = xi <= lim
            a.plot(xi[sel], normal_force(p)[sel], ".-", label=label)
    ax[0].set(xlabel="xi (whole beam, from the end)", ylabel="interaction force per length (+ repulsive)",
              title=f"a) xi in (0, {near:g})")
    ax[1].set(xlabel="xi (whole beam, from the end)", ylabel="interaction force per length (+ repulsive)",
              title="b) xi in (0, 0.025), clipped")
    ax[1].set_ylim(-clip, clip)
    for a in ax:
        a.grid(alpha=0.3)
        a.legend()
    save(fig, path)


def at_instants(t, values):
    """values interpolated linearly between steps at INSTANTS (nan where the run did not get there)."""
    return [float(np.interp(ti, t, values)) if t[-1] >= ti - 1e-9 else np.nan for ti in INSTANTS]


def figures(results, figdir, quick):
    meshes = list(QUICK_MESHES if quick else MESHES)
    done = {m: run_dir(results, f"mesh_{m}", quick, started=True) for m in meshes}
    done = {m: d for m, d in done.items() if (d / "history.csv").exists()}
    table = []
    # Fig. 23: u_z and interaction force at the beam end vs t, four meshes.
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    for m, d in done.items():
        h = read_csv(d / "history.csv")
        label = m if h["t"][-1] >= 1 - 1e-9 else f"{m} (stopped at t = {h['t'][-1]:.4f})"
        ax[0].plot(h["t"], h["end_uz"], label=label)
        f = end_force(d, h["step"])
        ax[1].plot(h["t"], f, label=label)
        table.append((m, at_instants(h["t"], h["end_uz"]), at_instants(h["t"], f), len(h["t"]) - 1,
                      int(h["iterations"].sum())))
    ax[0].set(xlabel="t", ylabel="u_z at the beam end", title="a) displacement at the beam end")
    ax[1].set(xlabel="t", ylabel="force per length, last Gauss point (+ repulsive)",
              title="b) interaction force at the beam end")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend()
    save(fig, figdir / "bending_fig23_meshes.png")
    head = " | ".join(f"u_z(end), t = {t:g}" for t in INSTANTS) + " | " + " | ".join(f"f(end), t = {t:g}" for t in INSTANTS)
    print(f"| mesh | {head} | steps | Newton iterations |\n|---|" + "---|" * (2 * len(INSTANTS) + 2))
    for m, u, f, steps, its in table:
        cells = " | ".join(f"{v:.5f}" for v in u) + " | " + " | ".join(f"{v:.1f}" for v in f)
        print(f"| {m} | {cells} | {steps} | {its} |")

    if not done:
        return
    finest = list(done.values())[-1]
    h = read_csv(finest / "history.csv")
    # Fig. 24: force distribution near the end at five instants.
    curves = []
    for target in (0.2, 0.4, 0.6, 0.828, 1.0):
        k = int(h["step"][np.argmin(np.abs(h["t"] - target))])
        f = finest / "interaction" / f"adhesion_{k:06d}.csv"
        if f.exists():
            curves.append((read_csv(f), f"t = {h['t'][k]:.3f}"))
    plot_end_distributions(curves, 0.005, figdir / "bending_fig24_force_distribution.png", clip=300)
    shell_section_forces(finest, figdir)
    # Fig. 26: three strengths at the final state.
    strength_mesh = f"mesh_{meshes[1]}"
    curves = []
    for s in STRENGTHS:
        d = run_dir(results, strength_mesh if s == "1" else f"strength_{s}", quick, started=True)
        if (d / "history.csv").exists():
            last = int(read_csv(d / "history.csv")["step"][-1])
            curves.append((read_csv(d / "interaction" / f"adhesion_{last:06d}.csv"), f"{s} s_ref"))
    plot_end_distributions(curves, 0.002, figdir / "bending_fig26_strengths.png", clip=600)


def final_state(directory):
    """The numbers docs/examples.md quotes for a finished run: the fiber's shape from its last VTK file (end
    angle from the end tangent, sagitta = z(middle) - z(end)), the monitors, and from the last interaction CSV
    the signed end force, the largest attraction, and the arc length over which the attraction exceeds 95 %
    of that."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    h = read_csv(directory / "history.csv")
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(sorted((directory / "vtk").glob("fiber_*.vtu"))[-1]))
    reader.Update()
    xyz = vtk_to_numpy(reader.GetOutput().GetPoints().GetData())
    tangent = vtk_to_numpy(reader.GetOutput().GetPointData().GetArray("tangent"))[-1]
    last = int(h["step"][-1])
    p = read_csv(directory / "interaction" / f"adhesion_{last:06d}.csv")
    f = normal_force(p)
    strong = p["s"][f < 0.95 * f.min()]
    return {"t": h["t"][-1], "end angle [deg]": np.degrees(np.arctan2(-tangent[2], tangent[1])),
            "end u_y": h["end_uy"][-1], "end u_z": h["end_uz"][-1], "fiber middle z": xyz[0, 2],
            "sagitta": xyz[0, 2] - xyz[-1, 2], "shell edge u_z": h["shell_corner_uz"][-1],
            "adhesion energy change [%]": 100 * (h["adhesion_energy"][-1] / h["adhesion_energy"][0] - 1),
            "end force": f[-1], "largest attraction": -f.min(),
            "attraction > 95 % over s": f"[{strong.min():.2f}, {strong.max():.2f}]" if strong.size else "-",
            "soft points": int(p["soft_minimum"].sum()) if "soft_minimum" in p else 0}


def print_final_states(results, quick):
    names = [f"mesh_{m}" for m in (QUICK_MESHES if quick else MESHES)] + [f"strength_{s}" for s in STRENGTHS if s != "1"]
    rows = {n: final_state(run_dir(results, n, quick, started=True)) for n in names
            if (run_dir(results, n, quick, started=True) / "history.csv").exists()}
    if not rows:
        return
    keys = list(next(iter(rows.values())))
    print("| run | " + " | ".join(keys) + " |\n|---|" + "---|" * len(keys))
    for n, r in rows.items():
        print(f"| {n} | " + " | ".join(f"{v:.5g}" if isinstance(v, float) else str(v) for v in r.values()) + " |")


def shell_section_forces(directory, figdir):
    """Fig. 25: every point-data array of the last shell VTK file, drawn over the reference plane."""
    try:
        from vtkmodules.util.numpy_support import vtk_to_numpy
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    except ImportError:
        print("  no python3-vtk: Fig. 25 skipped")
        return
    files = sorted((directory / "vtk").glob("membrane_*.vtu"))
    if not files:
        return
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(files[-1]))
    reader.Update()
    grid = reader.GetOutput()
    xyz = vtk_to_numpy(grid.GetPoints().GetData())
    data = grid.GetPointData()
    names = [data.GetArrayName(i) for i in range(data.GetNumberOfArrays())]
    # Section forces and moments in the local (orthonormal) frame: N_11, N_22, N_12 and M_11, M_22, M_12.
    wanted = [(n, c) for n in ("N_local", "M_local") if n in names for c in range(3)]
    if not wanted:
        return
    disp = vtk_to_numpy(data.GetArray("displacement")) if "displacement" in names else np.zeros_like(xyz)
    ref = xyz - disp
    fig, axes = plt.subplots(2, 3, figsize=(12.6, 7.2), squeeze=False)
    labels = ("11", "22", "12")
    for a, (name, c) in zip(axes.flat, wanted):
        v = vtk_to_numpy(data.GetArray(name))
        v = v if v.ndim == 1 else v[:, c]
        s = a.tricontourf(ref[:, 0], ref[:, 1], v, levels=30, cmap="coolwarm")
        fig.colorbar(s, ax=a)
        a.set(title=f"{name[0]}_{labels[c]} at {files[-1].stem}", aspect="equal", xlabel="X", ylabel="Y")
    for a in list(axes.flat)[len(wanted):]:
        a.axis("off")
    save(fig, figdir / "bending_fig25_section_forces.png")


def main():
    args = fibrane_runs.command_line(__doc__, "bending_figures")
    results = ROOT / ("results/bending-quick" if args.quick else "results/bending")
    figdir = results / "figures" if args.quick else ROOT / "docs" / "figures"  # quick PNGs stay with the runs
    results.mkdir(parents=True, exist_ok=True)
    todo = fibrane_runs.selected(variants(args.quick), args.only)
    if not args.no_run:
        print(f"running {len(todo)} variants with {args.fibrane} ({args.jobs} at a time) into {results}")
        fibrane_runs.run_all(todo, lambda n, e: run_variant(n, e, results, args.fibrane, args.quick), args.jobs)
    figures(results, figdir, args.quick)
    print_final_states(results, args.quick)


if __name__ == "__main__":
    main()
