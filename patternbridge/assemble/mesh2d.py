"""Triangulate pattern pieces with matched seam vertices and pattern UVs.

Every piece boundary is cut at its corners and at the marks, and the cuts are
carried across every seam (a cut at 40 % of one side of a seam makes a cut at
40 % of the other side), so both sides of a seam are made of the same number
of boundary segments. Sewn segments get one common vertex count, chosen from
the longer side and the target edge length, and are resampled at equal arc
length; vertex ``k`` of one side then faces vertex ``k`` of the other (or
``n - k`` for a reversed seam). Sewn segments shorter than a tenth of an
edge get no vertex: a cluster of cuts (carried round a loop of eased seams,
they land a few hundredths of a mm apart) is one vertex, at the piece's own
mark or corner when it has one. The interior is meshed by the triangle
library (quality mesh, no Steiner points on the boundary), and the 2D pattern
coordinates of each vertex are kept as its UV.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..pattern.model import Copy, Pattern, Piece

__all__ = ["Instance", "PatternMesh", "PieceMesh", "SeamPairs", "mesh_pattern"]

log = logging.getLogger(__name__)

_CORNER_ANGLE = np.deg2rad(30.0)  # turning angle above which a boundary vertex is a corner
_MIN_SEGMENT_SHARE = 0.1  # boundary segments shorter than this share of the edge length get no vertex


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class PieceMesh:
    """A triangulated piece in its own pattern frame.

    points : (n, 2) float64, cm — pattern coordinates (the UVs); the first
        ``n_boundary`` points are the boundary, counter-clockwise
    faces : (F, 3) int64, counter-clockwise in the pattern plane
    marks : mark name -> vertex index (boundary)
    """

    name: str
    points: np.ndarray
    faces: np.ndarray
    n_boundary: int
    marks: dict[str, int] = field(default_factory=dict)


@dataclass(frozen=True, slots=True, kw_only=True)
class Instance:
    """One cut copy of a piece in the garment (``copy`` primary or mirror)."""

    piece: str
    copy: Copy

    @property
    def key(self) -> str:
        return self.piece if self.copy is Copy.PRIMARY else f"{self.piece}~mirror"


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class SeamPairs:
    """Matched vertices of one seam: ``a[k]`` is sewn to ``b[k]`` (local vertex ids)."""

    seam: str
    a: Instance
    b: Instance
    a_vertices: np.ndarray
    b_vertices: np.ndarray


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class PatternMesh:
    """The meshed pattern: one mesh per piece, the cut copies and the sewn vertex pairs."""

    pieces: dict[str, PieceMesh]
    instances: tuple[Instance, ...]
    seams: tuple[SeamPairs, ...]
    max_edge_cm: float


# --------------------------------------------------------------------------- arc parameters
def _arc(outline: np.ndarray) -> tuple[np.ndarray, float]:
    seg = np.linalg.norm(np.roll(outline, -1, axis=0) - outline, axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    return s[:-1], float(s[-1])


def _point_at(outline: np.ndarray, s: np.ndarray, t: np.ndarray, total: float) -> np.ndarray:
    """Points at arc parameters ``t`` along the closed outline."""
    t = np.mod(t, total)
    i = np.clip(np.searchsorted(s, t, side="right") - 1, 0, len(s) - 1)
    nxt = np.roll(outline, -1, axis=0)
    seg = np.linalg.norm(nxt - outline, axis=1)
    u = np.where(seg[i] > 0, (t - s[i]) / np.where(seg[i] > 0, seg[i], 1.0), 0.0)
    return outline[i] + u[:, None] * (nxt[i] - outline[i])


def _corners(piece: Piece) -> np.ndarray:
    o = piece.outline
    d0 = o - np.roll(o, 1, axis=0)
    d1 = np.roll(o, -1, axis=0) - o
    a0 = np.arctan2(d0[:, 1], d0[:, 0])
    a1 = np.arctan2(d1[:, 1], d1[:, 0])
    turn = np.abs(np.angle(np.exp(1j * (a1 - a0))))
    kinds = np.array([str(k) == "turn" for k in piece.kinds])
    return np.flatnonzero((turn > _CORNER_ANGLE) | kinds)


class _Breaks:
    """Sorted arc-parameter cut positions of one piece boundary."""

    def __init__(self, total: float) -> None:
        self.total = total
        self.values: list[float] = []

    def add(self, t: float) -> bool:
        t = float(np.mod(t, self.total))
        tol = 1e-6 * max(self.total, 1.0)
        for v in self.values:
            d = abs(v - t)
            if min(d, self.total - d) < tol:
                return False
        self.values.append(t)
        self.values.sort()
        return True

    def index(self, t: float) -> int:
        t = float(np.mod(t, self.total))
        d = np.abs(np.array(self.values) - t)
        d = np.minimum(d, self.total - d)
        return int(np.argmin(d))


def _boundary_params(b: list[float], total: float, counts: list[int], own: set[float]) -> tuple[np.ndarray, list[int]]:
    """Arc parameters of a piece's boundary vertices and the index of every segment's first vertex.

    Segment ``j`` runs from cut ``b[j]`` to the next and gets ``counts[j]``
    vertices at equal arc length. A segment with none (shorter than a tenth
    of an edge, see :data:`_MIN_SEGMENT_SHARE`) merges into the next: the
    vertex that starts the next segment stands for the whole cluster of cuts,
    at the piece's own cut (a mark or corner, ``own``) when the cluster has
    one. Its index is the first vertex of every segment of the cluster.
    """
    k = len(b)
    first = next(j for j in range(k) if counts[j - 1] > 0)  # a segment after one with vertices: no wrap
    ts: list[float] = []
    starts = [0] * k
    cluster: list[float] = []
    for j in (np.arange(k) + first) % k:
        starts[j] = len(ts)
        cluster.append(b[j])
        if counts[j] == 0:
            continue
        length = float(np.mod(b[(j + 1) % k] - b[j], total)) or total
        at = [t for t in cluster if t in own]
        ts.append(at[0] if at else b[j])
        ts.extend((b[j] + length * np.arange(1, counts[j]) / counts[j]).tolist())
        cluster = []
    return np.array(ts), starts


def _instances(pattern: Pattern) -> tuple[Instance, ...]:
    out: list[Instance] = []
    for p in pattern.pieces:
        if p.quantity.right > 0 or p.quantity.left == 0:
            out.append(Instance(piece=p.name, copy=Copy.PRIMARY))
        if p.quantity.left > 0:
            out.append(Instance(piece=p.name, copy=Copy.MIRROR))
    have = {(i.piece, i.copy) for i in out}
    for seam in pattern.seams:
        for r in (seam.a, seam.b):
            if (r.piece, r.copy) not in have:
                log.warning(
                    "seam %s uses the %s copy of %s, which the quantity does not cut; adding it",
                    seam.id,
                    r.copy,
                    r.piece,
                )
                out.append(Instance(piece=r.piece, copy=r.copy))
                have.add((r.piece, r.copy))
    return tuple(out)


def _check_seams(pattern: Pattern) -> None:
    names = set(pattern.piece_names)
    for seam in pattern.seams:
        for r in (seam.a, seam.b):
            if r.piece not in names:
                raise InputError(
                    f"{pattern.style}: seam {seam.id!r} names piece {r.piece!r}, which the pattern lacks "
                    f"(pieces: {sorted(names)}); fix the seam table"
                )
            piece = pattern.piece(r.piece)
            for m in (r.start, r.end):
                if m not in piece.marks:
                    raise InputError(
                        f"{pattern.style}: seam {seam.id!r} names mark {m!r} on piece {r.piece!r}, which has "
                        f"only {sorted(piece.marks)}; fix the seam table or the marks"
                    )


def _on_sew_line(piece: Piece) -> Piece:
    """The piece with its sew line (net line) as outline when it has one vertex per outline vertex.

    Seams are sewn on the sew line; the seam allowance outside it is folded
    inside the garment and is not part of the draped surface.
    """
    import dataclasses

    if piece.sew_lines and len(piece.sew_lines[0].points) == piece.n_vertices and piece.sew_lines[0].closed:
        return dataclasses.replace(piece, outline=piece.sew_lines[0].points, sew_lines=(), notches=())
    return piece


def _range(r, pieces: dict[str, Piece], arcs: dict[str, tuple[np.ndarray, float]]) -> tuple[float, float, float]:
    """Start arc parameter, length and boundary length of the edge range ``r`` (an :class:`EdgeRange`)."""
    s, total = arcs[r.piece]
    p = pieces[r.piece]
    s0, s1 = s[p.marks[r.start]], s[p.marks[r.end]]
    length = float(np.mod(s1 - s0, total)) or total
    return s0, length, total


@dataclass(frozen=True, slots=True, kw_only=True)
class _Cuts:
    """Every piece boundary cut at its corners and marks, the cuts carried across every seam.

    arcs : piece -> (arc parameter of each outline vertex (n,), boundary length cm)
    breaks : piece -> its cuts (after carrying)
    own : piece -> the piece's own cuts (marks, corners), before carrying
    """

    pieces: dict[str, Piece]
    arcs: dict[str, tuple[np.ndarray, float]]
    breaks: dict[str, _Breaks]
    own: dict[str, set[float]]

    def range(self, r) -> tuple[float, float, float]:
        return _range(r, self.pieces, self.arcs)


def _cut_boundaries(pattern: Pattern, pieces: dict[str, Piece]) -> _Cuts:
    """Cut every boundary at its corners and marks and carry the cuts across the seams until both sides match."""
    arcs = {n: _arc(p.outline) for n, p in pieces.items()}
    breaks = {n: _Breaks(arcs[n][1]) for n in pieces}
    for n, p in pieces.items():
        s, _ = arcs[n]
        for v in sorted(set(p.marks.values()) | set(_corners(p).tolist())):
            breaks[n].add(s[v])
        if not breaks[n].values:
            breaks[n].add(0.0)
    own = {n: set(breaks[n].values) for n in pieces}
    for _ in range(20):
        changed = False
        for seam in pattern.seams:
            for x, y in ((seam.a, seam.b), (seam.b, seam.a)):
                s0x, lx, tx = _range(x, pieces, arcs)
                s0y, ly, _ = _range(y, pieces, arcs)
                for t in list(breaks[x.piece].values):
                    f = np.mod(t - s0x, tx) / lx
                    if 1e-6 < f < 1 - 1e-6:
                        g = 1.0 - f if seam.reverse else f
                        changed |= breaks[y.piece].add(s0y + g * ly)
        if not changed:
            break
    return _Cuts(pieces=pieces, arcs=arcs, breaks=breaks, own=own)


@dataclass(frozen=True, slots=True, kw_only=True)
class _Segments:
    """The boundary segments between the cuts and their vertex counts.

    counts : (piece, segment) -> vertex count (one count per group of sewn segments)
    seam_segments : per seam, the segments of its two sides (in each side's own order)
    """

    counts: dict[tuple[str, int], int]
    seam_segments: tuple[tuple[list[int], list[int]], ...]


def _range_segments(cuts: _Cuts, r) -> list[int]:
    """The segments of the edge range ``r``, in boundary order."""
    s0, length, _ = cuts.range(r)
    br = cuts.breaks[r.piece]
    j0 = br.index(s0)
    j1 = br.index(s0 + length)
    k = len(br.values)
    out, j = [], j0
    while True:
        out.append(j)
        j = (j + 1) % k
        if j == j1:
            break
    return out


def _segment_counts(pattern: Pattern, cuts: _Cuts, max_edge_cm: float) -> _Segments:
    """Group the sewn segments and give each group one vertex count, from its longest segment."""
    seg_keys: dict[tuple[str, int], int] = {}
    seg_len: list[float] = []
    for n in cuts.pieces:
        b = cuts.breaks[n].values
        total = cuts.breaks[n].total
        for j in range(len(b)):
            seg_keys[(n, j)] = len(seg_len)
            seg_len.append(float(np.mod(b[(j + 1) % len(b)] - b[j], total)) or total)
    parent = list(range(len(seg_len)))

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    seam_segments = []
    for seam in pattern.seams:
        sa, sb = _range_segments(cuts, seam.a), _range_segments(cuts, seam.b)
        if len(sa) != len(sb):
            raise InputError(
                f"{pattern.style}: seam {seam.id!r} sides could not be matched ({len(sa)} against {len(sb)} "
                "boundary segments); check that its marks bound the same stretch on both pieces"
            )
        sb_ordered = sb[::-1] if seam.reverse else sb
        for x, y in zip(sa, sb_ordered, strict=True):
            parent[find(seg_keys[(seam.a.piece, x)])] = find(seg_keys[(seam.b.piece, y)])
        seam_segments.append((sa, sb))
    # a group of sewn segments all shorter than a tenth of an edge gets no vertex of its own: its start merges
    # into the next segment's (cuts carried round a loop of seams with ease, such as sleeve cap, armhole, side
    # seam and underarm seam, land a few hundredths of a mm from each other)
    longest: dict[int, float] = {}
    for i, length in enumerate(seg_len):
        longest[find(i)] = max(longest.get(find(i), 0.0), length)
    counts_group = {
        g: int(np.ceil(length / max_edge_cm - 1e-9)) if length >= _MIN_SEGMENT_SHARE * max_edge_cm else 0
        for g, length in longest.items()
    }
    counts = {key: counts_group[find(i)] for key, i in seg_keys.items()}
    return _Segments(counts=counts, seam_segments=tuple(seam_segments))


@dataclass(frozen=True, slots=True, kw_only=True)
class _MeshedPiece:
    """A triangulated piece and the boundary vertex index where each of its segments starts."""

    mesh: PieceMesh
    starts: tuple[int, ...]


def _mesh_piece(style: str, n: str, cuts: _Cuts, segments: _Segments, max_edge_cm: float) -> _MeshedPiece:
    """Resample the boundary of piece ``n`` at its segments' vertex counts and triangulate its interior."""
    import triangle

    p = cuts.pieces[n]
    s, total = cuts.arcs[n]
    b = cuts.breaks[n].values
    counts = [segments.counts[(n, j)] for j in range(len(b))]
    ts, starts = _boundary_params(b, total, counts, cuts.own[n])
    boundary = _point_at(p.outline, s, ts, total)
    m = len(boundary)
    segs = np.stack([np.arange(m), (np.arange(m) + 1) % m], axis=1)
    area = 0.5 * np.sqrt(3.0) / 2.0 * max_edge_cm**2
    try:
        tri = triangle.triangulate({"vertices": boundary, "segments": segs}, f"pq28a{area:.6f}YQ")
    except Exception as exc:  # triangle raises plain RuntimeError on bad input
        raise InputError(
            f"{style}: piece {n!r} could not be triangulated ({exc}); check that its outline is simple"
        ) from exc
    pts = np.asarray(tri["vertices"], dtype=np.float64)
    faces = np.asarray(tri["triangles"], dtype=np.int64)
    if len(pts) < m or not np.allclose(pts[:m], boundary):
        raise InputError(
            f"{style}: piece {n!r} boundary changed while meshing (self-touching outline?); "
            "check that the outline is simple"
        )
    u, w = pts[faces[:, 1]] - pts[faces[:, 0]], pts[faces[:, 2]] - pts[faces[:, 0]]
    a2 = u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]
    faces = np.where((a2 < 0)[:, None], faces[:, ::-1], faces)
    marks = {name: starts[cuts.breaks[n].index(s[v])] for name, v in p.marks.items()}
    mesh = PieceMesh(name=n, points=pts, faces=faces, n_boundary=m, marks=marks)
    return _MeshedPiece(mesh=mesh, starts=tuple(starts))


