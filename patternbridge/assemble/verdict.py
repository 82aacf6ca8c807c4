"""The drape's verdict: ``ok``, ``flawed`` or ``failed``, with the reasons, from measured defects.

Each check compares one measured quantity of the finished drape with two
documented limits (:class:`VerdictLimits`): beyond the first the garment is
``flawed`` (usable, the defect shows on a close look), beyond the second it
has ``failed`` (the pictures show a garment that is not worn as designed).
The verdict is the worst of the checks. The checks see what the solver
left before any cosmetic step (the seam gaps are measured before welding)
and the skin is checked by an independent signed-distance query
(:mod:`.skin_check`), not by the solver's collider.

The stretch a drape may show depends on the fabric (:mod:`patternbridge.pattern.fabric`):
:func:`limits_for` gives the limits of a garment cut from a woven, a knit or
a stretch knit, the girth limits from the fabric's stretch across the grain
and the edge limits (:func:`edge_limits`) from its stretch in each edge's
direction to the grain, never below a woven's bias.
"""

from __future__ import annotations

import enum
from collections.abc import Iterable
from dataclasses import dataclass, field, replace

import numpy as np

from ..pattern.fabric import FabricClass, directional

__all__ = ["Check", "Reason", "Verdict", "VerdictLimits", "edge_limits", "judge", "limits_for", "worst"]


class Verdict(str, enum.Enum):
    """How the drape came out, in increasing order of badness."""

    OK = "ok"
    FLAWED = "flawed"
    FAILED = "failed"

    def __str__(self) -> str:
        return self.value

    @property
    def rank(self) -> int:
        """0 for ``ok``, 1 for ``flawed``, 2 for ``failed``."""
        return _RANK[self]


_RANK = {Verdict.OK: 0, Verdict.FLAWED: 1, Verdict.FAILED: 2}


def worst(verdicts: Iterable[Verdict]) -> Verdict:
    """The worst of ``verdicts`` (``ok`` for none)."""
    return max(verdicts, key=lambda v: v.rank, default=Verdict.OK)


class Check(str, enum.Enum):
    """What a reason is about."""

    SEAM_GAP = "seam_gap"  # a seam the simulation left open (before welding)
    SEAM_LENGTH = "seam_length"  # a seam's two sides differ by more than its declared ease
    SELF_CROSSING = "self_crossing"  # triangles of the cloth passing through the cloth
    SKIN = "skin"  # cloth inside the body (independent signed distance)
    STRETCH = "stretch"  # cloth stretched beyond what the fabric takes
    GIRTH = "girth"  # a girth the garment closes round the body only by stretching all the way round
    LEVEL = "level"  # a piece's anchor (a waist, a neck point) off its landmark, or its hem ridden up
    TURNED = "turned"  # cloth worn turned over, its outside facing the body (a twisted strap, a collar inside out)

    def __str__(self) -> str:
        return self.value


