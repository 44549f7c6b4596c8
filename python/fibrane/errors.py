"""fibrane.InputError: bad input, located as the CLI locates it."""
import re

__all__ = ["InputError"]

# "<file>:<line>: <key path>: <message>", the line and the key path each optional.
_LOCATED = re.compile(r"^(?P<file>.+?):(?:(?P<line>\d+):)? (?:(?P<key>[A-Za-z_][\w.\[\]-]*): )?(?P<rest>.*)$", re.S)

# Source names of cases that come from Python data: their messages name the key path, not a line.
DICT_SOURCE = "<dict>"


class InputError(ValueError):
    """Bad input: a case, a law or an argument the CLI would refuse with exit code 2.

    Attributes (None where the message does not say):
      file      the case file, "<text>" for YAML text, None for a case built from a dict
      line      the 1-based line in the file or text (None for dicts)
      key       the key path, e.g. "steps.dt" or "shells[0].material.poisson"
      expected  what was expected, e.g. "a number in (-1, 0.5)"
      got       what was found, e.g. "0.7"
    str(error) is the whole message; for dicts it starts with "case dict: <key path>: ".
    """

    def __init__(self, message):
        self.file = self.line = self.key = self.expected = self.got = None
        m = _LOCATED.match(message)
        if m and " " not in m.group("file"):
            self.file = m.group("file")
            self.line = int(m.group("line")) if m.group("line") else None
            self.key = m.group("key")
            rest = m.group("rest")
            if self.file == DICT_SOURCE:
                self.file, self.line = None, None
                message = "case dict: " + (self.key + ": " if self.key else "") + rest
            if rest.startswith("expected ") and ", got " in rest:
                self.expected, self.got = rest[len("expected "):].rsplit(", got ", 1)
        super().__init__(message)
