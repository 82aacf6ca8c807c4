"""The fabric a pattern is cut from, read off the pattern: its ease against the body and its fabric words.

A garment that is smaller than the body at a girth it closes round
(negative ease) goes on only if the fabric stretches: it is a knit, and a
stretch knit when it is smaller by more than a plain knit is drafted to
(``KNIT_AT_MOST``, 10 %: the top of the 0-10 % range jersey tops are drafted
in, :data:`~patternbridge.pattern.fabric.FABRIC_STRETCH`). The negative ease must
pass ``NEGATIVE_EASE_SHARE`` of the body girth: a body read off a size chart
for the file's sample size is known to about half a size step (a size adds
4 cm to an 84-100 cm girth, 4-5 %), so a pattern 1 % under the chart's body
says nothing about its fabric.

A **pullover** (no placket, every front and back closed at its centre line:
on a fold, drawn whole or sewn to its mirror copy) goes on over the head. A
woven neck opening gives only its limit stretch across the grain
(:data:`~patternbridge.pattern.fabric.FABRIC_STRETCH`, 5 %), so a neck
opening that even stretched that far is smaller than the head girth of the
file's size system (:data:`~.size_chart.HEAD_GIRTH_CM`) is cut from a knit:
the crew necks of the shared T-shirts (48.7 and 51.9 cm against the men's
57 cm head) are; the tanks' scoops (55.5-61.1 cm against the women's 55 cm)
and the CLO shirt's neck (57.3 cm) say nothing.

The words a file writes on a piece (its category and material annotation,
``1XRIB``, ``JERSEY``, ``DENIM``, in several languages) are hints: they
name the fabric of that piece, and the garment's when they are written on its
body pieces. Positive ease says nothing (a jersey T-shirt and a woven shirt
both have it): such a garment stays woven, the stricter limits, unless its
words say otherwise.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType

from ..pattern.fabric import FABRIC_STRETCH, FabricClass
from ..pattern.model import MeasurementLink, Pattern, Piece
from .bands import side_parts
from .model import BridgeInference, Role, RoleGuess, is_band
from .openings import openings

__all__ = [
    "KNIT_AT_MOST",
    "NEGATIVE_EASE_SHARE",
    "FabricInference",
    "infer_fabric",
    "pullover_neck_cm",
    "word_fabric",
]

NEGATIVE_EASE_SHARE = 0.025
"""A girth's ease below minus this share of the body girth says the fabric stretches."""
KNIT_AT_MOST = 0.10
"""A plain knit is drafted at most this much under the body; more needs elastane (a stretch knit)."""

_WORDS: tuple[tuple[FabricClass, tuple[str, ...]], ...] = (
    (FabricClass.STRETCH_KNIT, ("LYCRA", "SPANDEX", "ELASTANE", "ELASTHAN", "ELASTAN", "POWERNET")),
    (
        FabricClass.KNIT,
        ("RIB", "JERSEY", "PIQUE", "PIQUÉ", "INTERLOCK", "FLEECE", "KNIT", "TRICOT", "MAILLE", "STRICK", "PUNTO"),
    ),
    (
        FabricClass.WOVEN,
        ("WOVEN", "DENIM", "TWILL", "POPLIN", "CANVAS", "OXFORD", "CHAMBRAY", "GABARDINE", "TISSE", "GEWEBE"),
    ),
)
_STRETCH_ORDER = {FabricClass.WOVEN: 0, FabricClass.KNIT: 1, FabricClass.STRETCH_KNIT: 2}


@dataclass(frozen=True, slots=True, kw_only=True)
class FabricInference:
    """The garment's fabric class and why, and the pieces whose own words name another class."""

    fabric: FabricClass
    why: str
    pieces: Mapping[str, FabricClass] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "pieces", MappingProxyType(dict(self.pieces)))


def word_fabric(piece: Piece) -> tuple[FabricClass, str] | None:
    """The fabric class the piece's category, material annotation or fabric text names, with the word, or None.

    Examples
    --------
    >>> from patternbridge.pattern.model import Piece
    >>> word_fabric(Piece(name="CO", outline=[[0, 0], [1, 0], [0, 1]], annotation="1XRIB"))
    (<FabricClass.KNIT: 'knit'>, 'RIB')
    """
    text = " ".join((piece.category, piece.annotation, piece.fabric)).upper()
    for fabric, words in _WORDS:
        for w in words:
            if w in text:
                return fabric, w
    return None


