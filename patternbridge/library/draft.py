"""Drafting primitives: sampled curves, outline builders and seam-allowance offsets.

A draft is written as a walk round the net (sew) line of a piece: straight
lines and cubic Bézier curves, each sampled with a fixed number of points so
that every size of a garment has the same vertex count and order (vertex ``i``
of one size corresponds to vertex ``i`` of every other size). Named marks are
set on the vertices the walk passes through; notches can be dropped at an arc
length along a curve (a vertex is inserted there).

The cut line (layer 1, the piece outline) is the sew line offset outwards by a
per-edge seam allowance, vertex for vertex, with mitred corners, so a mark
indexes the same place on both lines. See ``docs/library.md``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely

from ..pattern.geometry import arc_lengths, signed_area
from ..pattern.model import VertexKind

__all__ = [
    "NetOutline",
    "OutlineBuilder",
    "bezier",
    "bezier_length",
    "bezier_split",
    "bezier_t_at",
    "hermite",
    "hermite_controls",
    "insert_at_length",
    "offset_outline",
]

#: longest mitre, as a multiple of the seam allowance, before a corner is blunted
MITRE_LIMIT = 3.0


def bezier(p0, p1, p2, p3, n: int) -> np.ndarray:
    """Sample a cubic Bézier curve at ``n + 1`` evenly spaced parameters.

    Parameters
    ----------
    p0, p1, p2, p3 : (2,) control points, cm
    n : number of segments (``n >= 1``)

    Returns
    -------
    (n + 1, 2) float64 — the first row is ``p0`` and the last ``p3``.

    Examples
    --------
    >>> bezier((0, 0), (1, 0), (2, 0), (3, 0), 3)[:, 0].round(12).tolist()
    [0.0, 1.0, 2.0, 3.0]
    """
    t = np.linspace(0.0, 1.0, n + 1)[:, None]
    c = np.asarray([p0, p1, p2, p3], dtype=np.float64)
    return (
        (1 - t) ** 3 * c[0]
        + 3 * (1 - t) ** 2 * t * c[1]
        + 3 * (1 - t) * t**2 * c[2]
        + t**3 * c[3]
    )


def bezier_split(ctrl, t: float) -> tuple[np.ndarray, np.ndarray]:
    """Split a cubic Bézier (4, 2) at parameter ``t`` (de Casteljau); returns two (4, 2)."""
    c = np.asarray(ctrl, dtype=np.float64)
    a = c[:-1] + t * (c[1:] - c[:-1])
    b = a[:-1] + t * (a[1:] - a[:-1])
    m = b[0] + t * (b[1] - b[0])
    return np.array([c[0], a[0], b[0], m]), np.array([m, b[1], a[2], c[3]])


def bezier_length(ctrl, n: int = 200) -> float:
    """Arc length (cm) of a cubic Bézier given as (4, 2) controls."""
    c = np.asarray(ctrl, dtype=np.float64)
    pts = bezier(*c, n)
    return float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())


def bezier_t_at(ctrl, axis: int, value: float, n: int = 400) -> float:
    """Parameter where a cubic Bézier first crosses ``coordinate[axis] == value``.

    Raises
    ------
    ValueError
        When the curve does not reach ``value``.
    """
    c = np.asarray(ctrl, dtype=np.float64)
    pts = bezier(*c, n)[:, axis] - value
    sign = np.sign(pts)
    cross = np.nonzero(sign[:-1] * sign[1:] <= 0)[0]
    if len(cross) == 0:
        raise ValueError(f"curve does not cross {'xy'[axis]} = {value}")
    i = int(cross[0])
    f = pts[i] / (pts[i] - pts[i + 1]) if pts[i] != pts[i + 1] else 0.0
    return (i + f) / n


def hermite_controls(p0, t0, p1, t1) -> np.ndarray:
    """Bézier controls (4, 2) of the Hermite curve of :func:`hermite`."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    t0, t1 = np.asarray(t0, float), np.asarray(t1, float)
    chord = float(np.hypot(*(p1 - p0)))
    return np.array([p0, p0 + t0 * chord / 3.0, p1 - t1 * chord / 3.0, p1])