def _seam_pairs(pattern: Pattern, meshed: dict[str, _MeshedPiece], segments: _Segments) -> tuple[SeamPairs, ...]:
    """The matched boundary vertices of every seam."""

    def range_vertices(r, segs: list[int]) -> np.ndarray:
        n = r.piece
        m = meshed[n].mesh.n_boundary
        first = meshed[n].starts[segs[0]]
        count = sum(segments.counts[(n, j)] for j in segs)
        return (first + np.arange(count + 1)) % m

    pairs = []
    for seam, (sa, sb) in zip(pattern.seams, segments.seam_segments, strict=True):
        va = range_vertices(seam.a, sa)
        vb = range_vertices(seam.b, sb)
        if seam.reverse:
            vb = vb[::-1]
        pairs.append(
            SeamPairs(
                seam=seam.id,
                a=Instance(piece=seam.a.piece, copy=seam.a.copy),
                b=Instance(piece=seam.b.piece, copy=seam.b.copy),
                a_vertices=va,
                b_vertices=vb,
            )
        )
    return tuple(pairs)


def mesh_pattern(pattern: Pattern, *, max_edge_cm: float = 2.0) -> PatternMesh:
    """Triangulate every piece so that sewn boundaries have matching vertices.

    Parameters
    ----------
    pattern : a pattern with seams (bridge data)
    max_edge_cm : target edge length of the triangles, cm

    Returns
    -------
    :class:`PatternMesh`

    Raises
    ------
    InputError
        A seam names an unknown piece or mark, or a piece cannot be triangulated.
    """
    if max_edge_cm <= 0:
        raise ValueError(f"max_edge_cm must be positive, got {max_edge_cm}")
    _check_seams(pattern)
    cuts = _cut_boundaries(pattern, {p.name: _on_sew_line(p) for p in pattern.pieces})
    segments = _segment_counts(pattern, cuts, max_edge_cm)
    meshed = {n: _mesh_piece(pattern.style, n, cuts, segments, max_edge_cm) for n in cuts.pieces}
    return PatternMesh(
        pieces={n: mp.mesh for n, mp in meshed.items()},
        instances=_instances(pattern),
        seams=_seam_pairs(pattern, meshed, segments),
        max_edge_cm=float(max_edge_cm),
    )
