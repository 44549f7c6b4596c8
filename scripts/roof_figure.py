#!/usr/bin/python3
"""Shallow hinged cylindrical roof (examples/shallow-roof.yaml): mesh study of the first limit point and the
load-deflection figure against the published path.

Runs the CLI on edited copies of the example (thickness 12.7 and 6.35; degree p with maximal continuity
C^{p-1}, n x n elements on the quarter) and prints markdown tables:
  * per thickness and mesh: the limit load P_lim = 3000 t_lim (N, whole roof) and the central deflection
    there, their differences from the limit point of Sze, Liu & Lo's (2004) path (Table 9, all rows in
    tests/model/data/sze2004_roof_table9.csv), and the largest distance of a published row from our path in
    the plane of P / 3000 N and w / 30 mm. Both limit points are the vertex of the parabola t(w) through the
    point with the first maximum of t and its two neighbours (w: central deflection, monotonic through the
    first limit point); the columns "step max" give our step itself. The arc lengths of the example (ds, ds_max) are scaled with n + p, the
    square root of the number of control points, so that every mesh takes steps of about the same size in w.
  * per thickness, the example's mesh with the arc lengths scaled by f (--ds-study): the interpolation error.
Writes docs/figures/shallow_roof.png (load-deflection paths of the example's mesh, both thicknesses) unless
--no-figure.

Usage: /usr/bin/python3 scripts/roof_figure.py [--fibrane build/app/fibrane] [--meshes 2 4 8 16 32]
       [--degrees 3 4] [--thickness 12.7 6.35] [--ds-factor 1.0] [--ds-study 1 0.5 0.25] [--no-figure]
"""
import argparse
import csv
import json
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
P_MAX = 3000.0  # N: the load at t = 1 (Sze et al.'s P_max); the example applies a quarter of it
SZE_TABLE = ROOT / "tests" / "model" / "data" / "sze2004_roof_table9.csv"
EXAMPLE_MESH = "refine: {degree: 4, continuity: 3, elements: [8, 8]}"
EXAMPLE_DEGREE, EXAMPLE_ELEMENTS = 4, 8


def case_text(thickness, degree, elements, ds_factor):
    text = (ROOT / "examples" / "shallow-roof.yaml").read_text()
    edits = [(EXAMPLE_MESH, f"refine: {{degree: {degree}, continuity: {degree - 1}, elements: [{elements}, {elements}]}}"),
             ("thickness: 12.7", f"thickness: {thickness}")]
    for old, new in edits:
        if text.count(old) != 1:
            sys.exit(f"shallow-roof.yaml: edit target must occur once: {old!r}")
        text = text.replace(old, new)
    # ds and ds_max scaled with n + p (about the square root of the number of control points)
    start = text.index("arc_length: {")
    end = text.index("}", start)
    keys = dict(item.split(":") for item in text[start + len("arc_length: {"):end].split(","))
    scale = ds_factor * (elements + degree) / (EXAMPLE_ELEMENTS + EXAMPLE_DEGREE)
    scaled = ", ".join(f"{k.strip()}: {float(v) * scale if k.strip() in ('ds', 'ds_max') else v.strip()}"
                       for k, v in keys.items())
    return text[:start] + "arc_length: {" + scaled + text[end:]


def run(fibrane, work, tag, text):
    """(summary, t, w) of one run; w is the downward central deflection (mm)."""
    case = work / f"{tag}.yaml"
    case.write_text(text)
    out = work / tag
    proc = subprocess.run([fibrane, "run", str(case), "-q", "-o", str(out)], capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"{tag}: {(proc.stderr or proc.stdout).strip()}")
    summary = json.loads((out / "summary.json").read_text())
    with open(out / "history.csv") as f:
        rows = list(csv.DictReader(f))
    t = np.array([float(r["t"]) for r in rows])
    w = -np.array([float(r["w_centre"]) for r in rows])
    return summary, t, w


def first_maximum(t):
    for i in range(1, len(t) - 1):
        if t[i] >= t[i - 1] and t[i] > t[i + 1]:
            return i
    return None


def limit_point(t, w):
    """(t_lim, w_lim, t_step, w_step, t_at): vertex of the parabola t(w) through the first maximum of t and its
    neighbours, the step itself, and the parabola as a function (for the load at a given deflection)."""
    i = first_maximum(t)
    if i is None:
        return None
    c = np.polyfit(w[i - 1:i + 2], t[i - 1:i + 2], 2)
    w_lim = -c[1] / (2 * c[0])
    return np.polyval(c, w_lim), w_lim, t[i], w[i], lambda x: np.polyval(c, x)


def sze_path(thickness):
    """(t, w) of Sze et al.'s rows for one thickness: t = P / P_max, w = -W (mm)."""
    with open(SZE_TABLE) as f:
        rows = [r for r in csv.DictReader(line for line in f if not line.startswith("#"))
                if float(r["thickness"]) == thickness]
    return np.array([float(r["load_ratio"]) for r in rows]), np.array([float(r["deflection"]) for r in rows])