@dataclass(frozen=True, slots=True, kw_only=True)
class VerdictLimits:
    """The limits of every check: beyond ``*_flawed`` the drape is flawed, beyond ``*_failed`` it failed.

    seam_gap_flawed_mm, seam_gap_failed_mm : widest gap between sewn
        vertices before welding. Welding moves each side by half the gap:
        2 mm is under the thickness of a seam; at 10 mm the weld drags the
        cloth by 5 mm, a visible pucker, and a seam that wide was torn open
        by the drape.
    seam_length_flawed_cm, seam_length_failed_cm : how much longer one side
        of a seam is than the other, beyond the ease the seam declares. The
        solver gathers the longer side into the shorter, so a pattern error
        would otherwise sew silently into a ruffle.
    self_crossing_flawed, self_crossing_failed : triangles where the cloth
        passes through itself. Any is a defect (a cloth simulation in the
        animator's tool knots there); more than 20 show as a torn, jagged
        region in the pictures.
    skin_depth_flawed_mm, skin_depth_failed_mm : depth of the deepest
        garment point (vertices, edge midpoints, triangle centres) inside the
        skin. Under 1 mm is the tolerance of the skin mesh itself.
    skin_share_failed : share of garment triangles with a point deeper than
        ``skin_depth_flawed_mm`` that fails the drape whatever the depth.
    fabric : the fabric the limits are for (:func:`limits_for`)
    stretch_limit : edge length / pattern length a woven fabric takes
        (about 10 % across the bias; on the grain far less): the least an
        edge of any fabric is allowed, whatever its direction (a triangle
        sheared on the bias stretches its edges that much).
    stretch_flawed_share, stretch_failed_share : share of the cloth's edges
        beyond their flawed limit (``stretch_limit``, or the fabric's worn
        stretch in the edge's direction when larger), and beyond their torn
        limit (``stretch_torn`` or the fabric's stretch limit in that
        direction) (failed): a woven stretched by a third is a tear or a hole
        in the picture.
    girth_flawed, girth_failed : strain of the garment's tightest girth,
        a horizontal cut closing round the body: its length worn on the skin
        (on the drape, less the solver's margin from the skin all the way
        round) over its length in the pattern (:func:`.defects.girth_strain`). A size
        step adds 4 cm to a waist or hip girth, 4-6 % of it: stretched 3 %
        all the way round a girth shows as drag lines (about a size too
        small, and a girth runs along the cross grain, which gives far less
        than the bias); beyond 8 % the garment is two sizes too small for the
        body and does not close round it as designed, however evenly the
        solver spreads the strain over single edges. These are a woven's
        figures; a knit's come from its stretch across the grain
        (:func:`limits_for`).
    level_flawed_cm, level_failed_cm : vertical distance between a piece's
        anchor mark and the body landmark it hangs from (a waistband off the
        waist, a cuff off the wrist, a neck point off the neck).
    hem_rise_flawed_cm, hem_rise_failed_cm : how much nearer a hanging
        piece's hem is to its anchor mark in the drape than in the pattern
        (:func:`~.defects.hem_rise_cm`): a hem ridden up or the cloth bunched
        along the grain. The straight line from the mark to the hem also
        shortens where the piece wraps round the body or its hem breaks on
        the foot (2.4-3.9 cm on the library shorts over the seat, 5.1-6.3 cm
        on the library trousers, shorts and T-shirt on B_slim_female, whose
        pictures show hems where they belong), hence limits above those: 8 cm
        is the anchor's failed limit, a hem plainly off its line; 15 cm is
        another garment (a full-length leg ending at mid-calf).
    turned_flawed_cm2, turned_failed_cm2 : area of the largest patch of cloth
        worn turned over, its outside facing the body, uncovered and reaching
        the cloth's edge (:mod:`.turned`: a twisted strap, a binding sewn on
        inside out). A triangle of the 2.5 cm mesh is 2.7 cm²: beyond two of
        them a strap's width is turned (the loose tank's front strap turned
        at B's shoulder seam, 5.6 cm²), while drapes judged ok measure 0 and
        the hems of flawed trousers and shorts 1.4-1.8 cm² (one rolled in
        above the heel, seen from behind, 9.1 cm²); beyond 20 cm² a
        strap or binding is worn inside out along its length (``GLX0926S16``'s
        armhole bindings sewn on inside out, 23-40 cm² on D, B and E).
    """

    seam_gap_flawed_mm: float = 2.0
    seam_gap_failed_mm: float = 10.0
    seam_length_flawed_cm: float = 1.0
    seam_length_failed_cm: float = 3.0
    self_crossing_flawed: int = 0
    self_crossing_failed: int = 20
    skin_depth_flawed_mm: float = 1.0
    skin_depth_failed_mm: float = 10.0
    skin_share_failed: float = 0.01
    stretch_limit: float = 1.10
    stretch_torn: float = 1.33
    stretch_flawed_share: float = 0.01
    stretch_failed_share: float = 0.01
    girth_flawed: float = 1.03
    girth_failed: float = 1.08
    level_flawed_cm: float = 3.0
    level_failed_cm: float = 8.0
    hem_rise_flawed_cm: float = 8.0
    hem_rise_failed_cm: float = 15.0
    turned_flawed_cm2: float = 5.0
    turned_failed_cm2: float = 20.0
    fabric: FabricClass = FabricClass.WOVEN

    def to_dict(self) -> dict:
        """The fabric and the stretch limits judged against (``fit_report.json`` ``drape.fabric``)."""
        s = self.fabric.stretch
        return {
            "class": self.fabric.value,
            "stretch": s.to_dict(),
            "girth_flawed": round(self.girth_flawed, 4),
            "girth_failed": round(self.girth_failed, 4),
            "edge_flawed": {
                "along": round(max(self.stretch_limit, 1.0 + s.along_worn), 4),
                "across": round(max(self.stretch_limit, 1.0 + s.across_worn), 4),
            },
            "edge_torn": {
                "along": round(max(self.stretch_torn, 1.0 + s.along_limit), 4),
                "across": round(max(self.stretch_torn, 1.0 + s.across_limit), 4),
            },
        }


