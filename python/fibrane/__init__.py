"""fibrane: beams adhering to shells by van der Waals forces, from Python (docs/python.md).

    import fibrane
    case = fibrane.Case.from_yaml("examples/peeling.yaml")
    case["steps"]["t_end"] = 0.5
    result = fibrane.run(case)
    result.history["t"], result.history["strain_energy"]
"""
import os as _os

# The OpenMP and OpenBLAS settings the CLI gives itself (run/process_environment.cpp says why), read by
# libgomp and OpenBLAS when the extension loads them: a user's own settings are kept.
_os.environ.setdefault("OMP_WAIT_POLICY", "passive")
_os.environ.setdefault("OMP_THREAD_LIMIT", str(_os.cpu_count() or 1))
_os.environ.setdefault("OPENBLAS_THREAD_TIMEOUT", "20")

from . import _core  # noqa: E402
from .case import Case, to_yaml  # noqa: E402
from .errors import InputError  # noqa: E402
from .results import Result, read_csv  # noqa: E402
from .runs import run  # noqa: E402
from .laws import law, study, study_figures  # noqa: E402

__all__ = ["Case", "InputError", "Result", "run", "law", "study", "study_figures", "to_yaml", "read_csv"]
__version__ = _core.version