def hermite(p0, t0, p1, t1, n: int) -> np.ndarray:
    """Sample a cubic Hermite curve from ``p0`` (tangent ``t0``) to ``p1`` (tangent ``t1``).

    The tangents are scaled to the chord length, so ``t0``/``t1`` give
    directions and a fullness factor (1 = a natural curve).

    Returns
    -------
    (n + 1, 2) float64, cm
    """
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    t0, t1 = np.asarray(t0, float), np.asarray(t1, float)
    chord = float(np.hypot(*(p1 - p0)))

    def unit(v):
        norm = float(np.hypot(*v))
        return v / norm if norm > 0 else v

    k0, k1 = float(np.hypot(*t0)), float(np.hypot(*t1))
    c1 = p0 + unit(t0) * k0 * chord / 3.0
    c2 = p1 - unit(t1) * k1 * chord / 3.0
    return bezier(p0, c1, c2, p1, n)


def insert_at_length(points: np.ndarray, s: float) -> tuple[np.ndarray, int]:
    """Insert a vertex into an open polyline at arc length ``s`` from its start.

    The vertex replaces the nearest existing interior vertex when one lies
    closer than 1 % of the segment, so repeated drafts keep their vertex count
    only if the caller always inserts (it does: the nearest vertex is moved,
    not dropped).

    Returns
    -------
    (points, index) — the new (m, 2) polyline and the index of the vertex at ``s``.
    """
    pts = np.asarray(points, dtype=np.float64)
    cum = arc_lengths(pts)
    s = float(np.clip(s, 1e-6, cum[-1] - 1e-6))
    j = int(np.searchsorted(cum, s) - 1)
    j = max(0, min(j, len(pts) - 2))
    t = (s - cum[j]) / max(cum[j + 1] - cum[j], 1e-12)
    p = pts[j] + t * (pts[j + 1] - pts[j])
    out = np.concatenate([pts[: j + 1], p[None], pts[j + 1 :]])
    return out, j + 1


@dataclass
class NetOutline:
    """A drafted net (sew-line) outline with vertex kinds, marks and notch marks.

    points : (n, 2) float64, cm, closed, CCW, no repeat
    kinds : n vertex kinds
    marks : mark name -> vertex index
    notches : names of the marks that carry a notch
    allowance : (n,) seam allowance (cm) of the edge from vertex i to i + 1
    darts : indices of dart apex vertices (the cut line closes over them)
    """

    points: np.ndarray
    kinds: list[VertexKind]
    marks: dict[str, int]
    notches: list[str]
    allowance: np.ndarray
    darts: list[int] = field(default_factory=list)

    def length(self, start: str, end: str) -> float:
        """Sew-line length (cm) from mark ``start`` to mark ``end`` in outline order."""
        n = len(self.points)
        i, j = self.marks[start], self.marks[end]
        idx = np.arange(i, j + 1) if j >= i else np.r_[i:n, 0 : j + 1]
        return float(np.linalg.norm(np.diff(self.points[idx], axis=0), axis=1).sum())

    def notch_offsets(self, start: str, end: str) -> list[float]:
        """Arc lengths (cm from ``start``) of the notches strictly inside the range."""
        n = len(self.points)
        i, j = self.marks[start], self.marks[end]
        idx = np.arange(i, j + 1) if j >= i else np.r_[i:n, 0 : j + 1]
        cum = arc_lengths(self.points[idx])
        notch_idx = {self.marks[m] for m in self.notches}
        return [
            float(cum[k]) for k in range(1, len(idx) - 1) if int(idx[k]) in notch_idx
        ]


