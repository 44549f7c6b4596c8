"""fibrane.law and fibrane.study: interaction laws and the error study of paper Sec. 4 (docs/laws.md)."""
import collections.abc

import numpy as np

from . import _core
from .case import to_yaml
from .results import read_csv

__all__ = ["law", "study", "study_figures"]


def law(spec, distance, radius, thickness, cos=1.0):
    """An interaction law of the registry against the separation, as `fibrane law interaction` evaluates it.

    spec       the law as a case's `law:` map: a dict such as {"model": "lennard_jones", "epsilon": 1,
               "sigma": 0.05} or its YAML text
    distance   disk centre to mid-plane distances (a number or an array; each above the contact distance
               cos * radius + thickness / 2)
    radius     the beam's section radius (the disk radius R);  thickness: the shell's thickness h
    cos        cos alpha, in [0, 1]
    Returns a dict: "value", "d_distance", "d_cos", "d2_distance", "d2_cos", "d2_distance_cos" (arrays of
    the shape of `distance`, flattened), "distance", "law" (its name), "contact_distance" and
    "equilibrium_distance" (None for a law without one). fibrane.InputError for a bad law or argument.
    """
    text = to_yaml(spec) if isinstance(spec, collections.abc.Mapping) else str(spec)
    d = np.atleast_1d(np.asarray(distance, dtype=float)).ravel()
    return _core.law(text, "law", float(radius), float(thickness), d, float(cos))


def study_figures():
    """The figures of the error study: ["fig6", ..., "fig12"]."""
    return list(_core.study_figures())


def study(name, coarse=False):
    """One figure of the error study (`fibrane study NAME`) as a dict: column -> array (docs/laws.md);
    coarse=True samples fewer gaps (quick looks, tests)."""
    return read_csv(_core.study_csv(name, bool(coarse)), text=True)
