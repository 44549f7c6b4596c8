"""Results as arrays (shapes as docs/python.md gives them), the deformed geometry, laws and the study."""
import json
import subprocess

import numpy as np
import pytest

import fibrane
from conftest import ROOT, coarse_peeling_text

Z0 = 0.78216128295028686


def control_points(degree, continuity, elements):
    """Control points of an open knot vector with interior knots of multiplicity degree - continuity."""
    return degree + 1 + (degree - continuity) * (elements - 1)


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    case = fibrane.Case.from_yaml(coarse_peeling_text(beam=10, shell=(6, 4), max_steps=3))
    return fibrane.run(case, output=tmp_path_factory.mktemp("results") / "out")


def test_history_and_summary_shapes(result):
    rows = result.steps + 1
    assert result.bodies == {"membrane": "shell", "fiber": "beam"}
    for column, values in result.history.items():
        assert values.shape == (rows,) and values.dtype == float, column
    assert {"step", "t", "strain_energy", "adhesion_energy", "reaction_total_z"} <= set(result.history)
    np.testing.assert_array_equal(result.history["step"], np.arange(rows))
    assert result.summary["steps"] == result.steps and result.summary["t_reached"] == result.t_reached
    assert result.summary["interactions"]["adhesion"]["quadrature_points"] > 0


def test_displacements_and_unknowns_shapes(result):
    n_shell = control_points(4, 1, 6) * control_points(4, 1, 4)
    n_beam = control_points(4, 1, 10)
    assert result.displacements("membrane").shape == (n_shell, 3)
    assert result.displacements("fiber").shape == (n_beam, 4)
    assert result.unknowns().shape == (result.summary["free_dofs"],)
    # The pulled ends are at the prescribed height 4 t; the pinned membrane edges do not move.
    fiber = result.displacements("fiber")
    np.testing.assert_allclose(fiber[[0, -1], 2], 4 * result.t_reached, rtol=1e-12)
    with pytest.raises(KeyError, match="bodies"):
        result.displacements("nobody")


def test_geometry_at_parametric_points(result):
    xi = np.linspace(0, 1, 7)
    reference = result.geometry("fiber", xi, deformed=False)
    assert reference.shape == (7, 3)
    np.testing.assert_allclose(reference[:, 0], -5 + 10 * xi, atol=1e-12)
    np.testing.assert_allclose(reference[:, 2], Z0, atol=1e-12)
    deformed = result.geometry("fiber", xi)
    np.testing.assert_allclose(deformed[[0, -1], 2], Z0 + 4 * result.t_reached, rtol=1e-12)
    uv = np.array([[0.0, 0.3], [1.0, 0.6], [0.5, 0.5]])
    surface = result.geometry("membrane", uv)
    assert surface.shape == (3, 3)
    np.testing.assert_allclose(surface[:2], result.geometry("membrane", uv, deformed=False)[:2], atol=1e-12)
    assert surface[2, 2] > 0  # the adhering fiber lifts the membrane's middle as it is pulled
    with pytest.raises(ValueError, match="domain"):
        result.geometry("fiber", [1.5])


def test_interaction_data_along_the_beam(result):
    steps = result.interaction_steps("adhesion")
    assert steps[-1] == result.steps
    data = result.interaction("adhesion")
    points = result.summary["interactions"]["adhesion"]["quadrature_points"]
    for column in ("xi", "s", "distance", "force_z", "energy_density"):
        assert data[column].shape == (points,), column
    assert np.all(np.diff(data["xi"]) > 0)
    assert set(data["status"]) <= {"interior", "soft", "outside", "failed"}


def test_law_matches_the_cli(fibrane_bin):
    spec = {"model": "lennard_jones", "epsilon": 1, "sigma": 0.05}
    d = np.array([0.8, 0.9, 1.2])
    values = fibrane.law(spec, d, radius=0.5, thickness=0.5, cos=1.0)
    assert values["value"].shape == (3,) and values["equilibrium_distance"] > values["contact_distance"]
    for x, value, force in zip(d, values["value"], values["d_distance"]):
        out = subprocess.run([fibrane_bin, "law", "lj-disk-plate", "--radius", "0.5", "--thickness", "0.5",
                              "--distance", repr(x), "--cos", "1", "--epsilon", "1", "--sigma", "0.05"],
                             check=True, capture_output=True, text=True).stdout
        cli = json.loads(out)
        assert (value, force) == (cli["value"], cli["d_distance"])
    with pytest.raises(fibrane.InputError, match="contact"):
        fibrane.law(spec, [0.2], radius=0.5, thickness=0.5)
    with pytest.raises(fibrane.InputError, match="law"):
        fibrane.law({"model": "no_such_law"}, [1.0], radius=0.5, thickness=0.5)


def test_study_matches_the_cli(fibrane_bin, tmp_path):
    assert "fig6" in fibrane.study_figures()
    table = fibrane.study("fig6", coarse=True)
    subprocess.run([fibrane_bin, "study", "fig6", "--coarse", "-o", str(tmp_path)], check=True, capture_output=True)
    cli = fibrane.read_csv(str(tmp_path / "fig6.csv"))
    assert list(table) == list(cli)
    for column in table:
        assert np.array_equal(table[column], cli[column]), column
    with pytest.raises(fibrane.InputError, match="fig6"):
        fibrane.study("fig99")


def test_shell_section_forces_carry_the_end_moment():
    # Roll-up strip (examples/rollup-strip.yaml): a cantilever under an end moment per width m t carries the
    # bending moment m t along its whole length.
    case = fibrane.Case.from_yaml(ROOT / "examples" / "rollup-strip.yaml")
    case["steps"]["t_end"] = 0.2
    result = fibrane.run(case)
    moment = -case["loads"][0]["moment"][1] * result.t_reached
    uv = np.array([[0.1, 0.5], [0.5, 0.5], [0.9, 0.2]])
    forces = result.section_forces("strip", uv)
    assert set(forces) == {"N_local", "M_local", "N", "M"}
    assert all(v.shape == (3, 3) for v in forces.values())
    np.testing.assert_allclose(forces["M_local"][:, 0], moment, rtol=2e-3)
    np.testing.assert_allclose(forces["M_local"][:, 1:], 0, atol=1e-9 * moment)
    with pytest.raises(ValueError, match="beam"):
        fibrane.run(fibrane.Case.from_yaml(coarse_peeling_text(max_steps=1))).section_forces("fiber", [[0.5, 0.5]])
