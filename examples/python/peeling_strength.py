"""The paper's Fig. 20: peeling (examples/peeling.yaml, FF) at the adhesion strengths s = 0.5, 1, 2; the
peak pull force and the pull-off point (the limit point of t) per strength, and the fit f_p ~ s^k.
    PYTHONPATH=build/python /usr/bin/python3 examples/python/peeling_strength.py [--coarse]"""
import argparse
import pathlib

import numpy as np

import fibrane

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--coarse", action="store_true", help="20 beam and 6 x 4 shell elements (seconds)")
args = parser.parse_args()

case = fibrane.Case.from_yaml(pathlib.Path(__file__).resolve().parents[1] / "peeling.yaml")
case["steps"]["t_end"] = 0.6     # the strongest adhesion peels off late; the stop rule ends every run
case["output"] = {"vtk": False}  # history and summary suffice
if args.coarse:
    case["beams"][0]["refine"]["elements"] = 20
    case["shells"][0]["refine"]["elements"] = [6, 4]
strengths, peaks = [0.5, 1.0, 2.0], []
for s in strengths:
    case["interactions"][0]["lennard_jones"]["strength"] = s
    result = fibrane.run(case)
    t, f = result.history["t"], result.history["reaction_total_z"]
    pull = next(p for p in result.summary["limit_points"] if p["kind"] == "maximum")
    peaks.append(f.max())
    print(f"s = {s:3}: peak force {f.max():.4f} at t = {t[f.argmax()]:.5f}; pull-off at t = {pull['t']:.5f} "
          f"(force {pull['values']['reaction_total_z']:.4f})")
k, log_c = np.polyfit(np.log(strengths), np.log(peaks), 1)
print(f"fitted f_p ~ s^k: k = {k:.3f} (paper: 0.678)")
