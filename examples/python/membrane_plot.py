"""The membrane under the peeling fiber (examples/peeling.yaml, coarse mesh) pulled to t = 0.1, shortly
before pull-off: its deflection from the deformed geometry on a parametric grid, with the fiber's axis.
    PYTHONPATH=build/python /usr/bin/python3 examples/python/membrane_plot.py [--output membrane.png]"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fibrane  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--output", default="membrane.png", help="the figure (PNG)")
args = parser.parse_args()

case = fibrane.Case.from_yaml(pathlib.Path(__file__).resolve().parents[1] / "peeling.yaml")
case["beams"][0]["refine"]["elements"] = 40
case["shells"][0]["refine"]["elements"] = [12, 6]
case["steps"]["t_end"] = 0.1
case["output"] = {"vtk": False}
result = fibrane.run(case)

u, v = np.meshgrid(np.linspace(0, 1, 61), np.linspace(0, 1, 31))
points = result.geometry("membrane", np.column_stack([u.ravel(), v.ravel()])).reshape(*u.shape, 3)
axis = result.geometry("fiber", np.linspace(0, 1, 101))
fig = plt.figure(figsize=(8, 4.5))
ax = fig.add_subplot(projection="3d")
surface = ax.plot_surface(points[..., 0], points[..., 1], points[..., 2], cmap="viridis", linewidth=0)
ax.plot(axis[:, 0], axis[:, 1], axis[:, 2], color="tab:red", label="fiber axis")
ax.set(xlabel="x", ylabel="y", zlabel="z", title=f"membrane deflection at t = {result.t_reached:.3f}")
fig.colorbar(surface, shrink=0.6, label="z")
ax.legend()
fig.savefig(args.output, dpi=120, bbox_inches="tight")
print(f"{args.output}: largest membrane deflection {points[..., 2].max():.4g}")
