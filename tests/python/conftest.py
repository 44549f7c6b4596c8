"""Shared helpers of the Python module's tests (run by ctest: tests/python/CMakeLists.txt)."""
import os
import pathlib

import pytest

import fibrane

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def coarse_peeling_text(beam=10, shell=(6, 4), t_end=0.3, max_steps=None):
    """examples/peeling.yaml as text at a coarse mesh, without VTK files (and with a step budget)."""
    text = (EXAMPLES / "peeling.yaml").read_text()
    edits = [("elements: 100}", f"elements: {beam}}}"), ("elements: [20, 10]", f"elements: [{shell[0]}, {shell[1]}]"),
             ("t_end: 0.3", f"t_end: {t_end}"), ("vtk_every: 5}", "vtk: false}")]
    if max_steps is not None:
        edits.append(("max_iterations: 10", f"max_iterations: 10\n  max_steps: {max_steps}"))
    for old, new in edits:
        assert old in text, f"examples/peeling.yaml changed: '{old}' not found"
        text = text.replace(old, new, 1)
    return text


@pytest.fixture
def peeling():
    """A coarse peeling case (10 beam elements, 6 x 4 shell elements) as a fibrane.Case, 6 steps at most."""
    return fibrane.Case.from_yaml(coarse_peeling_text(max_steps=6))


@pytest.fixture
def fibrane_bin():
    """The CLI executable (FIBRANE_BIN, set by ctest)."""
    path = os.environ.get("FIBRANE_BIN")
    if not path:
        pytest.skip("FIBRANE_BIN is not set (ctest sets it)")
    return path
