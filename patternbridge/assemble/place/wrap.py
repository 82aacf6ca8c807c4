"""Wrap the pieces on body-part proxies: a bounding cylinder per part, and a ring round the hips above the crotch.

Each body part gets a cylinder: the torso and the head stand on the vertical
axis, the limbs on the principal axis of their vertices (PCA), pointing
toward the body. Its radius is a little above the part's typical radius
(90th percentile; thicker places are cleared when wrapping), or the width
of the pieces side by side at one height divided by 2π when that is larger
(the pieces then lie side by side around it, as in the source method). A
piece is laid on the unrolled cylinder with its anchor mark on the anchor
landmark: pattern +x runs around the cylinder (to the right as seen from
outside), pattern +y along the axis toward the body (up for the torso and
legs, toward the shoulder for a sleeve), then it is wrapped. Points that
would still fall inside the body are moved out along their radius. Pieces
going round a limb and sewn to themselves (sleeves) are wrapped as tubes, one
turn per pattern row; the fronts and backs of a trouser leg share one radius
per height, and the rows of any leg piece above the crotch go round the
hips (a one-piece leg, sewn to its mirror copy at both rises, from centre
front to centre back). The rows by a leg's hem keep the
width of the pieces side by side there (a slanted hem would otherwise fold
in across the leg). The seams
this leaves open (over the shoulders, to a cuff, a collar or a yoke) are
closed by :mod:`.seam_graph`.

Frame of a cylinder: ``axis`` (proximal direction), ``e0`` (angle 0, the
front), ``e1 = axis x e0`` (angle +π/2, the right as seen from outside).
"""

from __future__ import annotations

import itertools
import logging
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...pattern.model import BINDING_ROLES, BodyPart, Copy, Pattern, Side
from ...report import Report
from ..bodyparts import HAND_SHARE, PARTS, BodyParts, crotch_height, limb_axis
from ..mesh2d import Instance, PatternMesh
from ..strategy import LEGS, mirror_part
from .length import CROTCH_LANDMARK, crotch_drop, length_stretches

__all__ = ["BAND_PARTS", "Cylinder", "bounding_cylinders", "landmark_position", "mirror_name", "place_instances"]

log = logging.getLogger(__name__)

