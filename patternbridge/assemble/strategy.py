"""The dressing strategy, chosen once from the body parts the pattern's pieces sit on.

A garment is dressed one of three ways, decided by its placement data alone
(no piece name, no garment type):

- :attr:`Dressing.TOP`: pieces on the torso and the arms, none on the legs
  (a shirt, a dress, a skirt). The body is dressed with its arms raised (a
  rig permitting), the space between the thighs is filled, seams between two
  pieces of one arm (a cuff on its sleeve) stay open until the arms come down.
- :attr:`Dressing.LEGS`: pieces on the legs, none on the arms (trousers,
  shorts). Dressed in the rest pose; while sewing, the cloth far from the
  seams that start open is pinned, and afterwards the bands round the torso
  and the leg pieces are held where the sewing left them.
- :attr:`Dressing.ACROSS`: pieces on the arms and on the legs (a boiler suit).
  Arms raised as for a top, pins and holds as for the legs, no fill between
  the thighs.

Each strategy is a :class:`Strategy` whose fields the pipeline reads; the
phases it runs are planned from it (:func:`~patternbridge.assemble.phases.plan_phases`).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from ..pattern.model import BodyPart, Pattern

__all__ = ["ARMS", "LEGS", "Dressing", "Strategy", "choose_strategy", "mirror_part", "piece_parts"]

ARMS: frozenset[BodyPart] = frozenset({BodyPart.LEFT_ARM, BodyPart.RIGHT_ARM})
LEGS: frozenset[BodyPart] = frozenset({BodyPart.LEFT_LEG, BodyPart.RIGHT_LEG})
_MIRROR = {
    BodyPart.LEFT_ARM: BodyPart.RIGHT_ARM,
    BodyPart.RIGHT_ARM: BodyPart.LEFT_ARM,
    BodyPart.LEFT_LEG: BodyPart.RIGHT_LEG,
    BodyPart.RIGHT_LEG: BodyPart.LEFT_LEG,
}


class Dressing(str, Enum):
    """How a garment is put on (see the module docstring)."""

    TOP = "top"
    LEGS = "legs"
    ACROSS = "across"

    def __str__(self) -> str:
        return str(self.value)


@dataclass(frozen=True, slots=True, kw_only=True)
class Strategy:
    """What a dressing strategy does; every field follows from :attr:`kind`.

    raise_arms : dress with the arms raised (a rigged or landmark-rigged body),
        then bring them down over keyframes
    pin_far_from_open_seams : while sewing, hold the cloth far (in the pattern)
        from the seams that start open, so closing them does not turn a tube
        round its limb
    hold_after_sewing : after sewing, hold the bands round the torso and the
        limb pieces where the sewing left them
    fill_between_thighs : fill the space between the thighs (nothing goes
        between the legs)
    """

    kind: Dressing
    raise_arms: bool
    pin_far_from_open_seams: bool
    hold_after_sewing: bool
    fill_between_thighs: bool

    @classmethod
    def of(cls, kind: Dressing | str) -> Strategy:
        """The strategy of ``kind`` (the enum or its value)."""
        kind = Dressing(kind)
        legs = kind in (Dressing.LEGS, Dressing.ACROSS)
        return cls(
            kind=kind,
            raise_arms=kind in (Dressing.TOP, Dressing.ACROSS),
            pin_far_from_open_seams=legs,
            hold_after_sewing=legs,
            fill_between_thighs=not legs,
        )


def mirror_part(part: BodyPart) -> BodyPart:
    """The body part on the other side (the torso, the neck and the head are their own mirror)."""
    return _MIRROR.get(BodyPart(part), BodyPart(part))


def piece_parts(pattern: Pattern) -> frozenset[BodyPart]:
    """The body parts the cut copies of the pattern's pieces sit on (mirror copies on the mirrored part)."""
    out: set[BodyPart] = set()
    for piece in pattern.pieces:
        if piece.placement is None:
            continue
        part = BodyPart(piece.placement.body_part)
        out.add(part)
        if piece.quantity.is_pair:
            out.add(mirror_part(part))
    return frozenset(out)


def choose_strategy(pattern: Pattern) -> Strategy:
    """The :class:`Strategy` for ``pattern``, from the body parts its pieces sit on.

    Examples
    --------
    >>> from patternbridge.pattern.model import Pattern
    >>> choose_strategy(Pattern(style="empty", pieces=())).kind is Dressing.TOP
    True
    """
    parts = piece_parts(pattern)
    on_legs, on_arms = bool(parts & LEGS), bool(parts & ARMS)
    if on_legs and on_arms:
        return Strategy.of(Dressing.ACROSS)
    return Strategy.of(Dressing.LEGS if on_legs else Dressing.TOP)
