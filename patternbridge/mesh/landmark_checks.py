"""Plausibility checks of a landmark set: symmetry, the midline, and the order of points along the body.

A landmark table from any source goes through :func:`check_landmarks` before
it is measured. Nothing implausible passes silently:

* **Midline**: where the body is left/right symmetric (the mirror image of the
  point in the mirror plane (:func:`mirror_plane_x`) lies on the surface, within
  :data:`MIRROR_TOL_CM`) a midline point (front and back neck points, waist front and back, crotch) that is not
  on the mirror plane is moved to the nearest vertex on it.
* **Pairs**: where the body is symmetric around both points, a left point and the mirror image of its right
  partner more than :data:`PAIR_TOL_CM` apart are made symmetric: the point of
  lower confidence is replaced by the mirror image of its partner, or, at equal
  confidence, both by the mirror-average of the two. Points given in a file are
  never moved; their confidence is lowered and the evidence says why.
* **Order**: along each arm, the shoulder point is nearer the back neck point
  than the elbow point, which is nearer than the wrist; the shoulder point lies
  above the armpit and within 20 % of the stature of the midline; the waist lies
  below the bust points and above the crotch; the bust points below the front
  neck point. A detected or projected point that breaks an order is refused
  (dropped, and reported in the log); a point from a file that does is an error.

Every change is written into the landmark's :class:`LandmarkEvidence`, and the
confidence falls with it.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from dataclasses import replace

import numpy as np

from ..errors import LandmarkError
from .character import Character, Landmark, LandmarkSource

__all__ = [
    "MIDLINE",
    "MIRROR_TOL_CM",
    "PAIR_TOL_CM",
    "check_landmarks",
    "mirror_plane_x",
    "pair_names",
]

log = logging.getLogger(__name__)

MIDLINE = ("front_neck_point", "back_neck_point", "waist_front", "waist_back", "crotch_point")
PAIR_TOL_CM = 2.0  # left and mirrored right points further apart than this are asymmetric
MIDLINE_TOL_CM = 0.5
MIRROR_TOL_CM = 0.5  # a point's mirror image this close to the surface: symmetric there


def pair_names(names) -> list[tuple[str, str]]:
    """(left, right) name pairs present in ``names``."""
    names = set(names)
    return sorted(
        (n, n[: -len("_left")] + "_right")
        for n in names
        if n.endswith("_left") and n[: -len("_left")] + "_right" in names
    )


def mirror_plane_x(vertices: np.ndarray, faces: np.ndarray) -> float:
    """x of the body's mirror plane, cm: the area-weighted centroid of the surface.

    Weighted by area, so neither the vertex order nor a denser meshing of one
    side moves it.
    """
    tri = np.asarray(vertices, dtype=np.float64)[faces]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    return float(np.sum(area * tri[:, :, 0].mean(axis=1)) / max(float(area.sum()), 1e-12))


def _mirror(p: np.ndarray, c: float) -> np.ndarray:
    return np.array([2.0 * c - p[0], p[1], p[2]])


def _moved(lm: Landmark, sym: _Symmetry, p: np.ndarray, text: str, confidence: float) -> Landmark:
    """``lm`` moved to the surface point closest to ``p``."""
    from .surface_point import locate_on_surface

    at = locate_on_surface(sym.v, sym.f, p).landmark(0, lm.name)
    return replace(lm, position=at.position, vertex=at.vertex, face=at.face, bary=at.bary,
                   confidence=float(np.clip(confidence, 0.0, 1.0)), evidence=lm.evidence.with_check(text))


class _Symmetry:
    """The body's mirror plane and whether the body is symmetric around given points.

    The plane is :func:`mirror_plane_x`. The body is symmetric around a
    point when the point's mirror image lies on the surface (within
    :data:`MIRROR_TOL_CM`): a bent knee on one side fails this at the knee,
    while the rest of the body still passes.
    """

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        self.v, self.f = vertices, faces
        self.plane = mirror_plane_x(vertices, faces)

    def off_surface(self, points: np.ndarray) -> np.ndarray:
        """(k,) distance from each point's mirror image to the surface, cm."""
        from .load import snap_to_surface

        mirrored = np.array([_mirror(p, self.plane) for p in np.atleast_2d(points)])
        snapped, _ = snap_to_surface(self.v, self.f, mirrored)
        return np.linalg.norm(snapped - mirrored, axis=1)

    def symmetric_at(self, *points: np.ndarray) -> bool:
        return bool(np.all(self.off_surface(np.array(points)) <= MIRROR_TOL_CM))


def _check_midline(marks: dict[str, Landmark], v: np.ndarray, sym: _Symmetry) -> None:
    for name in MIDLINE:
        lm = marks.get(name)
        if lm is None or lm.source == LandmarkSource.FILE:
            continue
        off = float(lm.position[0] - sym.plane)
        if abs(off) <= MIDLINE_TOL_CM or not sym.symmetric_at(lm.position):
            continue
        c = sym.plane
        band = np.abs(v[:, 0] - c) < max(MIDLINE_TOL_CM, 0.003 * float(np.ptp(v[:, 1])))
        if not band.any():
            continue
        idx = np.flatnonzero(band)
        target = np.array([c, lm.position[1], lm.position[2]])
        vid = int(idx[np.argmin(np.sum((v[idx] - target) ** 2, axis=1))])
        marks[name] = _moved(lm, sym, v[vid], f"moved to the midline of the symmetric body (was {off:+.1f} cm off)",
                             lm.confidence * 0.9)


