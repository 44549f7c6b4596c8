#!/usr/bin/python3
"""Mesh-convergence tables of the Kirchhoff-Love shell benchmarks (linear and nonlinear benchmarks).

Runs the CLI on edited copies of examples/scordelis-lo.yaml, examples/pinched-cylinder.yaml and
examples/rollup-strip.yaml and prints markdown tables:
  * Scordelis-Lo roof and pinched cylinder: free DOFs, monitored displacement and relative error against the
    reference for n x n elements, n in 2..32, degrees 2, 3, 4 at maximal continuity (C^{p-1}). The column
    "rate" is the observed order log2(|w_{n/2} - w_{n/4}| / |w_n - w_{n/2}|) from successive values, which
    does not depend on the four-digit reference.
  * Roll-up strip: tip position at t = 0.5 and t = 1 against the closed form (half circle, full circle).
  * Newton residual history of a few roll-up steps (bench program shell_newton_log), to show the quadratic
    convergence: the contraction r_k / r_{k-1}^2 settles to a constant.

Usage: /usr/bin/python3 scripts/shell_convergence.py [--build build-shellver] [--quick] [--meshes 2 4 ...]
       [--only scordelis|pinched|rollup|newton ...]
"""
import argparse
import csv
import io
import json
import math
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCORDELIS_REFERENCE = 0.3006       # converged Kirchhoff-Love value
SCORDELIS_SHEAR_REFERENCE = 0.3024  # the classic target (shear-deformable shells), for comparison
PINCHED_REFERENCE = 1.8248e-5
ROLLUP_LENGTH = 12.0


def edited_example(name, edits):
    """Text of examples/<name> with each (old, new) replacement applied exactly once."""
    text = (ROOT / "examples" / name).read_text()
    for old, new in edits:
        if text.count(old) != 1:
            raise SystemExit(f"{name}: edit target must occur once: {old!r}")
        text = text.replace(old, new)
    return text


def refine_edit(name, degree, elements):
    """Replace the example's refine line (degree 4, C3, 16 x 16 or 16 x 1) by the given mesh."""
    old = "refine: {degree: 4, continuity: 3, elements: [16, 16]}"
    if name == "rollup-strip.yaml":
        old = "refine: {degree: 4, continuity: 3, elements: [16, 1]}"
    return (old, f"refine: {{degree: {degree}, continuity: {degree - 1}, elements: [{elements[0]}, {elements[1]}]}}")


def output_edit(text):
    """Switch VTK output off (only history.csv and summary.json are read)."""
    start = text.index("output: {")
    end = text.index("}", start)
    return (text[start:end + 1], text[start:end] + ", vtk: false}")


def run_case(fibrane, work, tag, text):
    """Runs one case; returns (summary dict, history rows as dicts) or (None, error text)."""
    case = work / f"{tag}.yaml"
    case.write_text(text)
    out = work / tag
    proc = subprocess.run([str(fibrane), "run", str(case), "-q", "-o", str(out)], capture_output=True, text=True)
    if proc.returncode != 0:
        return None, (proc.stderr or proc.stdout).strip().splitlines()[-1]
    summary = json.loads((out / "summary.json").read_text())
    with open(out / "history.csv") as f:
        rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
    return summary, rows


def observed_rates(values):
    """log2 of the ratio of successive differences (mesh halving); None where undefined."""
    rates = [None] * len(values)
    for i in range(2, len(values)):
        a, b, c = values[i - 2], values[i - 1], values[i]
        if None in (a, b, c) or b == a or c == b:
            continue
        rates[i] = math.log2(abs(b - a) / abs(c - b))
    return rates


def fmt_rate(r):
    return "" if r is None else f"{r:.2f}"


def linear_table(fibrane, work, example, monitor, references, meshes, degrees):
    print(f"\n### {example}: |{monitor}| vs n x n elements\n")
    ref_heads = " | ".join(f"rel. err. vs {r:g}" for r in references)
    print(f"| degree | n | free DOFs | value | {ref_heads} | rate |")
    print("|---|---|---|---|" + "---|" * len(references) + "---|")
    for p in degrees:
        values, rows = [], []
        for n in meshes:
            text = edited_example(example, [refine_edit(example, p, (n, n))])
            text = text.replace(*output_edit(text))
            summary, hist = run_case(fibrane, work, f"{pathlib.Path(example).stem}-p{p}-n{n}", text)
            if summary is None:
                values.append(None)
                rows.append((n, None, hist))
                continue
            w = abs(summary["final_monitors"][monitor])
            values.append(w)
            rows.append((n, summary["free_dofs"], w))
        for (n, dofs, w), rate in zip(rows, observed_rates(values)):
            if dofs is None:
                print(f"| {p} | {n} | | failed: {w} |" + " |" * len(references) + " |")
                continue
            errs = " | ".join(f"{(w - r) / r:+.2e}" for r in references)
            print(f"| {p} | {n} | {dofs} | {w:.7g} | {errs} | {fmt_rate(rate)} |")
        sys.stdout.flush()