class OutlineBuilder:
    """Walk round a piece's sew line, collecting points, kinds and marks.

    Start with :meth:`start`, then :meth:`line` / :meth:`curve` segments; the
    seam allowance given with a segment applies to its edges. :meth:`close`
    checks the walk is counter-clockwise and returns a :class:`NetOutline`.

    Examples
    --------
    >>> b = OutlineBuilder()
    >>> b.start((0, 0), "a")
    >>> b.line((4, 0), "b", allowance_cm=1)
    >>> b.line((4, 3), "c", allowance_cm=1)
    >>> net = b.close(allowance_cm=1)
    >>> net.marks
    {'a': 0, 'b': 1, 'c': 2}
    """

    def __init__(self) -> None:
        self._pts: list[np.ndarray] = []
        self._kinds: list[VertexKind] = []
        self._allow: list[float] = []
        self._marks: dict[str, int] = {}
        self._notches: list[str] = []
        self._darts: list[int] = []

    def start(self, p, mark: str | None = None, *, notch: bool = False) -> None:
        """Set the first vertex (a turn point)."""
        self._pts = [np.asarray(p, dtype=np.float64)]
        self._kinds = [VertexKind.TURN]
        self._allow = []
        if mark:
            self._set_mark(mark, 0, notch)

    @property
    def current(self) -> np.ndarray:
        """The last vertex of the walk so far."""
        return self._pts[-1]

    def _set_mark(self, name: str, index: int, notch: bool) -> None:
        if name in self._marks:
            raise ValueError(f"mark {name!r} set twice")
        self._marks[name] = index
        if notch:
            self._notches.append(name)

    def line(
        self,
        p,
        mark: str | None = None,
        *,
        allowance_cm: float = 1.0,
        notch: bool = False,
        dart_apex: bool = False,
    ) -> None:
        """Straight edge to ``p``, ending in a turn point."""
        self._pts.append(np.asarray(p, dtype=np.float64))
        self._kinds.append(VertexKind.TURN)
        self._allow.append(float(allowance_cm))
        if mark:
            self._set_mark(mark, len(self._pts) - 1, notch)
        if dart_apex:
            self._darts.append(len(self._pts) - 1)

    def polyline(
        self,
        pts: np.ndarray,
        mark: str | None = None,
        *,
        allowance_cm: float = 1.0,
        notch: bool = False,
        at: Sequence[tuple[float, str, bool]] = (),
        end_kind: VertexKind = VertexKind.TURN,
    ) -> None:
        """Append a sampled curve ``pts`` whose first row is the current vertex.

        at : ``(arc_length_cm, mark, notch)`` marks dropped along the curve;
            a vertex is inserted at each.
        """
        pts = np.asarray(pts, dtype=np.float64)
        if not np.allclose(pts[0], self._pts[-1], atol=1e-9):
            raise ValueError("curve does not start at the current vertex")
        inserted: list[tuple[int, str, bool]] = []
        for s, name, is_notch in sorted(at, key=lambda a: a[0]):
            pts, idx = insert_at_length(pts, s)
            inserted = [(i + (1 if i >= idx else 0), n, k) for i, n, k in inserted]
            inserted.append((idx, name, is_notch))
        base = len(self._pts) - 1
        for q in pts[1:-1]:
            self._pts.append(q)
            self._kinds.append(VertexKind.CURVE)
            self._allow.append(float(allowance_cm))
        self._pts.append(pts[-1])
        self._kinds.append(end_kind)
        self._allow.append(float(allowance_cm))
        for idx, name, is_notch in inserted:
            self._set_mark(name, base + idx, is_notch)
        if mark:
            self._set_mark(mark, len(self._pts) - 1, notch)

    def curve(
        self,
        c1,
        c2,
        p3,
        mark: str | None = None,
        *,
        n: int = 10,
        allowance_cm: float = 1.0,
        notch: bool = False,
        at: Sequence[tuple[float, str, bool]] = (),
        end_kind: VertexKind = VertexKind.TURN,
    ) -> None:
        """Cubic Bézier from the current vertex with controls ``c1``, ``c2`` to ``p3``."""
        self.polyline(
            bezier(self._pts[-1], c1, c2, p3, n),
            mark,
            allowance_cm=allowance_cm,
            notch=notch,
            at=at,
            end_kind=end_kind,
        )

    def bezier(
        self,
        ctrl,
        mark: str | None = None,
        *,
        n: int = 10,
        allowance_cm: float = 1.0,
        notch: bool = False,
        at: Sequence[tuple[float, str, bool]] = (),
        end_kind: VertexKind = VertexKind.TURN,
    ) -> None:
        """Cubic Bézier given as (4, 2) controls whose first row is the current vertex.

        Marks ``at`` arc lengths split the curve there; each part is sampled
        with a fixed share of the ``n`` segments, so the vertex count and the
        marks' indices do not depend on where the marks fall (unlike
        :meth:`polyline`'s insertion, which is only safe far from vertices).
        """
        c = np.asarray(ctrl, dtype=np.float64)
        if not at:
            self.curve(
                c[1],
                c[2],
                c[3],
                mark,
                n=n,
                allowance_cm=allowance_cm,
                notch=notch,
                end_kind=end_kind,
            )
            return
        dense_t = np.linspace(0.0, 1.0, 4001)
        cum = arc_lengths(bezier(*c, 4000))
        stops = sorted(at, key=lambda a: a[0])
        ts = [float(np.interp(s, cum, dense_t)) for s, _m, _k in stops]
        k = len(stops) + 1
        counts = [max(2, n // k)] * (k - 1) + [max(2, n - (n // k) * (k - 1))]
        rest, t_done = c, 0.0
        for (_s, name, is_notch), t, m in zip(stops, ts, counts[:-1], strict=True):
            local = (t - t_done) / (1.0 - t_done)
            part, rest = bezier_split(rest, local)
            t_done = t
            self.polyline(
                bezier(*part, m),
                name,
                allowance_cm=allowance_cm,
                notch=is_notch,
                end_kind=VertexKind.CURVE,
            )
        self.polyline(
            bezier(*rest, counts[-1]),
            mark,
            allowance_cm=allowance_cm,
            notch=notch,
            end_kind=end_kind,
        )

    def darted_line(
        self,
        p,
        mark: str | None,
        darts: Sequence[tuple[float, float, float, str]],
        *,
        allowance_cm: float = 1.0,
    ) -> None:
        """Straight edge to ``p`` with V darts cut into it.

        darts : ``(centre_cm, width_cm, length_cm, prefix)`` — dart centre as a
            distance along the edge from the current vertex, its width at the
            edge and its length into the piece (square to the edge). Marks
            ``<prefix>_a`` (first dart top walked), ``<prefix>_apex`` and
            ``<prefix>_b`` are set, with notches on the tops.
        """
        p0 = self._pts[-1].copy()
        p1 = np.asarray(p, dtype=np.float64)
        d = p1 - p0
        u = d / np.hypot(*d)
        inward = np.array([-u[1], u[0]])  # the piece lies left of a CCW walk
        for centre, width, length, prefix in sorted(darts, key=lambda t: t[0]):
            c = p0 + u * centre
            self.line(
                c - u * width / 2, f"{prefix}_a", allowance_cm=allowance_cm, notch=True
            )
            self.line(
                c + inward * length,
                f"{prefix}_apex",
                allowance_cm=allowance_cm,
                dart_apex=True,
            )
            self.line(
                c + u * width / 2, f"{prefix}_b", allowance_cm=allowance_cm, notch=True
            )
        self.line(p1, mark, allowance_cm=allowance_cm)

    def close(self, *, allowance_cm: float = 1.0) -> NetOutline:
        """Close the walk (last vertex back to the first) and return the net outline.

        Raises
        ------
        ValueError
            When the walk is clockwise or self-intersecting (a drafting bug).
        """
        pts = np.asarray(self._pts, dtype=np.float64)
        if np.allclose(pts[0], pts[-1]):
            raise ValueError("do not repeat the first vertex; close() joins it")
        allow = np.asarray([*self._allow, float(allowance_cm)], dtype=np.float64)
        if signed_area(pts) <= 0:
            raise ValueError("outline walk must run counter-clockwise")
        if not shapely.is_simple(shapely.linearrings(pts)):
            raise ValueError("outline walk intersects itself")
        return NetOutline(
            points=pts,
            kinds=list(self._kinds),
            marks=dict(self._marks),
            notches=list(self._notches),
            allowance=allow,
            darts=list(self._darts),
        )


def offset_outline(
    points: np.ndarray, allowance_cm: np.ndarray, darts: Sequence[int] = ()
) -> np.ndarray:
    """Offset a CCW outline outwards edge by edge, keeping one vertex per vertex.

    Each cut-line vertex is the intersection of the two neighbouring edges'
    offset lines (a mitre); nearly parallel edges take the mean normal and
    mitres longer than ``MITRE_LIMIT`` allowances are pulled in. At a dart the
    two dart tops are offset along the edge outside the dart and the apex is
    put half-way between them, so the cut line runs straight across the dart
    mouth (the dart is marked by notches, not cut).

    Parameters
    ----------
    points : (n, 2) float64, cm, CCW
    allowance_cm : (n,) float64 — allowance of the edge from vertex i to i + 1
    darts : indices of dart apex vertices

    Returns
    -------
    (n, 2) float64, cm

    Examples
    --------
    >>> sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    >>> offset_outline(sq, np.ones(4)).tolist()
    [[-1.0, -1.0], [3.0, -1.0], [3.0, 3.0], [-1.0, 3.0]]
    """
    p = np.asarray(points, dtype=np.float64)
    d_next = np.asarray(allowance_cm, dtype=np.float64)
    d_prev = np.roll(d_next, 1)
    e_next = np.roll(p, -1, axis=0) - p
    e_prev = p - np.roll(p, 1, axis=0)
    # outward normal of a CCW edge (dx, dy) is (dy, -dx)
    n_next = np.stack([e_next[:, 1], -e_next[:, 0]], axis=1)
    n_prev = np.stack([e_prev[:, 1], -e_prev[:, 0]], axis=1)
    n_next /= np.linalg.norm(n_next, axis=1, keepdims=True)
    n_prev /= np.linalg.norm(n_prev, axis=1, keepdims=True)
    # solve (q - p)·n_prev = d_prev, (q - p)·n_next = d_next
    det = n_prev[:, 0] * n_next[:, 1] - n_prev[:, 1] * n_next[:, 0]
    safe = np.abs(det) > 1e-3
    det_s = np.where(safe, det, 1.0)
    ox = (d_prev * n_next[:, 1] - d_next * n_prev[:, 1]) / det_s
    oy = (n_prev[:, 0] * d_next - n_next[:, 0] * d_prev) / det_s
    off = np.stack([ox, oy], axis=1)
    mean_n = n_prev + n_next
    mean_n /= np.maximum(np.linalg.norm(mean_n, axis=1, keepdims=True), 1e-12)
    fallback = mean_n * (0.5 * (d_prev + d_next))[:, None]
    off = np.where(safe[:, None], off, fallback)
    limit = MITRE_LIMIT * np.maximum(d_prev, d_next)
    length = np.linalg.norm(off, axis=1)
    scale = np.where(length > limit, limit / np.maximum(length, 1e-12), 1.0)
    cut = p + off * scale[:, None]
    n = len(p)
    for i in darts:
        a, b = (i - 1) % n, (i + 1) % n
        # dart tops follow the edge outside the dart only; the apex sits between them
        cut[a] = p[a] + n_prev[a] * d_prev[a]
        cut[b] = p[b] + n_next[b] * d_next[b]
        cut[i] = 0.5 * (cut[a] + cut[b])
    return cut