MARGIN_CM = 1.5  # cylinder radius above the part's typical radius
CLEARANCE_CM = 1.0  # distance kept from the skin when a wrapped point is moved out
TYPICAL_RADIUS_PERCENTILE = 90.0  # of the distances from the axis: a limb's or the torso's cylinder radius
_DISTAL = {
    BodyPart.LEFT_ARM: HAND_SHARE,
    BodyPart.RIGHT_ARM: HAND_SHARE,
    BodyPart.LEFT_LEG: 0.12,
    BodyPart.RIGHT_LEG: 0.12,
}  # share of a limb's length taken by the hand / the foot
LIMBS = frozenset(_DISTAL)
#: parts a band goes round once on its own length, about the body's cross-section at its anchor (a waistband, a
#: collar); round a limb a ring is a tube (a sleeve, a cuff)
BAND_PARTS = frozenset({BodyPart.TORSO, BodyPart.HEAD})


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Cylinder:
    """A bounding cylinder.

    center : (3,) cm ; axis, e0, e1 : (3,) unit vectors ; radius_cm : cm ;
    body_radius_cm : the part's largest distance from the axis ; height range
    of the part along the axis: ``h_min``, ``h_max`` (cm from ``center``).
    """

    part: BodyPart
    center: np.ndarray
    axis: np.ndarray
    e0: np.ndarray
    e1: np.ndarray
    radius_cm: float
    body_radius_cm: float
    h_min: float
    h_max: float

    def coordinates(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(theta rad, h cm, r cm) of ``points`` (n, 3)."""
        d = np.asarray(points, dtype=np.float64) - self.center
        h = d @ self.axis
        radial = d - h[:, None] * self.axis
        return (
            np.arctan2(radial @ self.e1, radial @ self.e0),
            h,
            np.linalg.norm(radial, axis=1),
        )

    def points(self, theta: np.ndarray, h: np.ndarray, r: np.ndarray | float | None = None) -> np.ndarray:
        """(n, 3) positions at angle ``theta``, height ``h`` and radius ``r`` (default: the cylinder's)."""
        r = self.radius_cm if r is None else r
        r = np.broadcast_to(np.asarray(r, dtype=np.float64), np.shape(theta))
        return (
            self.center
            + h[:, None] * self.axis
            + (r * np.cos(theta))[:, None] * self.e0
            + (r * np.sin(theta))[:, None] * self.e1
        )


def mirror_name(name: str) -> str:
    """Swap left and right in a landmark or body-part name (``x_left`` ↔ ``x_right``)."""
    for a, b in (("left", "right"), ("right", "left")):
        if a in name:
            return name.replace(a, b)
    return name


def _frame(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    front = np.array([0.0, 0.0, 1.0])
    e0 = front - (front @ axis) * axis
    if np.linalg.norm(e0) < 0.3:
        up = np.array([0.0, 1.0, 0.0])
        e0 = up - (up @ axis) * axis
    e0 /= np.linalg.norm(e0)
    return e0, np.cross(axis, e0)


def bounding_cylinders(
    vertices: np.ndarray, parts: BodyParts, widths_cm: dict[str, float] | None = None
) -> dict[str, Cylinder]:
    """One bounding cylinder per body part.

    Parameters
    ----------
    vertices : (V, 3) float64, cm — the body in the pose used for dressing
    parts : body-part labels of those vertices
    widths_cm : part -> summed width of the pieces it carries (cm); the radius
        is at least width / 2π

    Returns
    -------
    dict part name -> :class:`Cylinder`
    """
    v = np.asarray(vertices, dtype=np.float64)
    widths_cm = widths_cm or {}
    torso = v[parts.mask(BodyPart.TORSO)]
    torso_c = 0.5 * (torso.min(axis=0) + torso.max(axis=0))
    out = {}
    for part in PARTS:
        pv = v[parts.mask(part)]
        if len(pv) < 10:
            continue
        if part not in LIMBS:
            axis = np.array([0.0, 1.0, 0.0])
            c = 0.5 * (pv.min(axis=0) + pv.max(axis=0))
        else:
            c, axis = limb_axis(pv, torso_c)
            # leave the hand or the foot out (the distal share of the limb's length)
            h = (pv - c) @ axis
            pv = pv[h > h.min() + _DISTAL[part] * np.ptp(h)]
            c, axis = limb_axis(pv, torso_c)
        e0, e1 = _frame(axis)
        d = pv - c
        h = d @ axis
        r = np.linalg.norm(d - h[:, None] * axis, axis=1)
        body_r = float(np.max(r))
        # the pieces should go all the way round a limb or the torso, or the
        # seams would start a hand's width open and pull the cloth across
        # the body: the typical radius is used and the thicker parts (a
        # shoulder, a belly) are cleared along the radius when wrapping
        base = body_r if part is BodyPart.HEAD else float(np.percentile(r, TYPICAL_RADIUS_PERCENTILE))
        radius = max(base + MARGIN_CM, widths_cm.get(part, 0.0) / (2 * np.pi))
        out[part] = Cylinder(
            part=part,
            center=c,
            axis=axis,
            e0=e0,
            e1=e1,
            radius_cm=radius,
            body_radius_cm=body_r,
            h_min=float(h.min()),
            h_max=float(h.max()),
        )
    return out


def instance_part(pattern: Pattern, inst: Instance) -> BodyPart:
    """Body part the instance wraps (the mirror copy goes on the mirrored part; a neck piece on the head's)."""
    part = pattern.piece(inst.piece).placement.body_part
    part = BodyPart.HEAD if part is BodyPart.NECK else part
    return mirror_part(part) if inst.copy is Copy.MIRROR else part


def instance_points2d(pmesh: PatternMesh, inst: Instance) -> np.ndarray:
    """(n, 2) pattern coordinates of a cut copy (the mirror copy flipped in x)."""
    pts = pmesh.pieces[inst.piece].points
    return pts * np.array([-1.0, 1.0]) if inst.copy is Copy.MIRROR else pts.copy()


def landmark_position(character, vertices: np.ndarray, name: str, mirrored: bool) -> np.ndarray | None:
    """(3,) position of landmark ``name`` on ``vertices`` (its mirror for a mirrored copy), or None if absent."""
    lm = character.landmarks
    if mirrored:
        mname = mirror_name(name)
        if mname != name and mname in lm:
            name = mname
        elif name in lm:
            p = landmark_position(character, vertices, name, False)
            return None if p is None else p * np.array([-1.0, 1.0, 1.0])
    if name not in lm:
        return None
    mark = lm[name]
    return mark.at(vertices, character.faces)


#: a limb landmark -> the landmarks below it down the limb, that a placement's ``drop_cm`` walks along
_DOWN_THE_LIMB = {
    "shoulder_point": ("elbow_point", "wrist_point"),
    "elbow_point": ("wrist_point",),
    "hip_side": ("knee_point", "ankle_outside"),
    "knee_point": ("ankle_outside",),
}


def anchor_position(character, vertices: np.ndarray, placement, mirrored: bool) -> np.ndarray | None:
    """(3,) where a placement's anchor mark goes: its landmark (:func:`landmark_position`), moved
    ``placement.drop_cm`` down the limb along the landmarks below it (past the last, along the last step);
    None if the landmark is absent."""
    anchor = landmark_position(character, vertices, placement.anchor, mirrored)
    drop = float(getattr(placement, "drop_cm", 0.0))
    if anchor is None or drop <= 0.0:
        return anchor
    stem, _, side = placement.anchor.rpartition("_")
    below = [landmark_position(character, vertices, f"{n}_{side}", mirrored) for n in _DOWN_THE_LIMB.get(stem, ())]
    chain = [anchor, *(p for p in below if p is not None)]
    if len(chain) < 2:
        return anchor
    for a, b in itertools.pairwise(chain):
        step = float(np.linalg.norm(b - a))
        if drop <= step or b is chain[-1]:
            return a + (b - a) * (drop / max(step, 1e-9))
        drop -= step
    return anchor  # pragma: no cover


def place_instances(
    character,
    vertices: np.ndarray,
    pattern: Pattern,
    pmesh: PatternMesh,
    cylinders: dict[str, Cylinder],
    report: Report,
    *,
    scene=None,
    parts: BodyParts | None = None,
) -> dict[str, np.ndarray]:
    """Wrap every cut copy onto its body part's cylinder.

    Parameters
    ----------
    character : the character (landmarks)
    vertices : (V, 3) float64, cm — the body in the dressing pose
    scene : a :class:`~patternbridge.assemble.collision.BodyCollider` of that
        body; when given, wrapped points inside the body move out along their
        radius
    parts : body-part labels of ``vertices``; when given, the parts of leg
        pieces above the crotch (a trouser seat) go round the hips instead of
        round the leg

    Returns
    -------
    dict instance key -> (n, 3) float64 positions, cm

    Raises
    ------
    InputError
        A piece has no placement hint, or its body part has no vertices.
    """
    out: dict[str, np.ndarray] = {}
    rows = []
    # a copy drafted short of its hem's landmark in a fabric worn stretched along the grain starts stretched to it
    stretches = length_stretches(character, vertices, pattern, pmesh, cylinders)
    for inst in pmesh.instances:
        piece = pattern.piece(inst.piece)
        pl = piece.placement
        part = instance_part(pattern, inst)
        if part not in cylinders:
            raise InputError(
                f"{pattern.style}: piece {inst.piece!r} goes on the {part}, which the character lacks; "
                "check the placement hint or the character's rig"
            )
        cyl = cylinders[part]
        mirrored = inst.copy is Copy.MIRROR
        if part in BAND_PARTS and pl.side is Side.AROUND and parts is not None:
            cyl = _band_cylinder(character, vertices, parts, cyl, pl.anchor, mirrored)
        p2 = instance_points2d(pmesh, inst)
        marks = pmesh.pieces[inst.piece].marks
        R = cyl.radius_cm
        anchor = anchor_position(character, vertices, pl, mirrored)
        if anchor is not None and pl.anchor_mark in marks:
            th_a, h_a, _ = cyl.coordinates(anchor[None])
            th_a, h_a = float(th_a[0]), float(h_a[0])
            a2 = p2[marks[pl.anchor_mark]]
        else:
            report.add(
                "anchor-missing",
                f"anchor {pl.anchor!r}/{pl.anchor_mark!r} not found; piece centred on the {pl.side} of the {part}",
                where=inst.key,
            )
            th_a = {Side.FRONT: 0.0, Side.BACK: np.pi}.get(pl.side, np.pi / 2)
            h_a = 0.5 * (cyl.h_min + cyl.h_max)
            a2 = 0.5 * (p2.min(axis=0) + p2.max(axis=0))
        rows.append((inst, pl, part, cyl, p2, R, th_a, h_a, a2))
    rows = _level_backs(pmesh, rows)
    rows, cylinders = _widen_for_rows(pattern, pmesh, rows, cylinders)
    shared = _shared_row_radii(pmesh, rows)
    seat: list = []
    for inst, pl, part, cyl, p2, R, th_a, h_a, a2 in rows:
        # pattern +x runs to the right as seen from outside (docs/library.md conventions)
        sigma = 1.0
        Rv = shared.get(inst.key)
        if Rv is None:
            Rv = _row_radii(pmesh, inst, part, pl.side, R)
        x_ref = a2[0]
        if inst.key in shared:
            # pieces side by side round a limb: the seam through the anchor
            # (a trouser side seam) sits on the anchor's angle row by row, so
            # that seam and the one on the far side (the inside leg) start
            # closed even where the pattern's edges slant
            x_ref = _anchor_line(pmesh, inst, p2, pl.anchor_mark, {r[0].key for r in rows if r[2] == part})
        theta = th_a + sigma * (p2[:, 0] - x_ref) / Rv
        if part is BodyPart.TORSO and pl.side is not Side.AROUND:
            # torso fronts and backs are drawn with the body midline at x = 0
            # (docs/library.md): x = 0 goes on the centre front / back, the
            # anchor only fixes the height (a neck point lies too near the
            # axis to give a reliable angle). A piece sewn to its own mirror
            # copy (a centre front seam) puts that seam on the centre, row by
            # row: grading can move it off x = 0
            theta = (0.0 if pl.side is Side.FRONT else np.pi) + (p2[:, 0] - _centre_line(pmesh, inst, p2)) / Rv
        ls = stretches.get(inst.key)
        h = h_a + ((ls.heights(p2[:, 1]) if ls is not None else p2[:, 1]) - a2[1])
        crotch = landmark_position(character, vertices, CROTCH_LANDMARK, False) if part in LEGS else None
        if crotch is not None:
            # a rise too short to pass under the crotch is laid stretched, the piece lower (length.crotch_drop)
            th_c, h_c, _ = cyl.coordinates(crotch[None])
            drop = crotch_drop(
                pattern, inst.piece, p2, pmesh.pieces[inst.piece].marks, float(a2[1]), h_a, float(h_c[0])
            )
            # a copy worn stretched has its rise's stretch in its worn heights already
            h = h - (drop.shift_cm if ls is not None and ls.stretched else drop.lowered(p2[:, 1]))
            both = _mirror_seam_count(pmesh, inst, p2) >= 2
            x_line = np.broadcast_to(np.asarray(x_ref, dtype=np.float64), (len(p2),))
            share = _ring_share(p2[: pmesh.pieces[inst.piece].n_boundary], p2, x_line, both_centres=both)
            theta = _facing_crotch(theta, h, share, th_a, float(th_c[0]), float(h_c[0]))
        out[inst.key] = _on_cylinder(cyl, theta, h, Rv, scene)
        if part in LEGS and BodyPart.TORSO in cylinders and parts is not None:
            # any leg piece: the rows that rise above the crotch go round the hips (see _seat_on_hips)
            x_ref = np.broadcast_to(np.asarray(x_ref, dtype=np.float64), (len(p2),))
            both = _mirror_seam_count(pmesh, inst, p2) >= 2
            seat.append((inst, p2, x_ref, part, float(a2[1]), p2[: pmesh.pieces[inst.piece].n_boundary], both))
    _bindings_way_up(pattern, pmesh, rows, shared, out, scene)
    if seat:
        _seat_on_hips(character, vertices, parts, cylinders[BodyPart.TORSO], seat, out, scene)
    return out


CROTCH_TURN_CM = 15.0  # below the crotch, the rows of a leg turn from facing the crotch to their widths' shares


def _facing_crotch(
    theta: np.ndarray, h: np.ndarray, share: np.ndarray, th_side: float, th_crotch: float, h_crotch: float
) -> np.ndarray:
    """(n,) angles of a leg piece's vertices with the far ends of its rows by the crotch turned to face it.

    Round a leg the pieces side by side share each row by their widths: the
    inside leg lies where the front's width ends. At the crotch the back is
    wider than the front (its crotch extension runs under the seat), so the
    inside leg's top, the crotch point, came to lie on the front of the
    thigh, 5-10 cm before the body's crotch on B, D and F, and its partners'
    rise and inseam corners were drawn to it under the body; sewing folded
    the crotch through itself. So at the crotch each piece spans, from the
    side line (``share`` 0) to its row's far end (``share`` ±1, signed as
    the angle runs), the angle from the side (``th_side``) to the crotch's
    (``th_crotch``) the way it runs: the ends of every piece meet facing the
    crotch, whatever the widths. The turn is full at and above the crotch's
    height ``h_crotch`` and fades over :data:`CROTCH_TURN_CM` below it.
    """
    ahead = float(np.mod(th_crotch - th_side, 2.0 * np.pi))
    facing = th_side + share * np.where(share >= 0.0, ahead, 2.0 * np.pi - ahead)
    turn = np.clip(1.0 - (h_crotch - h) / CROTCH_TURN_CM, 0.0, 1.0)
    return (1.0 - turn) * theta + turn * facing


def _on_cylinder(cyl: Cylinder, theta: np.ndarray, h: np.ndarray, Rv, scene) -> np.ndarray:
    """Points at angles ``theta`` and heights ``h`` on ``cyl`` at radius ``Rv`` (per row or one), clear of the scene."""
    r = Rv.copy() if np.ndim(Rv) else np.full(len(theta), float(Rv))
    if scene is not None:
        r = scene.radial_clearance(cyl, theta, h, r, CLEARANCE_CM)
    return cyl.points(theta, h, r)


#: a binding turned end over end must start its seams closer than this share of the summed squared gaps as drawn
TURNED_GAIN = 0.8


def _bindings_way_up(pattern: Pattern, pmesh: PatternMesh, rows: list, shared: dict, out: dict, scene) -> None:
    """Each binding wrapped the way up its seams meet the pieces it binds (``out`` updated in place).

    A binding's drawing says nothing of which long edge is up: wrapped with the
    edge it sews on top, a strip sewn face to face along a neckline runs round
    the neck against it, and every seam starts across the neck (20-36 cm on
    ``simple.DXF``'s neck binding on E_average_male). So each binding is also
    wrapped turned end over end (its pattern turned 180° in its plane, the same
    cloth) and kept so when the summed squared gaps of its seams to other pieces
    fall below :data:`TURNED_GAIN` of those as drawn.
    """
    for inst, pl, part, cyl, p2, R, th_a, h_a, a2 in rows:
        if pattern.piece(inst.piece).role not in BINDING_ROLES or inst.key in shared:
            continue
        sides = [
            (va, out[other.key][vb])
            for me, va, other, vb in _seam_sides(pmesh)
            if me.key == inst.key and other.piece != inst.piece
        ]
        if not sides:
            continue
        Rv = _row_radii(pmesh, inst, part, pl.side, R)
        q, b = -p2, -a2
        theta = th_a + (q[:, 0] - b[0]) / Rv
        h = h_a + (q[:, 1] - b[1])
        turned = _on_cylinder(cyl, theta, h, Rv, scene)

        as_drawn = sum(float(np.sum((out[inst.key][va] - t) ** 2)) for va, t in sides)
        if sum(float(np.sum((turned[va] - t) ** 2)) for va, t in sides) < TURNED_GAIN * as_drawn:
            out[inst.key] = turned


SIDE_SEAM_CM = 10.0  # a seam to a front running farther than this down a piece is a side seam, not a shoulder


def _over_shoulders(pattern: Pattern, pmesh: PatternMesh, inst: Instance) -> bool:
    """Whether ``inst`` is a yoke: a front or back torso piece sewn to larger torso pieces on the front and on
    the back, and to the fronts only across (shoulder seams, no side seam running :data:`SIDE_SEAM_CM` down
    the piece).

    A dress's back bodice half is sewn to the larger front bodice and skirt back too, but down its sides: it
    goes round the body, and laid over the shoulders its centre back started 21 cm from its mirror's. A
    skirt's waistband goes round the body (side ``around``).
    """
    own_side = pattern.piece(inst.piece).placement.side
    if instance_part(pattern, inst) is not BodyPart.TORSO or own_side is Side.AROUND:
        return False
    size = {k: len(pmesh.pieces[k].points) for k in pmesh.pieces}
    points = pmesh.pieces[inst.piece].points
    sides = set()
    for me, va, other, _ in _seam_sides(pmesh):
        if me.key != inst.key or other.key == inst.key or instance_part(pattern, other) is not BodyPart.TORSO:
            continue
        side = pattern.piece(other.piece).placement.side
        if side is Side.FRONT and float(np.ptp(points[va, 1])) > SIDE_SEAM_CM:
            return False
        if size[other.piece] > size[inst.piece]:
            sides.add(side)
    return sides == {Side.FRONT, Side.BACK}


def _seam_sides(pmesh: PatternMesh) -> Iterator[tuple[Instance, np.ndarray, Instance, np.ndarray]]:
    """Every seam seen from each of its two sides: (instance, its sewn vertices, other instance, theirs)."""
    for sp in pmesh.seams:
        yield sp.a, sp.a_vertices, sp.b, sp.b_vertices
        yield sp.b, sp.b_vertices, sp.a, sp.a_vertices


def _centre_line(pmesh: PatternMesh, inst: Instance, p2: np.ndarray) -> np.ndarray:
    """(n,) float64, cm: x of the seam to the instance's own mirror copy at each vertex's height.

    Zero when the piece has no such seam (the midline convention x = 0).
    """
    for sp in pmesh.seams:
        if sp.a.piece == sp.b.piece == inst.piece and sp.a.copy is not sp.b.copy:
            va = sp.a_vertices if sp.a.key == inst.key else sp.b_vertices
            ys, xs = p2[va, 1], p2[va, 0]
            if np.ptp(ys) < 1.0:
                continue
            order = np.argsort(ys)
            return np.interp(p2[:, 1], ys[order], xs[order])
    return np.zeros(len(p2))


SEAT_BLEND_CM = (-2.0, 8.0)  # heights above the crotch where a leg piece goes from the leg to the hips


def _seat_on_hips(
    character,
    vertices: np.ndarray,
    parts: BodyParts,
    torso: Cylinder,
    seat: list,
    out: dict[str, np.ndarray],
    scene,
) -> None:
    """Wrap the parts of leg pieces above the crotch round the hips (in place).

    On the leg's cylinder the seat of a trouser (the rows above the crotch,
    wider than the leg) would stand off the body and leave the centre front
    and back seams a hand's width apart; closing them then turns the whole
    leg tube round the leg. Above the crotch every row goes instead round a
    ring centred on the body's cross-section at its height, with the side
    seam on the side of the hips and the radius of both legs' pieces
    together; each piece spans its quarter (side to centre front or back)
    whatever its share of the row, so the centre seams start on the midline. The two
    wrappings are blended over :data:`SEAT_BLEND_CM` around the crotch.
    """
    v = np.asarray(vertices, dtype=np.float64)
    crotch_y = crotch_height(character, v, parts)
    if crotch_y is None:
        return
    legs = parts.mask(BodyPart.LEFT_LEG) | parts.mask(BodyPart.RIGHT_LEG)
    trunk = v[parts.mask(BodyPart.TORSO) | legs]
    lo, hi = crotch_y + SEAT_BLEND_CM[0] - 2.0, crotch_y + 60.0
    grid = np.arange(lo, hi, 1.0)
    centres = np.full((len(grid), 3), np.nan)
    for k, y in enumerate(grid):
        band = trunk[np.abs(trunk[:, 1] - y) < 1.0]
        if len(band) >= 8:
            centres[k] = 0.5 * (band.min(axis=0) + band.max(axis=0))
    ok = np.isfinite(centres[:, 0])
    if ok.sum() < 2:
        return
    for inst, p2, x_ref, part, a2y, b_own, both in seat:
        pos = out[inst.key]
        y = pos[:, 1]
        t = np.clip((y - crotch_y - SEAT_BLEND_CM[0]) / (SEAT_BLEND_CM[1] - SEAT_BLEND_CM[0]), 0.0, 1.0)
        w = t * t * (3.0 - 2.0 * t)
        if not (w > 0).any():
            continue
        # the side seam on the side of the hips the leg hangs from (torso e1 points to the character's left)
        th_side = 0.5 * np.pi * float(np.sign((v[parts.mask(part)].mean(axis=0) - torso.center) @ torso.e1))
        # both legs' pieces together go once round the hips at each height
        # (the pieces of one leg are aligned on their anchor's height)
        rel = p2[:, 1] - a2y
        total = sum(_held_widths(b, rel + oy) for _, _, _, opart, oy, b, _ in seat if opart == part)
        r_t = np.maximum(total / np.pi, 1.0)
        # each piece covers its quarter of the hips, from the side to the
        # centre front or back, whatever its share of the row's width: a
        # grading can give the back twice the front's waist, and with one
        # scale for both the centre seams started 14 cm apart
        theta = th_side + 0.5 * np.pi * _ring_share(b_own, p2, x_ref, both_centres=both)
        c = np.stack([np.interp(y, grid[ok], centres[ok, j]) for j in range(3)], axis=1)
        ring = (
            c * np.array([1.0, 0.0, 1.0])
            + y[:, None] * np.array([0.0, 1.0, 0.0])
            + (r_t * np.cos(theta))[:, None] * torso.e0
            + (r_t * np.sin(theta))[:, None] * torso.e1
        )
        blended = (1.0 - w)[:, None] * pos + w[:, None] * ring
        if scene is not None:
            moving = w > 0
            fixed, _ = scene.push_out(blended[moving], CLEARANCE_CM, robust=True)
            blended[moving] = fixed
        out[inst.key] = blended


def _level_backs(pmesh: PatternMesh, rows: list) -> list:
    """Torso backs moved along the axis so that their side seams face the fronts' at the same heights.

    A front hangs from its neck landmark and a back from its waist
    landmark; where the body's neck-to-waist length differs from the
    pattern's, the two would start with their side seams offset (5 cm on
    the child). The back takes the mean height difference of the pairs of
    each seam it shares with a front that runs more than 5 cm along the
    axis (a side seam, not a shoulder seam).
    """
    side = {r[0].key: (i, r[1].side) for i, r in enumerate(rows) if r[2] is BodyPart.TORSO}
    out = list(rows)
    shifts: dict[int, list[float]] = {}
    for me, va, other, vb in _seam_sides(pmesh):
        if me.key not in side or other.key not in side:
            continue
        (i, s_me), (j, s_other) = side[me.key], side[other.key]
        if s_me is not Side.BACK or s_other is not Side.FRONT:
            continue
        _, _, _, _, p2b, _, _, hb, a2b = rows[i]
        _, _, _, _, p2f, _, _, hf, a2f = rows[j]
        yb, yf = p2b[va, 1], p2f[vb, 1]
        if np.ptp(yb) < 5.0:
            continue
        shifts.setdefault(i, []).append(float(np.mean((hf + yf - a2f[1]) - (hb + yb - a2b[1]))))
    for i, d in shifts.items():
        inst, pl, part, cyl, p2, R, th_a, h_a, a2 = out[i]
        out[i] = (inst, pl, part, cyl, p2, R, th_a, h_a + float(np.mean(d)), a2)
    return out


ROW_WIDTH_INSET_CM = 2.0  # a piece's rows nearer its top or bottom than this do not count (see _widen_for_rows)


def _widen_for_rows(
    pattern: Pattern, pmesh: PatternMesh, rows: list, cylinders: dict[str, Cylinder]
) -> tuple[list, dict[str, Cylinder]]:
    """Cylinders widened so that the pieces side by side at any height fit once round (``rows`` and ``cylinders``).

    At every height the pieces a part carries lie side by side round its
    cylinder, 1 cm apart: the radius is at least the widest such row / 2π.
    Pieces above one another (a yoke over a back) do not add up; their rows
    within :data:`ROW_WIDTH_INSET_CM` of a piece's top or bottom are left
    out, where a piece meets the one sewn above or below it, and a yoke,
    laid over the shoulders, does not count. (Summing every piece's full
    width, yoke included, made E's torso cylinder 26 cm in radius for a
    body 17 cm round at the 90th percentile: the side seams started 32 cm
    open, and closing them drew the back up into a fold across it.)
    """
    import dataclasses

    spans: dict[str, list] = {}
    for inst, _, part, _, p2, _, _, h_a, a2 in rows:
        if _over_shoulders(pattern, pmesh, inst):
            continue  # a yoke: the seam graph lays it across the shoulders, not round the cylinder
        b = p2[: pmesh.pieces[inst.piece].n_boundary]
        spans.setdefault(part, []).append((h_a - a2[1], b))
    wide: dict[str, float] = {}
    for part, members in spans.items():
        lo = min(off + b[:, 1].min() for off, b in members)
        hi = max(off + b[:, 1].max() for off, b in members)
        grid = np.linspace(lo, hi, 400)
        total = np.zeros_like(grid)
        for off, b in members:
            y = grid - off
            inner = (y > b[:, 1].min() + ROW_WIDTH_INSET_CM) & (y < b[:, 1].max() - ROW_WIDTH_INSET_CM)
            w = _widths(b, y)
            total += np.where(inner & (w > 0), w + 1.0, 0.0)
        wide[part] = float(total.max()) / (2 * np.pi)
    out = dict(cylinders)
    for part, r in wide.items():
        if part in out and r > out[part].radius_cm:
            out[part] = dataclasses.replace(out[part], radius_cm=r)
        log.debug("%s: cylinder radius %.1f cm (pieces side by side: %.1f cm)", part, out[part].radius_cm, r)
    fixed = []
    for inst, pl, part, cyl, p2, R, th_a, h_a, a2 in rows:
        if out[part].radius_cm > R:  # (a band keeps its own centre, see _band_cylinder)
            cyl = dataclasses.replace(cyl, radius_cm=out[part].radius_cm)
        fixed.append((inst, pl, part, cyl, p2, cyl.radius_cm, th_a, h_a, a2))
    return fixed, out


SIDE_INSIDE_SHARE = 0.25  # a side line this far inside a row on both hands is kept; else the row's middle


def _ring_share(boundary: np.ndarray, p2: np.ndarray, x_ref: np.ndarray, *, both_centres: bool) -> np.ndarray:
    """(n,) float64 in [-1, 1]: each vertex's share of a quarter of the hips, signed, from the side line ``x_ref``.

    A piece sewn to its mirror copy along one end of its rows (a trouser
    front or back: the side seam on the other end) spans one quarter, side
    to centre: the share is the distance from the side line over the row's
    width. A piece sewn to its mirror copy along both ends
    (``both_centres``: a one-piece leg, front and back rises in one) spans
    two quarters, centre front to centre back: the side line is ``x_ref``
    when it lies at least :data:`SIDE_INSIDE_SHARE` of the row inside it on
    both hands, else the row's middle, and each hand of the row is scaled
    to its own quarter, so both rises start on the midline.
    """
    xl, xr = _held_ends(boundary, p2[:, 1])
    width = np.maximum(xr - xl, 1.0)
    if not both_centres:
        return np.clip((p2[:, 0] - x_ref) / width, -1.0, 1.0)
    inside = np.minimum(x_ref - xl, xr - x_ref) > SIDE_INSIDE_SHARE * width
    side = np.where(inside, x_ref, 0.5 * (xl + xr))
    d = p2[:, 0] - side
    return np.clip(d / np.maximum(np.where(d >= 0, xr - side, side - xl), 1.0), -1.0, 1.0)


def _mirror_seam_count(pmesh: PatternMesh, inst: Instance, p2: np.ndarray) -> int:
    """Seams of ``inst`` to its own mirror copy that run at least 1 cm along y (centre front / back seams)."""
    count = 0
    for sp in pmesh.seams:
        if sp.a.piece == sp.b.piece == inst.piece and sp.a.copy is not sp.b.copy:
            va = sp.a_vertices if sp.a.key == inst.key else sp.b_vertices
            count += int(np.ptp(p2[va, 1]) >= 1.0)
    return count


def _held_ends(boundary: np.ndarray, ys: np.ndarray, hold_cm: float = 4.0) -> tuple[np.ndarray, np.ndarray]:
    """(k,) x of the left and right ends of the rows ``ys`` of ``boundary``, held as in :func:`_held_widths`."""
    top = float(boundary[:, 1].max())
    y = np.asarray(ys, dtype=np.float64)
    xl, xr = _ends(boundary, y)
    rl, rr = _ends(boundary, np.array([top - hold_cm]))
    high = y > top - hold_cm
    return np.where(high, np.minimum(xl, rl[0]), xl), np.where(high, np.maximum(xr, rr[0]), xr)


def _held_widths(boundary: np.ndarray, ys: np.ndarray, hold_cm: float = 4.0, *, at_hem: bool = False) -> np.ndarray:
    """Row widths of ``boundary`` at ``ys`` (see :func:`_widths`), never below the width ``hold_cm`` inside its end.

    The end is the top (``at_hem`` False) or the bottom (True); beyond the
    end the rows keep that width too. The pieces round the hips end at
    different heights and their top edges slant (a back rises above the front
    at the centre back); the pieces side by side round a leg end at hems that
    slant or curve (a shorts hem rises toward the inside leg): a row that one
    of them barely or no longer reaches still has that piece beside it once
    sewn. Without the hold at the hem the rows by it went round on a radius a
    fraction of the leg's and the hem lay folded in across the leg, through
    the cloth above it (every trouser and shorts leg on A-F: 10-20 triangles
    a piece).
    """
    y = np.asarray(ys, dtype=np.float64)
    w = _widths(boundary, y)
    if at_hem:
        end = float(boundary[:, 1].min())
        ref = _widths(boundary, np.array([end + hold_cm]))[0]
        return np.where(y < end + hold_cm, np.maximum(w, ref), w)
    end = float(boundary[:, 1].max())
    ref = _widths(boundary, np.array([end - hold_cm]))[0]
    return np.where(y > end - hold_cm, np.maximum(w, ref), w)


def _band_cylinder(
    character, vertices: np.ndarray, parts: BodyParts, cyl: Cylinder, anchor: str, mirrored: bool
) -> Cylinder:
    """``cyl`` moved onto the centre of the body's cross-section at the anchor's height.

    A band going round the waist or the neck is wrapped on its own length;
    round the torso's bounding-box centre it would sit off the body (a belly
    pushes the box forward), round the head's (a collar) behind the neck (the
    face pushes the box forward and up).
    """
    import dataclasses

    a = landmark_position(character, vertices, anchor, mirrored)
    if a is None:
        return cyl
    v = np.asarray(vertices, dtype=np.float64)
    own = v[parts.mask(cyl.part)]
    band = own[np.abs((own - a) @ cyl.axis) < 1.5]
    if len(band) < 8:
        return cyl
    centre = 0.5 * (band.min(axis=0) + band.max(axis=0))
    radial = centre - cyl.center
    radial -= (radial @ cyl.axis) * cyl.axis
    return dataclasses.replace(cyl, center=cyl.center + radial)


def _anchor_line(pmesh: PatternMesh, inst: Instance, p2: np.ndarray, mark: str, partners: set[str]) -> np.ndarray:
    """(n,) float64, cm: x of the seam through ``mark`` at each vertex's height (y).

    The seam is the one joining ``inst`` to another instance in
    ``partners`` whose edge on ``inst`` contains the mark; without one, the
    mark's x for every vertex.
    """
    marks = pmesh.pieces[inst.piece].marks
    mv = marks.get(mark)
    for me, va, other, _ in _seam_sides(pmesh):
        if me.key != inst.key or other.key == inst.key or other.key not in partners:
            continue
        if mv is None or not np.any(va == mv):
            continue
        ys, xs = p2[va, 1], p2[va, 0]
        if np.ptp(ys) < 1.0:
            continue
        order = np.argsort(ys)
        return np.interp(p2[:, 1], ys[order], xs[order])
    return np.full(len(p2), p2[mv, 0] if mv is not None else float(p2[:, 0].mean()))


def _ends(boundary: np.ndarray, ys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(k,) float64, cm: x of the leftmost and rightmost crossings of the closed outline ``boundary`` (n, 2) with
    the rows ``ys`` (both 0 for a row outside it)."""
    a, c = boundary, np.roll(boundary, -1, axis=0)
    ya, yc = a[:, 1][None, :], c[:, 1][None, :]
    g = np.asarray(ys, dtype=np.float64)[:, None]
    cross = ((ya - g) * (yc - g) <= 0) & (ya != yc)
    t = np.where(cross, (g - ya) / np.where(ya != yc, yc - ya, 1.0), 0.0)
    xs = a[:, 0][None, :] + t * (c[:, 0] - a[:, 0])[None, :]
    hit = cross.any(axis=1)
    return (
        np.where(hit, np.where(cross, xs, np.inf).min(axis=1), 0.0),
        np.where(hit, np.where(cross, xs, -np.inf).max(axis=1), 0.0),
    )


def _widths(boundary: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """(k,) float64, cm: width of the closed outline ``boundary`` (n, 2) along the rows ``ys`` (0 outside)."""
    xl, xr = _ends(boundary, ys)
    return xr - xl


def _shared_row_radii(pmesh: PatternMesh, rows: list) -> dict[str, np.ndarray]:
    """Wrapping radii of the pieces side by side round a limb (a trouser leg's front and back).

    At every height the pieces on one limb together go once round: the
    radius is the sum of their widths at that height / 2π (kept from the
    widest height below it, toward the body). Returns instance key -> (n,)
    radii, cm, for the limbs carrying two or more such pieces.
    """
    groups: dict[str, list] = {}
    for row in rows:
        inst, pl, part = row[0], row[1], row[2]
        if part in LIMBS and pl.side is not Side.AROUND:
            groups.setdefault(part, []).append(row)
    out: dict[str, np.ndarray] = {}
    for members in groups.values():
        if len(members) < 2:
            continue
        spans = [(h_a - a2[1], p2) for _, _, _, _, p2, _, _, h_a, a2 in members]
        lo = min(off + p2[:, 1].min() for off, p2 in spans)
        hi = max(off + p2[:, 1].max() for off, p2 in spans)
        grid = np.linspace(lo, hi, 300)
        total = np.zeros_like(grid)
        for (off, p2), (inst, *_) in zip(spans, members, strict=True):
            b = p2[: pmesh.pieces[inst.piece].n_boundary]
            total += _held_widths(b, grid - off, at_hem=True)
        total = np.maximum.accumulate(total)
        for (off, p2), (inst, *_) in zip(spans, members, strict=True):
            radius = np.interp(off + p2[:, 1], grid, total) / (2 * np.pi)
            out[inst.key] = np.maximum(radius, 1.0)
    return out


def _row_radii(pmesh: PatternMesh, inst: Instance, part: BodyPart, side: Side, radius_cm: float) -> np.ndarray:
    """(n,) float64, cm: the wrapping radius of every vertex of ``inst``.

    A piece going round a limb (side ``around``) that is sewn to itself (a
    sleeve, a cuff) is wrapped
    as a tube: every row of the pattern (a height y) goes once round, on the
    radius ``width(y) / 2π``, so its seam edges start side by side instead
    of across the limb. Rows beyond the widest row toward the body (a
    sleeve cap) keep the radius of the widest row below them, and sit on top
    of the limb. A band round the torso or the neck sewn to itself (a
    waistband, a collar) goes once round on its full width. Other pieces use
    the cylinder's ``radius_cm``.
    """
    pts = pmesh.pieces[inst.piece].points
    n = len(pts)
    closes = any(sp.a.key == inst.key and sp.b.key == inst.key for sp in pmesh.seams)
    if not (closes and side is Side.AROUND):
        return np.full(n, float(radius_cm))
    b = pts[: pmesh.pieces[inst.piece].n_boundary]
    if part in BAND_PARTS:
        # a band round the waist or the neck (a waistband, a collar): once
        # round on its full length, its closure edges side by side (on the
        # head's radius a collar went a third again round, its side neck
        # marks 6 cm behind the neck after the seam graph drew it in)
        return np.full(n, max(float(np.ptp(b[:, 0])) / (2 * np.pi), 1.0))
    if part not in LIMBS:
        return np.full(n, float(radius_cm))
    y0, y1 = float(b[:, 1].min()), float(b[:, 1].max())
    grid = np.linspace(y0, y1, 200)
    grid[0] += 1e-6 * (y1 - y0)
    grid[-1] -= 1e-6 * (y1 - y0)
    width = _widths(b, grid)
    width = np.maximum.accumulate(width)  # the cap keeps the widest row's radius
    w = np.interp(pts[:, 1], grid, width)
    return np.maximum(w / (2 * np.pi), 1.0)
