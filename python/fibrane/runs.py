"""fibrane.run: the CLI's run driver from Python."""
import collections.abc
import os
import signal
import tempfile

from . import _core
from .case import Case
from .results import Result

__all__ = ["run"]


def run(case, output=None, threads=0, restart=False, callback=None, quiet=True, newton_log=False, max_steps=None):
    """Runs a case as `fibrane run` does and returns a fibrane.Result.

    case        a fibrane.Case, a dict of case keys, or a case file's path
    output      the output directory (an earlier run's files there are replaced, as with -o); None: a
                temporary directory, removed when the Result is
    threads     threads of the assembly and the solvers (0: all cores, or OMP_NUM_THREADS if set, as the CLI)
    restart     continue the run in `output` from its last checkpoint (as --restart OUTPUT); the case's
                text must be the one that run started with
    callback    called after every converged step, once its output is written, as
                callback(t, step, monitors, state): monitors is a dict of the history quantities (strain
                energy, interaction energies and forces, the case's monitors), state a fibrane StepState
                (state.unknowns, state.displacements(body), state.iterations, ...; valid during the call
                only). Returning False ends the run after that step (outcome "stopped"); an exception ends
                it likewise and is raised again once the run's files are written.
    quiet       no progress line on stderr (quiet=False: the CLI's progress line)
    newton_log  one line per Newton iteration on stderr (--newton-log)
    max_steps   stop after at most this many steps (--max-steps; a checkpoint is written)

    The GIL is released while the run computes. Ctrl-C (SIGINT) ends the run after the step in progress,
    with its output and a checkpoint written, and then raises KeyboardInterrupt; SIGTERM likewise raises
    SystemExit(143). fibrane.InputError for bad input (nothing is written then).
    """
    if not isinstance(case, Case):
        case = Case(case) if isinstance(case, collections.abc.Mapping) else Case.from_yaml(os.fspath(case))
    if max_steps is not None and (int(max_steps) != max_steps or max_steps < 1):
        raise ValueError(f"max_steps: expected an integer >= 1, got {max_steps!r}")
    if int(threads) != threads or threads < 0:
        raise ValueError(f"threads: expected an integer >= 0, got {threads!r}")
    if callback is not None and not callable(callback):
        raise TypeError("callback: expected a callable (t, step, monitors, state) or None")
    temporary = None
    if output is None:
        if restart:
            raise ValueError("restart=True continues the run in `output`: name that directory")
        temporary = tempfile.TemporaryDirectory(prefix="fibrane-")
        directory = os.path.join(temporary.name, "out")
    else:
        directory = os.fspath(output)
    if not threads:  # the CLI's default, also after an earlier run of this process with other threads
        threads = _default_threads()
    text, source = case._current()
    state = _core.run(text, source, case.name, directory, int(threads), bool(restart), bool(quiet),
                      bool(newton_log), int(max_steps or 0), callback)
    result = Result(state, directory, temporary)
    if state.interrupted_by == signal.SIGINT:
        raise KeyboardInterrupt(f"fibrane: {state.message}; output in {directory}")
    if state.interrupted_by == signal.SIGTERM:
        raise SystemExit(143)
    return result


def _default_threads():
    try:
        return max(1, int(os.environ.get("OMP_NUM_THREADS", "").split(",")[0]))
    except ValueError:
        return os.cpu_count() or 1
