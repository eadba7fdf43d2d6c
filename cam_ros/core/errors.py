"""The one error root of cam_ros and its few meaningful subclasses."""
from __future__ import annotations

from collections.abc import Iterable
import difflib
import reprlib

#: Longest quoted value in an error message (characters), before "... (N items)".
QUOTE_LIMIT = 100
_REPR = reprlib.Repr()
_REPR.maxlist = _REPR.maxtuple = _REPR.maxdict = _REPR.maxset = QUOTE_LIMIT
_REPR.maxstring = _REPR.maxother = _REPR.maxlong = QUOTE_LIMIT + 2


def quote(value: object) -> str:
    """Return repr(value), cut to QUOTE_LIMIT characters and saying how much was left out.

    A long string keeps its start and its end (a file name ends a path); a long list its first
    entries. Only that much is ever formatted, so quoting a million-entry list costs no more
    than quoting a short one.
    """
    if isinstance(value, str):
        text = repr(value)
        if len(value) <= QUOTE_LIMIT and len(text) <= QUOTE_LIMIT:
            return text
        half = (QUOTE_LIMIT - 3) // 2
        head, tail = repr(value[:half])[:half], repr(value[-half:])[-half:]
        return f'{head}...{tail} ({len(value)} characters)'
    if isinstance(value, (list, tuple)):
        text, size = _REPR.repr(value[:QUOTE_LIMIT]), f' ({len(value)} items)'
    else:
        text, size = _REPR.repr(value), ''
    if len(text) <= QUOTE_LIMIT:
        return text
    text = text[:QUOTE_LIMIT - 4]
    if ', ' in text:  # end on a whole entry
        text = text[:text.rfind(', ') + 2]
    return f'{text}...{size}'


def one_line(message: str) -> str:
    """Join a multi-line message (e.g. a YAML parser's, with caret lines) into one line."""
    return ' '.join(line.strip() for line in message.splitlines() if line.strip(' ^'))


def did_you_mean(name: str, known: Iterable[str]) -> str:
    """Return ' (did you mean X?)' for the closest of the known names, or '' if none is close."""
    close = difflib.get_close_matches(name, list(known), n=1)
    return f' (did you mean {close[0]}?)' if close else ''


def similar_names(name: str, known: Iterable[str], count: int) -> list[str]:
    """Return up to count known names like name: same last /-part first, then close spellings."""
    names = [found for found in known if found != name]
    base = name.rpartition('/')[2]
    similar = [found for found in names if found.rpartition('/')[2] == base]
    similar += difflib.get_close_matches(name, names, n=count, cutoff=0.6)
    return list(dict.fromkeys(similar))[:count]


class CamError(Exception):
    """Root of every error cam_ros raises on purpose."""


class InvalidParameter(CamError, ValueError):
    """A design parameter broke a rule; names the parameter, the value and the rule.

    The message quotes at most QUOTE_LIMIT characters of the value (and of the name), so it
    stays one short line whatever was given.
    """

    def __init__(self, parameter: str, value: object, rule: str):
        self.parameter = parameter
        self.value = value
        self.rule = rule
        name = parameter if len(parameter) <= QUOTE_LIMIT else parameter[:QUOTE_LIMIT] + '...'
        super().__init__(f'{name} = {quote(value)}: {rule}')


class RecordingError(CamError, OSError):
    """A recording could not be written or read."""
