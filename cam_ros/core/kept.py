"""Costly results kept for inputs seen before, told apart by their class and exact repr.

A design is built anew on every parameter change (in the studio, on every edit), and with it
its laws, follower and motion program: new objects, most of them equal in value to the last
ones. What is costly to compute from them alone is kept here under their classes and repr,
computed once for equal inputs. Only frozen dataclasses of floats, strings, tuples and such
dataclasses go in: their repr holds every field exactly (-0.0, nan and inf too).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any, Callable, TypeVar

#: Results kept, the least recently used dropped first.
KEPT = 1024
T = TypeVar('T')


@dataclass(frozen=True)
class _Inputs:
    """A call told apart by its function and the text of its inputs; it carries the inputs."""

    function: Callable[..., Any]
    text: str
    values: tuple[Any, ...] = field(compare=False, hash=False)


@lru_cache(maxsize=KEPT)
def _result(inputs: _Inputs) -> Any:
    return inputs.function(*inputs.values)


def kept(function: Callable[..., T], *inputs: Any) -> T:
    """Return function(*inputs), computed once for inputs of the same classes and repr."""
    text = repr(tuple((type(value), value) for value in inputs))
    result: T = _result(_Inputs(function, text, inputs))
    return result


def forget() -> None:
    """Drop every kept result: each is computed anew when next asked for."""
    _result.cache_clear()
