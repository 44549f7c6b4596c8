"""fibrane.Case: a case as an editable tree of dicts and lists, read and checked by the CLI's reader."""
import collections.abc
import copy
import math
import numbers
import os
import pathlib
import re

from . import _core
from .errors import DICT_SOURCE, InputError

__all__ = ["Case", "to_yaml"]

_BARE_KEY = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def _scalar(value, path):
    if value is None:
        return "null"
    if isinstance(value, (bool,)) or type(value).__name__ == "bool_":
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        x = float(value)
        if math.isnan(x):
            return ".nan"
        if math.isinf(x):
            return ".inf" if x > 0 else "-.inf"
        return repr(x)
    if isinstance(value, str):
        return '"' + _escape(value) + '"'
    raise InputError(f"{DICT_SOURCE}:0: {path or 'case'}: expected a number, string, boolean, None, list or dict, "
                     f"got a {type(value).__name__}")


def _escape(s):
    out = []
    for ch in s:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\x{ord(ch):02x}")
        else:
            out.append(ch)
    return "".join(out)


def _plain(value):
    """numpy arrays and scalars as lists and Python numbers."""
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        return value.tolist()
    return value


def _inline(value):
    """A scalar, an empty container, or a list of scalars or of lists of scalars: written on one line."""
    def scalar(v):
        return not isinstance(_plain(v), (collections.abc.Mapping, list, tuple))
    value = _plain(value)
    if isinstance(value, collections.abc.Mapping):
        return not value
    if isinstance(value, (list, tuple)):
        return all(scalar(v) or (isinstance(_plain(v), (list, tuple)) and all(scalar(w) for w in _plain(v)))
                   for v in value)
    return True


def _flow(value, path):
    value = _plain(value)
    if isinstance(value, collections.abc.Mapping):
        return "{}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_flow(v, f"{path}[{i}]") for i, v in enumerate(value)) + "]"
    return _scalar(value, path)


def _block(value, path, indent):
    """The lines of a non-empty map or list, block style, at `indent` spaces."""
    pad = " " * indent
    lines = []
    value = _plain(value)
    if isinstance(value, collections.abc.Mapping):
        for key, v in value.items():
            if not isinstance(key, str):
                raise InputError(f"{DICT_SOURCE}:0: {path or 'case'}: expected string keys, got {key!r}")
            child = f"{path}.{key}" if path else key
            name = key if _BARE_KEY.match(key) else '"' + _escape(key) + '"'
            if _inline(v):
                lines.append(f"{pad}{name}: {_flow(v, child)}")
            else:
                lines.append(f"{pad}{name}:")
                lines.extend(_block(v, child, indent + 2))
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            child = f"{path}[{i}]"
            if _inline(v):
                lines.append(f"{pad}- {_flow(v, child)}")
            else:
                sub = _block(v, child, indent + 2)
                sub[0] = pad + "- " + sub[0][indent + 2:]
                lines.extend(sub)
    else:
        raise InputError(f"{DICT_SOURCE}:0: {path or 'case'}: expected a map or a list, got {value!r}")
    return lines


def to_yaml(data):
    """The YAML text of a case given as dicts and lists (strings are always quoted, numbers never)."""
    if not isinstance(data, collections.abc.Mapping):
        raise InputError(f"{DICT_SOURCE}:0: expected a dict of the case's keys (shells, beams, steps, ...), "
                         f"got a {type(data).__name__}")
    return "\n".join(_block(data, "", 0)) + "\n" if data else "{}\n"


class Case(collections.abc.MutableMapping):
    """A case: the keys of a case file (docs/case-format.md) as a tree of dicts and lists.

    Case(data, name="case") takes a dict; Case.from_yaml(path_or_text) a case file or YAML text. Either is
    read and checked at once by the CLI's reader (fibrane.InputError for bad input). The tree stays
    editable until it is run: case["steps"]["t_end"] = 0.5, and fibrane.run reads and checks it again.
    An unedited case from a file runs from the file's own text, as the CLI runs it.
    """

    def __init__(self, data, name="case"):
        """A case from a dict of the case keys; `name` is its name in summaries and the default title."""
        if isinstance(data, Case):
            data = data.to_dict()
        if not isinstance(data, collections.abc.Mapping):
            raise InputError(f"{DICT_SOURCE}:0: expected a dict of the case's keys (shells, beams, steps, ...), "
                             f"got a {type(data).__name__}")
        self._tree = copy.deepcopy(dict(data))
        self._text = None      # the file's text, while the tree is as read from it
        self._pristine = None  # the tree as read from the file
        self._source = DICT_SOURCE
        self.name = name
        self.check()

    @classmethod
    def from_yaml(cls, path_or_text):
        """A case from a YAML file (a pathlib.Path, or a str without a newline) or from YAML text."""
        if isinstance(path_or_text, os.PathLike) or (isinstance(path_or_text, str) and "\n" not in path_or_text):
            path = os.fspath(path_or_text)
            text, source, name = _core.read_text_file(path), path, pathlib.Path(path).stem
        else:
            text, source, name = str(path_or_text), "<text>", "case"
        case = cls.__new__(cls)
        case._tree = _core.yaml_to_data(text, source)
        case._text, case._source, case.name = text, source, name
        case._pristine = copy.deepcopy(case._tree)
        case.check()
        return case

    def _current(self):
        """(text, source) to read: the file's own text while the tree is unedited, else the tree's YAML."""
        if self._text is not None and self._tree == self._pristine:
            return self._text, self._source
        return to_yaml(self._tree), DICT_SOURCE

    def check(self):
        """Reads and checks the case as it is now (InputError if bad); returns its size and bodies as a dict."""
        text, source = self._current()
        return _core.check_case(text, source, self.name)

    def to_yaml(self):
        """The case as YAML text (what a run reads)."""
        return self._current()[0]

    def to_dict(self):
        """A deep copy of the tree."""
        return copy.deepcopy(self._tree)

    def copy(self):
        """An independent copy of the case."""
        other = copy.copy(self)
        other._tree = copy.deepcopy(self._tree)
        return other

    @property
    def source(self):
        """The case file, "<text>", or "<dict>" once the tree differs from what was read."""
        return self._current()[1]

    def __getitem__(self, key):
        return self._tree[key]

    def __setitem__(self, key, value):
        self._tree[key] = value

    def __delitem__(self, key):
        del self._tree[key]

    def __iter__(self):
        return iter(self._tree)

    def __len__(self):
        return len(self._tree)

    def __repr__(self):
        return f"fibrane.Case({self.name!r}, keys={list(self._tree)})"
