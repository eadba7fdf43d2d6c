"""
An engagement's moves onto the cams, planned together: each axis's move (moves.plan_move), then
the machine's check of them all against its interference pairs (the moves as they are, delayed
one after another, or refused naming the pair).

A pure function of what the axes gave when the moves came due (MoveRequest, and what every other
axis does meanwhile), so SlaveAxes can have it computed off the master thread.
"""
from __future__ import annotations

from typing import Callable, Mapping, Optional, Union

from .slave_path import Held
from .moves import MasterMotion, Move, MoveRequest, on_cam

#: Checks every axis's move (by axis name; an axis on its cam or holding: a move of duration 0)
#: with the virtual master's motion: the moves to make (some delayed to their turn), or why none.
CheckMoves = Callable[[Mapping[str, Move], MasterMotion], Union[Mapping[str, Move], str]]


def plan_engagement(requests: Mapping[str, MoveRequest], others: Mapping[str, Move],
                    master: MasterMotion,
                    check: Optional[CheckMoves]) -> dict[str, Union[Move, str]]:
    """Return each requesting axis's move to make, or why it does not move.

    others: what every other axis does meanwhile (Follower.during). An axis whose move cannot be
    made is checked holding where it is; when the check refuses, every move is refused with its
    reason.
    """
    planned = {name: request.plan() for name, request in requests.items()}
    moves = {name: found for name, found in planned.items() if isinstance(found, Move)}
    if not moves or check is None:
        return planned
    held = {name: on_cam(Held(requests[name].start.position), requests[name].limits, master)
            for name, found in planned.items() if isinstance(found, str)}
    checked = check({**others, **held, **moves}, master)
    if isinstance(checked, str):
        return {**planned, **{name: checked for name in moves}}
    return {**planned, **{name: checked[name] for name in moves}}