def pullover_neck_cm(pattern: Pattern, inference: BridgeInference) -> float | None:
    """The neck opening (cm, every copy counted) of a garment that goes on over the head, or None.

    None when the garment opens: a placket among its pieces, or a front or back
    whose centre line is neither a fold, nor drawn whole, nor sewn to its
    mirror copy; or when it has no neckline. The opening is the neckline's free
    edge before any band is sewn to it (a band only makes it smaller).
    """
    chosen = set(inference.chosen)
    roles = {n: inference.roles[n].role for n in chosen}
    if Role.PLACKET in roles.values():
        return None
    centred = {side.piece for j in inference.joins if j.kind in ("centre", "fold") for side in (j.a, j.b)}
    for name, role in roles.items():
        o = inference.orientations[name]
        if role in (Role.FRONT, Role.BACK) and o.fold is None and not o.whole and name not in centred:
            return None
    used = {
        (side.piece, part)
        for j in inference.joins
        if j.kind != "band"
        for side in (j.a, j.b)
        for part in side_parts(pattern, side)
    }
    opened = openings(pattern, used, dict(inference.roles), inference.orientations, chosen)
    whole = [o.length_cm for o in opened if o.kind == "neck" and not o.part]
    return whole[0] if whole else None


def _over_the_head(neck_cm: float | None, body: Mapping[str, float]) -> str | None:
    """Why a woven could not go over the head through a neck opening of ``neck_cm``, or None."""
    head, give = body.get("head_girth"), FABRIC_STRETCH[FabricClass.WOVEN].across_limit
    if neck_cm is None or head is None or neck_cm * (1.0 + give) >= head:
        return None
    return (
        f"a pullover whose neck opening of {neck_cm:.1f} cm, stretched {100 * give:g} % as a woven gives, "
        f"is under the head girth of {head:g} cm: it goes over the head only by stretching"
    )


def _tightest(links: Sequence[MeasurementLink], body: Mapping[str, float]) -> tuple[float, MeasurementLink] | None:
    """The girth link with the most negative ease as a share of its body girth, or None."""
    girths = [
        (m.ease_cm / body[m.measurement], m)
        for m in links
        if "girth" in m.id and "girth" in m.measurement and body.get(m.measurement, 0.0) > 0.0
    ]
    return min(girths, key=lambda g: g[0], default=None)


def infer_fabric(
    pattern: Pattern,
    roles: Mapping[str, RoleGuess],
    chosen: Sequence[str],
    links: Sequence[MeasurementLink],
    body: Mapping[str, float],
    *,
    neck_cm: float | None = None,
) -> FabricInference:
    """The fabric of the chosen garment from its links' ease against ``body``, its neck and the pieces' words.

    Parameters
    ----------
    roles : piece -> inferred role ; chosen : the garment's pieces
    links : the measurement links read off the pattern (:mod:`.links`), ease in cm
    body : the sample body the ease was read against, measurement id -> cm (``head_girth`` among them)
    neck_cm : the neck opening of a pullover (:func:`pullover_neck_cm`), None for a garment that opens
    """
    words = {name: word_fabric(pattern.piece(name)) for name in chosen}
    body_pieces = [n for n in chosen if not is_band(roles[n].role) and roles[n].role is not Role.INTERLINING]
    said = [(n, w) for n in body_pieces if (w := words[n]) is not None]
    fabric, why = FabricClass.WOVEN, "no negative ease at a linked girth and no fabric word on the body pieces"
    if said:
        name, (fabric, word) = max(said, key=lambda s: _STRETCH_ORDER[s[1][0]])
        why = f"{name} says {word!r}"
    head = _over_the_head(neck_cm, body)
    if head is not None and _STRETCH_ORDER[FabricClass.KNIT] > _STRETCH_ORDER[fabric]:
        fabric, why = FabricClass.KNIT, head
    tight = _tightest(links, body)
    if tight is not None and tight[0] < -NEGATIVE_EASE_SHARE:
        share, link = tight
        knit = KNIT_AT_MOST
        need = FabricClass.STRETCH_KNIT if -share > knit else FabricClass.KNIT
        if _STRETCH_ORDER[need] >= _STRETCH_ORDER[fabric]:
            fabric = need
            why = (
                f"{link.id} {link.ease_cm:+.1f} cm against the body's {body[link.measurement]:.1f} cm "
                f"({100 * share:+.1f} %): it goes on only by stretching "
                + (
                    f"more than a plain knit is drafted to ({100 * knit:g} %)"
                    if need is FabricClass.STRETCH_KNIT
                    else ""
                )
            ).rstrip()
    trims = {n: w[0] for n in chosen if (w := words[n]) is not None and n not in body_pieces and w[0] is not fabric}
    if trims:
        why += "; " + ", ".join(f"{n} {f}" for n, f in sorted(trims.items()))
    return FabricInference(fabric=fabric, why=why, pieces=trims)
