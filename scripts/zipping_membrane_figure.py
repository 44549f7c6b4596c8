#!/usr/bin/python3
"""Two fibers zipping into a bundle on a membrane: runs examples/zipping-membrane.yaml (damped dynamics),
draws docs/figures/zipping_membrane.png and prints the numbers that docs/examples.md quotes.

    scripts/zipping_membrane_figure.py [--fibrane PATH] [--no-run]

The run goes to results/zipping-membrane/ (a finished run is not repeated).
Left: the contact length of the fibers (zip_contact_length) and the membrane's deflection under the
bundle (membrane_mid_z) over time. Middle: the membrane's u_z at the last step (sampled VTK, read with
python3-vtk9), the fibers' axes at t = 0 (dashed) and at the end. Right: the section x = 0 of the membrane
at t = 0 and at the end, with the fibers' cross sections there.
"""
import json

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import vtk  # noqa: E402
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402

import fibrane_runs  # noqa: E402

ROOT = fibrane_runs.ROOT
CASE = ROOT / "examples" / "zipping-membrane.yaml"
RADIUS = 0.1


def read_vtu(path):
    """Current point positions and point fields of a sampled .vtu file."""
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    data = grid.GetPointData()
    fields = {data.GetArrayName(i): vtk_to_numpy(data.GetArray(i)) for i in range(data.GetNumberOfArrays())}
    return vtk_to_numpy(grid.GetPoints().GetData()), fields


def frame_file(out, series, step):
    return out / "vtk" / f"{series}_sampled_{step:06d}.vtu"


def last_step(out):
    steps = sorted(int(p.stem.rsplit("_", 1)[1]) for p in (out / "vtk").glob("membrane_sampled_*.vtu"))
    return steps[-1]


def axis_at(points, x):
    """y and z of a fiber's sampled axis where it crosses x (linear between samples)."""
    order = np.argsort(points[:, 0])
    p = points[order]
    return np.interp(x, p[:, 0], p[:, 1]), np.interp(x, p[:, 0], p[:, 2])


def membrane_section(points, x, half_width):
    """The membrane's current z along y on the section x (samples within half_width of it, sorted by y)."""
    near = np.abs(points[:, 0] - x) < half_width
    p = points[near]
    order = np.argsort(p[:, 1])
    return p[order, 1], p[order, 2]


def main():
    args = fibrane_runs.command_line(__doc__, "zipping_membrane_figure.py")
    results = ROOT / "results"
    out = results / "zipping-membrane"
    results.mkdir(parents=True, exist_ok=True)
    if not args.no_run and not fibrane_runs.is_finished(out):
        fibrane_runs.run_case(args.fibrane, "zipping-membrane", CASE.read_text(), results, out)
    h = fibrane_runs.read_csv(out / "history.csv")
    summary = json.loads((out / "summary.json").read_text())
    t, length, w = h["t"], h["zip_contact_length"], h["membrane_mid_z"]
    peak = int(np.argmax(length))
    print(f"steps {summary['steps']}, Newton iterations {summary['newton_iterations']}, "
          f"wall {summary['wall_seconds']:.1f} s")
    print(f"contact length: {length[0]:.4g} at t = 0, largest {length[peak]:.4g} at t = {t[peak]:.4g}, "
          f"{length[-1]:.4g} at t = {t[-1]:.4g}")
    settled = np.nonzero(np.abs(length - length[-1]) > 1e-12)[0]
    if len(settled):
        print(f"contact length constant from t = {t[min(settled[-1] + 1, len(t) - 1)]:.4g}")
    print(f"membrane_mid_z at the end {w[-1]:.4g}; zip_energy {h['zip_energy'][0]:.4g} -> {h['zip_energy'][-1]:.4g}; "
          f"adhesion energies {h['left_adhesion_energy'][-1]:.4g}, {h['right_adhesion_energy'][-1]:.4g}")
    print(f"energy_balance {h['energy_balance'][0]:.4g} -> {h['energy_balance'][-1]:.4g}, damping work "
          f"{h['damping_work'][-1]:.4g}, kinetic energy at the end {h['kinetic_energy'][-1]:.3g}")
    print(f"end: edges_z {h['edges_z'][-1]:.5g}, left pin {h['left_pin_y'][-1]:.5g}, fiber pull "
          f"{h['zip_force_left_y'][-1]:.5g}, membrane push {h['left_adhesion_force_y'][-1]:.5g}")

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.3), gridspec_kw={"width_ratios": [1, 1.35, 1]})
    ax = axes[0]
    ax.plot(t, length, color="C0", lw=1.6, drawstyle="steps-post")
    ax.set_xlabel("time t")
    ax.set_ylabel("contact length (zip_contact_length)", color="C0")
    ax.set_ylim(0, 2.0)
    ax.axhline(2.0, color="0.7", lw=0.5)
    twin = ax.twinx()
    twin.plot(t, w, color="C3", lw=1.2)
    twin.set_ylabel("membrane $u_z$ under the bundle (membrane_mid_z)", color="C3")

    step = last_step(out)
    mem, fields = read_vtu(frame_file(out, "membrane", step))
    uz = fields["displacement"][:, 2]
    ax = axes[1]
    tc = ax.tripcolor(mem[:, 0], mem[:, 1], uz, shading="gouraud", cmap="viridis")
    fig.colorbar(tc, ax=ax, label="membrane $u_z$", shrink=0.85)
    for fiber, color in (("left", "w"), ("right", "w")):
        start, _ = read_vtu(frame_file(out, fiber, 0))
        end, _ = read_vtu(frame_file(out, fiber, step))
        ax.plot(start[:, 0], start[:, 1], "--", color="0.85", lw=1.0)
        ax.plot(end[:, 0], end[:, 1], "-", color=color, lw=1.6)
    ax.axvline(0, color="0.6", lw=0.5, ls=":")
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_title(f"t = {t[-1]:.3g}: fibers' axes (dashed: t = 0), membrane $u_z$", fontsize=9)

    ax = axes[2]
    for frame, style, label in ((0, "--", "t = 0"), (step, "-", f"t = {t[-1]:.3g}")):
        mem, _ = read_vtu(frame_file(out, "membrane", frame))
        y, z = membrane_section(mem, 0.0, 1e-9 + 0.5 * 2.8 / 10 / 4)
        ax.plot(y, z, style, color="C2", lw=1.4, label=f"membrane, {label}")
        for fiber in ("left", "right"):
            axis, _ = read_vtu(frame_file(out, fiber, frame))
            cy, cz = axis_at(axis, 0.0)
            ax.add_patch(plt.Circle((cy, cz), RADIUS, fill=False, ls=style, color="C0"))
    ax.plot([], [], "-", color="C0", label="fiber sections at x = 0")
    ax.set_aspect("equal")
    ax.set_xlim(-0.45, 0.45)
    ax.set_ylim(-0.06, 0.24)
    ax.set_xlabel("y (section x = 0)")
    ax.set_ylabel("z")
    ax.set_title("section x = 0 (dashed: t = 0)", fontsize=9)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.45), fontsize=8, ncol=2)
    fibrane_runs.save(fig, ROOT / "docs" / "figures" / "zipping_membrane.png")


if __name__ == "__main__":
    main()
