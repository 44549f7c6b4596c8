"""The examples in examples/python at their quick settings: they run, and say what they should."""
import os
import re
import subprocess
import sys

from conftest import ROOT

EXAMPLES = ROOT / "examples" / "python"


def run_example(name, *args, cwd=None):
    return subprocess.run([sys.executable, str(EXAMPLES / name), *args], check=True, capture_output=True, text=True,
                          env=dict(os.environ), cwd=cwd, timeout=800).stdout


def test_peeling_strength_study_at_a_coarse_mesh():
    out = run_example("peeling_strength.py", "--coarse")
    rows = re.findall(r"s = +([\d.]+): peak force ([\d.]+) at t = [\d.]+; pull-off at t = ([\d.]+)", out)
    assert [float(r[0]) for r in rows] == [0.5, 1.0, 2.0], out
    peaks, pulloffs = [float(r[1]) for r in rows], [float(r[2]) for r in rows]
    assert peaks == sorted(peaks) and pulloffs == sorted(pulloffs), out  # both grow with the strength
    k = float(re.search(r"k = ([-\d.]+)", out).group(1))
    assert 0 < k < 1, out  # sublinear, as the paper's 0.678


def test_membrane_plot(tmp_path):
    out = run_example("membrane_plot.py", "--output", str(tmp_path / "m.png"))
    assert (tmp_path / "m.png").stat().st_size > 10000
    assert float(re.search(r"deflection ([-\d.e]+)", out).group(1)) > 0
