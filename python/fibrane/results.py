"""fibrane.Result: what a run gives back, as numpy arrays and dicts."""
import csv
import glob
import io
import json
import os

import numpy as np

__all__ = ["Result", "read_csv"]


def read_csv(path_or_text, text=False):
    """A CSV file (or, with text=True, CSV text) as a dict: column -> numpy array (float where every value
    is a number, else str)."""
    handle = io.StringIO(path_or_text) if text else open(path_or_text, newline="")
    with handle:
        rows = list(csv.reader(handle))
    header, rows = rows[0], rows[1:]
    columns = {}
    for j, name in enumerate(header):
        values = [r[j] for r in rows]
        try:
            columns[name] = np.array([float(v) for v in values], dtype=float)
        except ValueError:
            columns[name] = np.array(values, dtype=str)
    return columns


class Result:
    """A finished run (fibrane.run): its history, summary and final state.

    history      dict: history.csv column -> array of shape (rows,) (row 0: the initial state)
    summary      dict: summary.json
    outcome      "reached_end", "stopped", "limit_point", "max_steps", "failed" or "interrupted"
    completed    whether the run reached its end (t_end, a stop rule or the step callback)
    message      how it ended, in words
    t_reached    the last converged t;  steps: the number of converged steps
    directory    the output directory (a temporary one for output=None, removed with this object)
    bodies       dict: body name -> "shell" or "beam"
    """

    def __init__(self, state, directory, temporary=None):
        self._state = state
        self._temporary = temporary  # kept alive as long as the result: the files stay readable
        self.directory = directory
        self.outcome = state.outcome
        self.completed = state.completed
        self.message = state.message
        self.t_reached = state.t_reached
        self.steps = state.steps
        self.bodies = dict(state.bodies())
        self.history = read_csv(os.path.join(directory, "history.csv"))
        with open(os.path.join(directory, "summary.json")) as f:
            self.summary = json.load(f)

    def displacements(self, body):
        """Control-point displacements of the final state: shape (n, 3) for a shell (x, y, z), (n, 4) for a
        beam (x, y, z, twist); rows in the body's control-point order (docs/case-format.md)."""
        return self._state.displacements(body)

    def unknowns(self):
        """The free unknowns of the final state, shape (free_dofs,)."""
        return self._state.unknowns()

    def geometry(self, body, params, deformed=True):
        """Points of the deformed body (deformed=False: the reference body) at parametric points: for a shell
        an array of shape (n, 2) of (u, v), for a beam shape (n,) of xi; returns shape (n, 3)."""
        params = np.asarray(params, dtype=float)
        if self.bodies.get(body) == "shell" and params.ndim == 1 and params.shape[0] == 2:
            params = params.reshape(1, 2)
        return self._state.geometry(body, params, deformed)

    def section_forces(self, body, params):
        """A shell's section forces and moments of the final state at parametric points (n, 2) of (u, v), as the
        sampled VTK output gives them: a dict of arrays of shape (n, 3) with the components (11, 22, 12) of
        "N_local", "M_local" (per current length in the frame e1 = g1/|g1|, e2 = n x e1) and of the
        contravariant "N", "M" (N^ab, M^ab)."""
        params = np.asarray(params, dtype=float)
        if params.ndim == 1 and params.shape[0] == 2:
            params = params.reshape(1, 2)
        return self._state.section_forces(body, params)

    def interaction_steps(self, name):
        """The steps for which the interaction `name` has per-point data (interaction/<name>_<step>.csv)."""
        files = glob.glob(os.path.join(glob.escape(self.directory), "interaction", glob.escape(name) + "_*.csv"))
        return sorted(int(f.rsplit("_", 1)[1][:-4]) for f in files)

    def interaction(self, name, step=None):
        """The per-point data of an interaction along the beam at a step (default: the last with data): dict
        column -> array of shape (beam quadrature points,); columns as in README's interaction CSV table."""
        steps = self.interaction_steps(name)
        if not steps:
            raise KeyError(f"no per-point data of interaction '{name}' in {self.directory}")
        step = steps[-1] if step is None else step
        if step not in steps:
            raise KeyError(f"interaction '{name}' has no data for step {step} (steps: {steps[0]} ... {steps[-1]})")
        return read_csv(os.path.join(self.directory, "interaction", f"{name}_{step:06d}.csv"))

    def __repr__(self):
        return f"fibrane.Result({self.outcome}, t_reached={self.t_reached}, steps={self.steps})"