def largest_distance(t_ref, w_ref, t, w, w_scale=30.0):
    """Largest distance of a published row (up to our path's end load) from our path, a polyline in the
    plane of t and w / w_scale."""
    a = np.c_[w[:-1] / w_scale, t[:-1]]
    d = np.c_[w[1:] / w_scale, t[1:]] - a
    largest = 0.0
    for tq, wq in zip(t_ref, w_ref):
        if tq > t[-1]:
            continue
        q = np.array([wq / w_scale, tq])
        s = np.clip(np.einsum("ij,ij->i", q - a, d) / np.einsum("ij,ij->i", d, d), 0.0, 1.0)
        largest = max(largest, np.min(np.linalg.norm(a + s[:, None] * d - q, axis=1)))
    return largest


def ds_table(fibrane, work, thickness, factors):
    """The example's mesh with the arc lengths scaled: the error of the interpolated maximum."""
    print(f"\n#### h = {thickness}: quartic 8 x 8, arc lengths ds and ds_max of the example times f\n")
    print("| f | steps | P_lim (N) | w_lim (mm) | P step max (N) | w step max (mm) |")
    print("|---|---|---|---|---|---|")
    for f in factors:
        summary, t, w = run(fibrane, work, f"ds_h{thickness}_{f}",
                            case_text(thickness, EXAMPLE_DEGREE, EXAMPLE_ELEMENTS, f))
        t_lim, w_lim, t_step, w_step, _ = limit_point(t, w)
        print(f"| {f} | {summary['steps']} | {P_MAX * t_lim:.2f} | {w_lim:.3f} | {P_MAX * t_step:.2f} | "
              f"{w_step:.3f} |", flush=True)


def mesh_table(fibrane, work, thickness, degrees, meshes, ds_factor):
    t_sze, w_sze = sze_path(thickness)
    t_ref, w_ref = limit_point(t_sze, w_sze)[:2]
    p_ref = P_MAX * t_ref
    print(f"\n#### h = {thickness}: limit point of Sze et al.'s path P = {p_ref:.1f} N at w = {w_ref:.3f} mm\n")
    print("| degree | n | free DOFs | steps | Newton its | P_lim (N) | err. | w_lim (mm) | err. | "
          "largest row distance | P step max (N) | w step max (mm) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for p in degrees:
        for n in meshes:
            summary, t, w = run(fibrane, work, f"h{thickness}_p{p}_n{n}", case_text(thickness, p, n, ds_factor))
            lim = limit_point(t, w)
            if lim is None:
                print(f"| {p} | {n} | {summary['free_dofs']} | {summary['steps']} | no limit point |")
                continue
            t_lim, w_lim, t_step, w_step, _ = lim
            print(f"| {p} | {n} | {summary['free_dofs']} | {summary['steps']} | {summary['newton_iterations']} | "
                  f"{P_MAX * t_lim:.1f} | {P_MAX * t_lim / p_ref - 1:+.2%} | {w_lim:.3f} | {w_lim / w_ref - 1:+.1%} | "
                  f"{largest_distance(t_sze, w_sze, t, w):.4f} | {P_MAX * t_step:.1f} | {w_step:.3f} |", flush=True)


def figure(fibrane, work, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, h in zip(axes, (12.7, 6.35)):
        _, t, w = run(fibrane, work, f"figure_h{h}", case_text(h, EXAMPLE_DEGREE, EXAMPLE_ELEMENTS, 1.0))
        t_lim, w_lim, _, _, _ = limit_point(t, w)
        ax.plot(w, P_MAX * t, "-", color="C0", lw=1.2, label="fibrane (quartic, 8 x 8 quarter)")
        ax.plot(w, P_MAX * t, ".", color="C0", ms=3)
        ax.plot([w_lim], [P_MAX * t_lim], "x", color="C0", ms=8, label="fibrane limit point (parabola)")
        t_sze, w_sze = sze_path(h)
        t_ref, w_ref = limit_point(t_sze, w_sze)[:2]
        ax.plot(w_sze, P_MAX * t_sze, "o", mfc="none", color="C3", ms=5, label="Sze et al. (2004), Table 9")
        ax.plot([w_ref], [P_MAX * t_ref], "+", color="C3", ms=10, label="Sze et al., limit point (parabola)")
        ax.axhline(0, color="0.7", lw=0.6)
        ax.set_xlabel("central deflection $-w$ (mm)")
        ax.set_ylabel("central load P (N)")
        ax.set_title(f"h = {h} mm")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"\nwrote {path.relative_to(ROOT)}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fibrane", default=str(ROOT / "build" / "app" / "fibrane"))
    ap.add_argument("--meshes", type=int, nargs="+", default=[2, 4, 8, 16, 32])
    ap.add_argument("--degrees", type=int, nargs="+", default=[3, 4])
    ap.add_argument("--thickness", type=float, nargs="+", default=[12.7, 6.35])
    ap.add_argument("--ds-factor", type=float, default=1.0, help="multiplies ds and ds_max of every run")
    ap.add_argument("--ds-study", type=float, nargs="*", default=[1.0, 0.5, 0.25],
                    help="factors of the arc lengths for the interpolation-error table (none: skip it)")
    ap.add_argument("--no-figure", action="store_true")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        for h in args.thickness:
            mesh_table(args.fibrane, work, h, args.degrees, args.meshes, args.ds_factor)
        for h in args.thickness:
            if args.ds_study:
                ds_table(args.fibrane, work, h, args.ds_study)
        if not args.no_figure:
            figure(args.fibrane, work, ROOT / "docs" / "figures" / "shallow_roof.png")


if __name__ == "__main__":
    main()