def rollup_table(fibrane, work, meshes, degrees, thicknesses=((0.1, 1.2e6),)):
    """thicknesses: (h, E) pairs with the same D = E h^3 / 12; the example's (0.1, 1.2e6) comes first."""
    L = ROLLUP_LENGTH
    print("\n### rollup-strip.yaml: tip position (n x 1 elements, dt = 0.05)\n")
    print("Closed form: t = 0.5 half circle, tip at (0, 2L/pi) = (0, 7.639437); t = 1 full circle, tip at (0, 0). "
          "Errors are |tip - exact| / L.\n")
    print("| h | degree | n | free DOFs | steps | Newton its | tip (x, z) at t = 0.5 | err / L | tip (x, z) at t = 1 "
          "| err / L |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    runs = [(h, E, p, n) for p in degrees for n in meshes for h, E in thicknesses[:1]]
    runs += [(h, E, degrees[-1], meshes[-1]) for h, E in thicknesses[1:]]
    for h, E, p, n in runs:
        example = "rollup-strip.yaml"
        edits = [refine_edit(example, p, (n, 1))]
        if h != 0.1:
            edits += [("thickness: 0.1", f"thickness: {h}"), ("young: 1.2e6", f"young: {E:g}")]
        text = edited_example(example, edits)
        text = text.replace(*output_edit(text))
        summary, hist = run_case(fibrane, work, f"rollup-h{h}-p{p}-n{n}", text)
        if summary is None:
            print(f"| {h} | {p} | {n} | | failed: {hist} | | | | | |")
            continue
        half = min(hist, key=lambda r: abs(r["t"] - 0.5))
        last = hist[-1]
        e_half = math.hypot(half["tip_x"], half["tip_z"] - 2 * L / math.pi) / L
        e_end = math.hypot(last["tip_x"], last["tip_z"]) / L
        print(f"| {h} | {p} | {n} | {summary['free_dofs']} | {summary['steps']} | {summary['newton_iterations']} "
              f"| ({half['tip_x']:.5f}, {half['tip_z']:.5f}) | {e_half:.1e} "
              f"| ({last['tip_x']:.5f}, {last['tip_z']:.5f}) | {e_end:.1e} |")
        sys.stdout.flush()


def newton_log(log_program, work, tag, steps_edit, max_steps):
    text = edited_example("rollup-strip.yaml", [("steps: {t_end: 1.0, dt: 0.05, dt_max: 0.1}", steps_edit)])
    case = work / f"{tag}.yaml"
    case.write_text(text)
    proc = subprocess.run([str(log_program), str(case), str(max_steps)], capture_output=True, text=True)
    if proc.returncode != 0:
        print(f"\n{tag}: shell_newton_log failed: {proc.stderr.strip()}")
        return
    print(f"\n#### Roll-up strip (degree 4, 16 x 1), `{steps_edit}`\n")
    print("| step | t | iteration k | residual r_k | r_k / r_{k-1}^2 |")
    print("|---|---|---|---|---|")
    for row in csv.DictReader(io.StringIO(proc.stdout)):
        c = float(row["contraction"])
        print(f"| {row['step']} | {row['t']} | {row['iteration']} | {float(row['residual']):.3e} "
              f"| {'' if math.isnan(c) else f'{c:.2e}'} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build-shellver", help="build directory (relative to the repository)")
    ap.add_argument("--quick", action="store_true", help="meshes 2..16 only")
    ap.add_argument("--meshes", type=int, nargs="+", help="elements per direction of the linear benchmarks")
    ap.add_argument("--only", choices=["scordelis", "pinched", "rollup", "newton"], action="append")
    args = ap.parse_args()
    build = ROOT / args.build
    fibrane = build / "app" / "fibrane"
    log_program = build / "bench" / "shell_newton_log"
    meshes = args.meshes or ([2, 4, 8, 16] if args.quick else [2, 4, 8, 16, 32])
    parts = args.only or ["scordelis", "pinched", "rollup", "newton"]
    with tempfile.TemporaryDirectory(prefix="fibrane-shell-convergence-") as tmp:
        work = pathlib.Path(tmp)
        if "scordelis" in parts:
            linear_table(fibrane, work, "scordelis-lo.yaml", "w_free_edge_mid",
                         [SCORDELIS_REFERENCE, SCORDELIS_SHEAR_REFERENCE], meshes, [2, 3, 4])
        if "pinched" in parts:
            linear_table(fibrane, work, "pinched-cylinder.yaml", "w_load", [PINCHED_REFERENCE], meshes, [2, 3, 4])
        if "rollup" in parts:
            # The thinner strips (same D) separate the discretisation error from the thickness effect.
            rollup_table(fibrane, work, [4, 8, 16] if args.quick else [4, 8, 16, 32], [3, 4],
                         [(0.1, 1.2e6), (0.05, 9.6e6), (0.025, 7.68e7)])
        if "newton" in parts:
            print("\n### Newton residual history (roll-up strip)")
            newton_log(log_program, work, "newton-example", "steps: {t_end: 1.0, dt: 0.05, dt_max: 0.1}", 2)
            newton_log(log_program, work, "newton-small", "steps: {t_end: 0.01, dt: 0.01}", 1)


if __name__ == "__main__":
    main()
