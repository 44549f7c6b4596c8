"""Cases as data: the CLI's reader and checks on dicts and YAML, located errors, edits before a run."""
import numpy as np
import pytest

import fibrane
from conftest import EXAMPLES, coarse_peeling_text

Z0 = 0.78216128295028686


def peeling_dict(beam=10, shell=(6, 4), max_steps=4):
    """The coarse peeling case of coarse_peeling_text written as Python data."""
    return {
        "title": "Peeling of an adhering beam from a shell",
        "shells": [{"name": "membrane",
                    "geometry": {"rectangle": {"origin": [-6, -3, 0], "edge_u": [12, 0, 0], "edge_v": [0, 6, 0]}},
                    "refine": {"degree": 4, "continuity": 1, "elements": list(shell)},
                    "thickness": 0.5, "material": {"young": 1000, "poisson": 0.3}}],
        "beams": [{"name": "fiber", "geometry": {"line": {"from": [-5, 0, Z0], "to": [5, 0, Z0]}},
                   "refine": {"degree": 4, "continuity": 1, "elements": beam},
                   "material": {"young": 1000, "poisson": 0.3}, "section": {"circle": {"radius": 0.5}}}],
        "interactions": [{"name": "adhesion", "beam": "fiber", "shell": "membrane", "formulation": "FF",
                          "lennard_jones": {"epsilon": 6400, "sigma": 0.05, "density_beam": 1, "density_shell": 1,
                                            "strength": 1}}],
        "constraints": [{"body": "membrane", "at": {"edge": e}, "fix": ["x", "y", "z"]} for e in ("u0", "u1", "v0", "v1")]
        + [{"body": "fiber", "at": [{"end": "start"}, {"end": "end"}], "prescribe": {"z": 4.0}, "fix": ["y"]},
           {"body": "fiber", "at": {"end": "start"}, "fix": ["x", "twist"]}],
        "monitors": [{"name": "reaction_start_z", "type": "reaction", "body": "fiber", "at": {"end": "start"}, "component": "z"},
                     {"name": "reaction_end_z", "type": "reaction", "body": "fiber", "at": {"end": "end"}, "component": "z"},
                     {"name": "reaction_total_z", "type": "reaction", "body": "fiber",
                      "at": [{"end": "start"}, {"end": "end"}], "component": "z"},
                     {"name": "mid_z", "type": "position", "body": "fiber", "at": {"xi": 0.5}, "component": "z"}],
        "steps": {"method": "arc_length", "t_end": 0.3, "arc_length": {"ds": 0.02, "ds_max": 0.5}, "max_iterations": 10,
                  "max_steps": max_steps, "tolerance_absolute": 1.0e-8,
                  "stop": {"column": "reaction_total_z", "below_fraction_of_peak": 5.0e-3}},
        "output": {"directory": "out/peeling", "vtk": False},
    }


def test_dict_case_gives_the_yaml_cases_history(tmp_path):
    from_yaml = fibrane.run(fibrane.Case.from_yaml(coarse_peeling_text(max_steps=4)), output=tmp_path / "yaml")
    from_dict = fibrane.run(fibrane.Case(peeling_dict(max_steps=4)), output=tmp_path / "dict")
    assert from_yaml.steps == 4 and from_dict.steps == 4
    assert list(from_yaml.history) == list(from_dict.history)
    for column, values in from_yaml.history.items():
        assert np.array_equal(values, from_dict.history[column], equal_nan=True), column
    # The per-point interaction data are the same too.
    a, b = from_yaml.interaction("adhesion"), from_dict.interaction("adhesion")
    for column in a:
        assert np.array_equal(a[column], b[column]), column


def test_malformed_dict_names_the_key_path():
    data = peeling_dict()
    data["shells"][0]["material"]["poisson"] = 0.7
    with pytest.raises(fibrane.InputError) as e:
        fibrane.Case(data)
    assert e.value.key == "shells[0].material.poisson"
    assert e.value.got == "0.7" and "0.5" in e.value.expected
    assert e.value.file is None and e.value.line is None
    assert str(e.value).startswith("case dict: shells[0].material.poisson: expected")


def test_dict_typo_and_wrong_types_are_refused():
    data = peeling_dict()
    data["steps"]["t_ned"] = 1.0
    with pytest.raises(fibrane.InputError, match=r"unknown key 't_ned'") as e:
        fibrane.Case(data)
    assert e.value.key == "steps"
    data = peeling_dict()
    data["beams"][0]["material"]["poison"] = data["beams"][0]["material"].pop("poisson")
    with pytest.raises(fibrane.InputError, match=r"'poisson' \(found 'poison': a typo\?\)") as e:
        fibrane.Case(data)
    assert e.value.key == "beams[0].material"
    data = peeling_dict()
    data["steps"]["t_end"] = "0.3"  # a string is no number, as a quoted number in YAML
    with pytest.raises(fibrane.InputError) as e:
        fibrane.Case(data)
    assert e.value.key == "steps.t_end" and e.value.expected == "a number"
    data = peeling_dict()
    data["steps"]["t_end"] = object()
    with pytest.raises(fibrane.InputError, match="steps.t_end"):
        fibrane.Case(data)


def test_yaml_errors_carry_file_and_line(tmp_path):
    text = coarse_peeling_text().replace("poisson: 0.3}", "poisson: 0.7}", 1)
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    line = 1 + text[: text.index("poisson: 0.7")].count("\n")
    with pytest.raises(fibrane.InputError) as e:
        fibrane.Case.from_yaml(path)
    assert (e.value.file, e.value.line, e.value.key) == (str(path), line, "shells[0].material.poisson")
    with pytest.raises(fibrane.InputError) as e:
        fibrane.Case.from_yaml(text)
    assert (e.value.file, e.value.line) == ("<text>", line)
    with pytest.raises(fibrane.InputError, match="missing.yaml"):
        fibrane.Case.from_yaml(tmp_path / "missing.yaml")


def test_edits_before_a_run_are_read_and_checked(tmp_path):
    case = fibrane.Case.from_yaml(coarse_peeling_text())
    assert case.source == "<text>"
    case["steps"]["max_steps"] = 2
    case["interactions"][0]["lennard_jones"]["strength"] = 2
    assert case.source == "<dict>"
    result = fibrane.run(case, output=tmp_path / "edited")
    assert result.steps == 2
    assert "strength: 2" in case.to_yaml()
    case["steps"]["max_steps"] = 0
    with pytest.raises(fibrane.InputError) as e:
        fibrane.run(case, output=tmp_path / "refused")
    assert e.value.key == "steps.max_steps"
    assert not (tmp_path / "refused").exists()  # nothing written for rejected input


def test_file_case_round_trips_through_data():
    case = fibrane.Case.from_yaml(EXAMPLES / "peeling.yaml")
    assert case.source == str(EXAMPLES / "peeling.yaml") and case.name == "peeling"
    assert case["beams"][0]["geometry"]["line"]["from"][2] == Z0
    assert case["output"]["vtk_every"] == 5 and isinstance(case["output"]["vtk_every"], int)
    again = fibrane.Case(case.to_dict())
    assert again.to_dict() == case.to_dict()
    info = again.check()
    assert info["shells"] == ["membrane"] and info["beams"] == ["fiber"] and info["free_dofs"] < info["dofs"]