def limits_for(fabric: FabricClass | str, base: VerdictLimits | None = None) -> VerdictLimits:
    """The verdict's limits for a garment cut from ``fabric``.

    The girth limits are ``base``'s (a woven's: a size too small is flawed,
    two sizes failed) shifted by the fabric's worn stretch across the grain
    (:data:`~patternbridge.pattern.fabric.FABRIC_STRETCH`): a knit drafted
    under the body is judged as a woven garment that much larger, so a knit
    two sizes too small for the body still fails.

    Examples
    --------
    >>> lim = limits_for("stretch_knit")
    >>> round(lim.girth_flawed, 2), round(lim.girth_failed, 2)
    (1.18, 1.23)
    >>> limits_for("woven").girth_failed
    1.08
    """
    fabric = FabricClass(fabric)
    base = base or VerdictLimits()
    worn = fabric.stretch.across_worn
    return replace(base, fabric=fabric, girth_flawed=base.girth_flawed + worn, girth_failed=base.girth_failed + worn)


def edge_limits(
    lim: VerdictLimits, fabrics: tuple[FabricClass, ...], group: np.ndarray, grain: np.ndarray, d: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The flawed and torn limit (edge length / pattern length) of every edge, from its fabric and direction.

    Parameters
    ----------
    fabrics : the fabric of every piece instance ; group : (E,) int64, the instance of each edge
    grain : (G, 2) float64, the unit grain direction of each instance in pattern coordinates
    d : (E, 2) float64, each edge's direction in the pattern

    Returns
    -------
    flawed, torn : (E,) float64, at least ``lim.stretch_limit`` and ``lim.stretch_torn``
    """
    stretch = [f.stretch for f in fabrics]
    along_w, across_w, along_l, across_l = (
        np.array([getattr(s, a) for s in stretch] or [0.0])[group]
        for a in ("along_worn", "across_worn", "along_limit", "across_limit")
    )
    g = np.asarray(grain, dtype=np.float64).reshape(-1, 2)[group] if len(group) else np.zeros((0, 2))
    flawed = np.maximum(lim.stretch_limit, 1.0 + directional(along_w, across_w, g, d))
    torn = np.maximum(lim.stretch_torn, 1.0 + directional(along_l, across_l, g, d))
    return flawed, torn


@dataclass(frozen=True, slots=True, kw_only=True)
class Reason:
    """One check beyond its limit.

    value : the measured quantity, in ``unit``
    limit : the limit it passed (the flawed or the failed one, after ``verdict``)
    where : the seams or pieces concerned, worst first
    """

    check: Check
    verdict: Verdict
    value: float
    limit: float
    unit: str
    where: tuple[str, ...]
    message: str

    def to_dict(self) -> dict:
        """JSON form (``fit_report.json``)."""
        return {
            "check": self.check.value,
            "verdict": self.verdict.value,
            "value": round(self.value, 3),
            "limit": self.limit,
            "unit": self.unit,
            "where": list(self.where),
            "message": self.message,
        }


@dataclass(frozen=True, slots=True, kw_only=True)
class Measured:
    """The quantities the verdict judges, measured on the finished drape.

    seam_gaps_mm : seam id -> widest gap between its sewn vertices before welding
    seam_excess_cm : seam id -> |length difference of its sides - declared ease|
    self_crossing : piece -> triangles passing through the cloth
    skin_depth_mm : deepest garment point inside the skin (0 when none)
    skin_share : share of garment triangles with a point inside deeper than the flawed limit
    skin_pieces : pieces with such triangles
    stretch_share : share of measured edges beyond ``stretch_limit``
    torn_share : share beyond ``stretch_torn``
    stretch_pieces : pieces with edges beyond ``stretch_limit``, most first
    levels_cm : piece instance -> |height of its anchor mark - height of its landmark|
    girth_strain : the strain of the tightest girth (length worn on the skin / pattern length of a horizontal cut)
    girth_height_cm : the height of that cut ; girth_pieces : the pieces it crosses
    hem_rise_cm : piece instance -> how much nearer its hem hangs to its anchor than in the pattern
    turned_cm2 : piece instance -> area of the largest patch of its cloth worn turned over (:mod:`.turned`)
    """

    seam_gaps_mm: dict[str, float]
    seam_excess_cm: dict[str, float]
    self_crossing: dict[str, int]
    skin_depth_mm: float
    skin_share: float
    skin_pieces: tuple[str, ...]
    stretch_share: float
    torn_share: float
    stretch_pieces: tuple[str, ...]
    levels_cm: dict[str, float]
    girth_strain: float = 1.0
    girth_height_cm: float = 0.0
    girth_pieces: tuple[str, ...] = ()
    hem_rise_cm: dict[str, float] = field(default_factory=dict)
    turned_cm2: dict[str, float] = field(default_factory=dict)


def _grade(value: float, flawed: float, failed: float) -> Verdict:
    if value > failed:
        return Verdict.FAILED
    if value > flawed:
        return Verdict.FLAWED
    return Verdict.OK


def _worst_keys(values: dict[str, float], above: float) -> tuple[str, ...]:
    return tuple(k for k, v in sorted(values.items(), key=lambda kv: -kv[1]) if v > above)


def _largest(
    check: Check, values: dict[str, float], flawed: float, failed: float, unit: str, what: str
) -> Reason | None:
    """A reason for the largest of ``values`` when it passes ``flawed``."""
    if not values:
        return None
    top = max(values.values())
    verdict = _grade(top, flawed, failed)
    if verdict is Verdict.OK:
        return None
    limit = failed if verdict is Verdict.FAILED else flawed
    where = _worst_keys(values, flawed)
    shown = ", ".join(f"{k} {values[k]:.1f}" for k in where[:3]) + (", ..." if len(where) > 3 else "")
    return Reason(
        check=check,
        verdict=verdict,
        value=top,
        limit=limit,
        unit=unit,
        where=where,
        message=f"{what} {top:.1f} {unit} (limit {limit:g} {unit}): {shown}",
    )


def _self_crossing_reason(m: Measured, lim: VerdictLimits) -> Reason | None:
    """Too many triangles passing through the cloth, or None."""
    n_self = sum(m.self_crossing.values())
    v = _grade(n_self, lim.self_crossing_flawed, lim.self_crossing_failed)
    if v is not Verdict.OK:
        where = _worst_keys({k: float(c) for k, c in m.self_crossing.items()}, 0.0)
        limit = lim.self_crossing_failed if v is Verdict.FAILED else lim.self_crossing_flawed
        return Reason(
            check=Check.SELF_CROSSING,
            verdict=v,
            value=float(n_self),
            limit=float(limit),
            unit="triangles",
            where=where,
            message=f"{n_self} triangles pass through the cloth (limit {limit}): "
            + ", ".join(f"{k} {m.self_crossing[k]}" for k in where[:3]),
        )
    return None


def _skin_reason(m: Measured, lim: VerdictLimits) -> Reason | None:
    """Cloth too deep inside the skin, or on too many triangles, or None."""
    v = _grade(m.skin_depth_mm, lim.skin_depth_flawed_mm, lim.skin_depth_failed_mm)
    value, limit, unit = (
        m.skin_depth_mm,
        lim.skin_depth_failed_mm if v is Verdict.FAILED else lim.skin_depth_flawed_mm,
        "mm",
    )
    if v is not Verdict.FAILED and m.skin_share > lim.skin_share_failed:
        v, value, limit, unit = Verdict.FAILED, 100 * m.skin_share, 100 * lim.skin_share_failed, "% of triangles"
    if v is not Verdict.OK:
        return Reason(
            check=Check.SKIN,
            verdict=v,
            value=value,
            limit=limit,
            unit=unit,
            where=m.skin_pieces,
            message=f"cloth inside the skin up to {m.skin_depth_mm:.1f} mm deep on "
            f"{100 * m.skin_share:.1f} % of the triangles (limit {limit:g} {unit}): {', '.join(m.skin_pieces[:3])}",
        )
    return None


def _stretch_reason(m: Measured, lim: VerdictLimits) -> Reason | None:
    """Too many edges stretched (flawed) or torn (failed), or None."""
    v = Verdict.FAILED if m.torn_share > lim.stretch_failed_share else Verdict.OK
    if v is Verdict.OK and m.stretch_share > lim.stretch_flawed_share:
        v = Verdict.FLAWED
    if v is not Verdict.OK:
        share, ratio, limit = (
            (m.torn_share, lim.stretch_torn, lim.stretch_failed_share)
            if v is Verdict.FAILED
            else (m.stretch_share, lim.stretch_limit, lim.stretch_flawed_share)
        )
        word = "limit" if v is Verdict.FAILED else "worn stretch"
        return Reason(
            check=Check.STRETCH,
            verdict=v,
            value=100 * share,
            limit=100 * limit,
            unit="% of edges",
            where=m.stretch_pieces,
            message=f"{100 * share:.1f} % of the edges (limit {100 * limit:g} %) stretched beyond the "
            f"{lim.fabric.value.replace('_', ' ')}'s {word} (at least {ratio:g} x their pattern length): "
            + ", ".join(m.stretch_pieces[:3]),
        )
    return None


def _girth_reason(m: Measured, lim: VerdictLimits) -> Reason | None:
    """A girth stretched all the way round beyond what a size's ease allows, or None."""
    v = _grade(m.girth_strain, lim.girth_flawed, lim.girth_failed)
    if v is Verdict.OK:
        return None
    limit = lim.girth_failed if v is Verdict.FAILED else lim.girth_flawed
    return Reason(
        check=Check.GIRTH,
        verdict=v,
        value=100 * (m.girth_strain - 1.0),
        limit=round(100 * (limit - 1.0), 6),
        unit="% strain",
        where=m.girth_pieces,
        message=f"the girth at {m.girth_height_cm:.0f} cm is stretched {100 * (m.girth_strain - 1.0):.1f} % all "
        f"the way round (limit {100 * (limit - 1.0):g} % for a {lim.fabric.value.replace('_', ' ')}): the garment "
        "is too small there; " + ", ".join(m.girth_pieces[:3]),
    )


def judge(m: Measured, limits: VerdictLimits | None = None) -> tuple[Verdict, tuple[Reason, ...]]:
    """The verdict on a drape and the reasons for it, worst first.

    Examples
    --------
    >>> m = Measured(seam_gaps_mm={"side": 12.0}, seam_excess_cm={}, self_crossing={}, skin_depth_mm=0.0,
    ...     skin_share=0.0, skin_pieces=(), stretch_share=0.0, torn_share=0.0, stretch_pieces=(), levels_cm={})
    >>> verdict, reasons = judge(m)
    >>> str(verdict), reasons[0].check.value
    ('failed', 'seam_gap')
    """
    lim = limits or VerdictLimits()
    reasons = [
        _largest(
            Check.SEAM_GAP,
            m.seam_gaps_mm,
            lim.seam_gap_flawed_mm,
            lim.seam_gap_failed_mm,
            "mm",
            "seams open before welding by up to",
        ),
        _largest(
            Check.SEAM_LENGTH,
            m.seam_excess_cm,
            lim.seam_length_flawed_cm,
            lim.seam_length_failed_cm,
            "cm",
            "seam sides differ beyond their ease by up to",
        ),
        _largest(
            Check.LEVEL,
            m.levels_cm,
            lim.level_flawed_cm,
            lim.level_failed_cm,
            "cm",
            "pieces hang off their landmark by up to",
        ),
        _largest(
            Check.LEVEL,
            m.hem_rise_cm,
            lim.hem_rise_flawed_cm,
            lim.hem_rise_failed_cm,
            "cm",
            "hems ride up towards their anchor by up to",
        ),
        _largest(
            Check.TURNED,
            m.turned_cm2,
            lim.turned_flawed_cm2,
            lim.turned_failed_cm2,
            "cm²",
            "cloth worn turned over, its outside facing the body, over up to",
        ),
    ]
    reasons += [_self_crossing_reason(m, lim), _skin_reason(m, lim), _stretch_reason(m, lim), _girth_reason(m, lim)]
    found = sorted((r for r in reasons if r is not None), key=lambda r: -r.verdict.rank)
    return worst(r.verdict for r in found), tuple(found)