def _check_pairs(marks: dict[str, Landmark], v: np.ndarray, sym: _Symmetry, name: str) -> None:
    for left, right in pair_names(marks):
        a, b = marks[left], marks[right]
        c = sym.plane
        d = float(np.linalg.norm(a.position - _mirror(b.position, c)))
        if d <= PAIR_TOL_CM or not sym.symmetric_at(a.position, b.position):
            continue  # an asymmetric body: its left and right are measured as they are
        text = f"left/right {d:.1f} cm apart on a symmetric body"
        if a.source == LandmarkSource.FILE and b.source == LandmarkSource.FILE:
            log.warning("%s: %s and %s are %s (from the file, kept)", name, left, right, text)
            marks[left] = replace(a, confidence=min(a.confidence, 0.4), evidence=a.evidence.with_check(text))
            marks[right] = replace(b, confidence=min(b.confidence, 0.4), evidence=b.evidence.with_check(text))
            continue
        file_side = a.source == LandmarkSource.FILE or b.source == LandmarkSource.FILE
        if file_side or abs(a.confidence - b.confidence) > 0.05:
            keep, fix = (a, b) if (a.source == LandmarkSource.FILE
                                   or (b.source != LandmarkSource.FILE and a.confidence > b.confidence)) else (b, a)
            marks[fix.name] = _moved(fix, sym, _mirror(keep.position, c), f"{text}: mirrored from {keep.name}",
                                     keep.confidence * 0.9)
        else:
            pa = 0.5 * (a.position + _mirror(b.position, c))
            conf = min(a.confidence, b.confidence) * 0.7
            marks[left] = _moved(a, sym, pa, f"{text}: mirror-averaged with {right}", conf)
            marks[right] = _moved(b, sym, _mirror(pa, c), f"{text}: mirror-averaged with {left}", conf)
        log.warning("%s: %s and %s were %s; corrected", name, left, right, text)


def _order_rules(marks: Mapping[str, Landmark], stature: float, c: float):
    """(offending landmark, other landmark, what is wrong) for every broken order."""
    p = {k: lm.position for k, lm in marks.items()}
    out = []
    for s in ("left", "right"):
        sh, el, wr, ap = (f"{n}_{s}" for n in ("shoulder_point", "elbow_point", "wrist_point", "armpit_point"))
        if "back_neck_point" in p and sh in p and el in p:
            bnp = p["back_neck_point"]
            d_sh, d_el = np.linalg.norm(p[sh] - bnp), np.linalg.norm(p[el] - bnp)
            if d_sh >= d_el:
                out.append((sh, el, f"the shoulder point is beyond the elbow ({d_sh:.1f} against "
                                    f"{d_el:.1f} cm from the back neck point)"))
            if wr in p and d_el >= np.linalg.norm(p[wr] - bnp):
                out.append((el, wr, "the elbow point is beyond the wrist"))
        if sh in p and abs(p[sh][0] - c) > 0.2 * stature:
            out.append((sh, sh, f"the shoulder point is {abs(p[sh][0] - c):.1f} cm from the midline "
                                f"(more than 20 % of the stature)"))
        if sh in p and ap in p and p[sh][1] <= p[ap][1]:
            out.append((sh, ap, "the shoulder point is not above the armpit"))
        bp = f"bust_point_{s}"
        if bp in p and "waist_front" in p and p["waist_front"][1] >= p[bp][1]:
            out.append(("waist_front", bp, "the waist is not below the bust point"))
        if bp in p and "front_neck_point" in p and p[bp][1] >= p["front_neck_point"][1]:
            out.append((bp, "front_neck_point", "the bust point is not below the front neck point"))
    if "waist_front" in p and "crotch_point" in p and p["waist_front"][1] <= p["crotch_point"][1]:
        out.append(("waist_front", "crotch_point", "the waist is not above the crotch"))
    return out


def _check_order(marks: dict[str, Landmark], v: np.ndarray, faces: np.ndarray, name: str) -> None:
    stature = float(np.ptp(v[:, 1]))
    c = mirror_plane_x(v, faces)
    for _ in range(len(marks)):  # drop one offender at a time, then look again
        broken = _order_rules(marks, stature, c)
        if not broken:
            return
        a, b, what = broken[0]
        la, lb = marks[a], marks[b]
        if la.source == LandmarkSource.FILE and lb.source == LandmarkSource.FILE:
            raise LandmarkError(
                f"{name}: landmarks {a} and {b} are implausible: {what}; fix the landmark file"
            )
        drop = a if (lb.source == LandmarkSource.FILE or la.confidence <= lb.confidence) else b
        if marks[drop].source == LandmarkSource.FILE:
            drop = b if drop == a else a
        log.warning("%s: refused the %s landmark %s: %s", name, marks[drop].source, drop, what)
        del marks[drop]


def check_landmarks(character: Character, marks: Mapping[str, Landmark]) -> dict[str, Landmark]:
    """Check a landmark set on its body; return it corrected (see the module notes).

    Raises
    ------
    LandmarkError
        Landmarks from a file break an order (a shoulder point beyond the elbow...).
    """
    out = dict(marks)
    v = np.asarray(character.vertices, dtype=np.float64)
    sym = _Symmetry(v, np.asarray(character.faces))
    _check_order(out, v, np.asarray(character.faces), character.name)
    _check_midline(out, v, sym)
    _check_pairs(out, v, sym, character.name)
    return out
