"""Results of the bridge inference: roles, orientation, joins and the whole inference."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..pattern.model import Role

__all__ = ["BridgeInference", "Join", "Orientation", "Role", "RoleGuess", "Side", "is_band", "is_body"]


_BODY = {Role.FRONT, Role.BACK, Role.LEG, Role.LEG_FRONT, Role.LEG_BACK}
_BAND = {
    Role.NECKBAND,
    Role.NECK_BINDING,
    Role.ARMHOLE_BINDING,
    Role.CUFF,
    Role.WAISTBAND,
    Role.COLLAR,
    Role.COLLAR_STAND,
}


def is_body(role: Role | None) -> bool:
    """Front, back or a leg: a piece that carries the garment's girths."""
    return role in _BODY


def is_band(role: Role | None) -> bool:
    """A strip sewn along an opening (binding, band, cuff, collar)."""
    return role in _BAND


@dataclass(frozen=True, slots=True, kw_only=True)
class RoleGuess:
    """A piece's role and how sure the inference is (0..1); ``why`` names the evidence."""

    role: Role
    confidence: float
    why: str = ""


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Orientation:
    """The turn that stands a piece upright in the library's conventions.

    turn_rad : counter-clockwise rotation about the origin, radians, applied to
        the designer's drawing (grain along the body, +y up the body)
    offset : (2,) float64 cm, translation after the turn (centre line at x = 0)
    fold : (start, end) outline vertices of a straight fold edge (a half piece
        cut on the fold), or None
    whole : drawn whole: mirror-symmetric about its vertical mid-line (x = 0 after the turn)
    centre_on_right : after the turn, the centre line (fold or centre seam) lies
        on the piece's +x side, as the library draws a right-side front
    confidence : 0..1, how clear the evidence for "up" was
    """

    turn_rad: float
    offset: np.ndarray
    fold: tuple[int, int] | None = None
    centre_on_right: bool = True
    whole: bool = False
    confidence: float = 1.0
    why: str = ""

    def __post_init__(self) -> None:
        off = np.array(self.offset, dtype=np.float64).reshape(2)
        off.flags.writeable = False
        object.__setattr__(self, "offset", off)

    @property
    def turn_deg(self) -> float:
        return float(np.degrees(self.turn_rad))

    def apply(self, points: np.ndarray) -> np.ndarray:
        """``points`` (..., 2) cm in the designer's frame, turned upright."""
        c, s = np.cos(self.turn_rad), np.sin(self.turn_rad)
        rot = np.array([[c, -s], [s, c]])
        return np.asarray(points, dtype=np.float64) @ rot.T + self.offset


@dataclass(frozen=True, slots=True, kw_only=True)
class Side:
    """One boundary range of a join: ``piece`` from vertex ``start`` to ``end`` (outline order)."""

    piece: str
    start: int
    end: int
    length_cm: float = 0.0

    @property
    def key(self) -> tuple[str, int, int]:
        return (self.piece, self.start, self.end)


@dataclass(frozen=True, slots=True, kw_only=True)
class Join:
    """A seam at the edge level: range ``a`` sewn to range ``b``.

    kind : ``seam``, ``fold`` (a half piece's fold edge, a == b), ``centre``
        (an edge sewn to the same edge of the piece's mirror copy), ``band``
        (a band's edge sewn along one stretch of an opening)
    ease_cm : len(b) - len(a) in the sample size
    spans : for a ``band`` join, where each copy of ``a`` the band runs along
        lies on ``b``: ``(copy of a, start, end)``, fractions of ``b``'s sew-line
        length from ``b.start`` (:mod:`.band_spans`); empty when not placed
    copy_a, copy_b : the copies sewn (``primary`` as drawn, ``mirror``); a
        sidecar writes the band's ``spans`` as ordinary seams on these copies
    """

    id: str
    a: Side
    b: Side
    kind: str = "seam"
    confidence: float = 1.0
    ease_cm: float = 0.0
    why: str = ""
    spans: tuple[tuple[str, float, float], ...] = ()
    copy_a: str | None = None
    copy_b: str | None = None


@dataclass(frozen=True, slots=True, kw_only=True)
class Trim:
    """A band applied flat, worn trimmed to the opening it binds (:mod:`.band_spans`).

    A strip cut longer than its opening is sewn from one end and the excess cut
    off where the sewing meets its start; the drape wears it so
    (:mod:`.worn`). ``start`` and ``end`` are the band vertices where the sewn
    range begins and ends on the sewn edge (outline order), ``start_across`` and
    ``end_across`` the vertices straight across the strip from them: the two
    cut lines. The designer's file keeps the whole strip.
    """

    piece: str
    start: int
    start_across: int
    end: int
    end_across: int


@dataclass(frozen=True, slots=True, kw_only=True)
class BridgeInference:
    """Everything inferred for one pattern.

    roles : piece name -> RoleGuess
    orientations : piece name -> Orientation
    joins : the seams at the edge level (one-to-one except band edges, which
        run along several stretches of an opening)
    alternatives : groups of interchangeable piece sets; the first set of each
        group is the default
    chosen : the pieces of the default consistent garment
    trims : bands applied flat, worn cut to their opening (set by :func:`.band_spans.split_bands`)
    """

    roles: dict[str, RoleGuess]
    orientations: dict[str, Orientation]
    joins: tuple[Join, ...]
    alternatives: tuple[tuple[tuple[str, ...], ...], ...] = ()
    chosen: tuple[str, ...] = ()
    seconds: float = 0.0
    notes: tuple[str, ...] = field(default_factory=tuple)
    trims: tuple[Trim, ...] = ()

    @property
    def lowest_confidence(self) -> float:
        values = [g.confidence for g in self.roles.values()]
        values += [j.confidence for j in self.joins]
        return min(values, default=1.0)
