"""Checks that a graded pattern still is the design: findings for a collapsed piece, a flattened curve, a lost symmetry.

The fit figures (measurements, seams) and the shape error can all look
good while the pattern is not the design any more: a yoke squeezed to half
its height, a neckline pulled straight, a front that gave one side what it
took from the other. A fold-free grid and simple outlines do not see any of
that. These checks compare the graded pattern with proportional scaling
(the same design, only scaled per axis) and return one
:class:`~patternbridge.report.Finding` per problem; :func:`design_checks`
is run on the chosen solution by :func:`~.run.fit_pattern` and the findings
go into the fit report.

The functions on points are vectorised over the population, like the
objectives.
"""

from __future__ import annotations

import numpy as np

from ..report import Finding
from .objectives import ObjectiveData, balanced_links, link_shares, piece_axes_turn

__all__ = [
    "AXIS_TOL_DEG",
    "MAX_SHARE_MOVE",
    "MAX_SHEAR_DEG",
    "MAX_SYMMETRY_CM",
    "MAX_TURN_DEG",
    "MIN_CURVE_RATIO",
    "MIN_EXTENT_RATIO",
    "curve_depth",
    "curve_runs",
    "cut_line_turns",
    "design_checks",
    "piece_extents",
    "piece_turn",
    "share_move",
    "span_sagitta",
]

MIN_EXTENT_RATIO = 0.7
"""A piece narrower or shorter than this share of its proportional size (or wider or
longer than its inverse) has collapsed or ballooned."""

MIN_CURVE_RATIO = 0.5
"""A curve whose depth (sagitta over chord) falls below this share of the design's is flattened."""

MIN_CURVE_DEPTH = 0.04
"""Spans whose depth in the design is below this (sagitta / chord) count as straight."""

SMOOTH_DEG = 20.0
"""A critical point where the design's outline turns by less than this (a centre-back neck mark, an
armhole notch) lies inside one curve: the curve is judged whole as well as span by span."""

MAX_SYMMETRY_CM = 0.2
"""A symmetric piece further than this from its mirror image has lost its symmetry."""


MAX_TURN_DEG = 2.0
"""A piece whose longest edge (a fold, a centre line, a band's long edge) turned by more than this, in
degrees, has lost its grain: grading scales along and across the grain, it does not turn a piece."""

AXIS_TOL_DEG = 2.0
"""An edge within this of a drawing axis (the grain frame) is one whose direction grading keeps."""

MAX_SHEAR_DEG = 5.0
"""A piece whose best-fit linear map turns one drawing axis against the other by more than this, in
degrees, beyond proportional scaling's, has been sheared: a band slanted into a parallelogram."""

MAX_SHARE_MOVE = 0.03
"""A girth over several pieces whose share on one piece moved by more than this (3 cm of a 100 cm chest)
has changed the balance of the design: a front narrowed while the back widened."""


def piece_turn(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """Turn of every piece's grain against the design, ``(n_pop, P)`` rad (signed).

    Measured on the piece's longest edge within :data:`AXIS_TOL_DEG` of a
    drawing axis in the design (``data.points0``): a fold, a centre line, a
    straight hem, a band's long edge; the longest edge of any direction on a
    piece with none. Per-axis scaling keeps an axis-parallel edge's
    direction; a slanted edge turns as much as the piece's aspect ratio
    changes, so :func:`design_checks` compares with proportional scaling's
    turn.
    """
    points = np.asarray(points, dtype=np.float64)
    P = len(data.centre0)
    d0 = data.points0[data.nxt] - data.points0
    length0 = np.linalg.norm(d0, axis=1)
    slant = np.degrees(np.arctan2(np.abs(d0).min(axis=1), np.abs(d0).max(axis=1)))
    key = length0 + np.where(slant <= AXIS_TOL_DEG, length0.max() + 1.0, 0.0)  # axis-parallel edges first
    longest = np.array([np.flatnonzero(data.piece_of_point == p)[np.argmax(key[data.piece_of_point == p])]
                        for p in range(P)], dtype=np.int64)
    a0 = d0[longest]
    d = points[:, data.nxt[longest], :] - points[:, longest, :]
    return np.arctan2(a0[None, :, 0] * d[..., 1] - a0[None, :, 1] * d[..., 0],
                      a0[None, :, 0] * d[..., 0] + a0[None, :, 1] * d[..., 1])


def _edge_turn(d0: np.ndarray, d: np.ndarray) -> np.ndarray:
    return np.arctan2(d0[..., 0] * d[..., 1] - d0[..., 1] * d[..., 0], np.sum(d0 * d, axis=-1))


def _shear(a: np.ndarray, b: np.ndarray) -> float:
    """Angle (rad) between the images of the two drawing axes under the best-fit linear map ``a -> b``, minus 90°."""
    q0, q = a - a.mean(axis=0), b - b.mean(axis=0)
    m = (q.T @ q0) @ np.linalg.inv(q0.T @ q0 + 1e-12 * np.eye(2))
    return float(np.arctan2(m[1, 0], m[0, 0]) - np.arctan2(-m[0, 1], m[1, 1]))


def cut_line_turns(design, graded, reference) -> dict[str, tuple[float, float]]:
    """Turn and shear (rad) of every piece's **cut line** against proportional scaling.

    The turn of its longest axis-parallel edge, and its shear (the two
    drawing axes turned against each other under the best-fit linear map,
    as :func:`~.objectives.piece_axes_turn` measures the reference line).

    :func:`piece_turn` watches the reference line the grader moves; the cut
    line is rebuilt around it (the allowance carried, :func:`~.grid.deform_pattern`)
    and is what the cutter gets, so it is checked on its own. ``design``,
    ``graded``, ``reference``: the original pattern, the graded one and
    proportional scaling's (same pieces, same vertex counts). Pieces whose
    outline changed its vertex count are reported with ``(inf, inf)``.
    """
    out = {}
    for piece in design.pieces:
        a, b, r = piece.outline, graded.piece(piece.name).outline, reference.piece(piece.name).outline
        if not (a.shape == b.shape == r.shape):
            out[piece.name] = (float("inf"), float("inf"))
            continue
        d0 = np.roll(a, -1, axis=0) - a
        length = np.linalg.norm(d0, axis=1)
        slant = np.degrees(np.arctan2(np.abs(d0).min(axis=1), np.abs(d0).max(axis=1)))
        k = int(np.argmax(length + np.where(slant <= AXIS_TOL_DEG, length.max() + 1.0, 0.0)))
        db, dr = np.roll(b, -1, axis=0)[k] - b[k], np.roll(r, -1, axis=0)[k] - r[k]
        out[piece.name] = (float(_edge_turn(d0[k], db) - _edge_turn(d0[k], dr)), _shear(a, b) - _shear(a, r))
    return out


def share_move(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """Largest change of any piece's share of every link against the design, ``(n_pop, L)``.

    0 for links on a single piece and for links with a negative leg (a band
    length taken as a difference of edges: its parts are no shares).
    """
    points = np.asarray(points, dtype=np.float64)
    shares, _ = link_shares(data, points)
    shares0, _ = link_shares(data, data.points0[None])
    move = np.abs(shares - shares0).max(axis=1)
    return np.where(balanced_links(data)[None, :], move, 0.0)


def piece_extents(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """Width and height of every piece in the drawing axes, ``(n_pop, P, 2)`` cm."""
    points = np.asarray(points, dtype=np.float64)
    P = len(data.centre0)
    lo = np.full((points.shape[0], P, 2), np.inf)
    hi = np.full((points.shape[0], P, 2), -np.inf)
    np.minimum.at(lo.transpose(1, 0, 2), data.piece_of_point, points.transpose(1, 0, 2))
    np.maximum.at(hi.transpose(1, 0, 2), data.piece_of_point, points.transpose(1, 0, 2))
    return hi - lo


def span_sagitta(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """Depth of every span between consecutive critical points, ``(n_pop, B)``, sagitta / chord.

    The largest distance of the span's vertices from the chord joining its
    ends, over the chord's length: 0 for a straight span, about 0.2 for a
    neckline's quarter circle.
    """
    points = np.asarray(points, dtype=np.float64)
    a = points[:, data.span_a, :]
    b = points[:, data.span_b, :]
    chord = b - a
    length = np.maximum(np.linalg.norm(chord, axis=-1), 1e-9)
    # (n_pop, N, B) distance of every vertex from every chord, kept where the vertex is on the span
    rel = points[:, :, None, :] - a[:, None, :, :]
    dist = np.abs(rel[..., 0] * chord[:, None, :, 1] - rel[..., 1] * chord[:, None, :, 0]) / length[:, None, :]
    on_span = data.span_edges > 0
    return np.where(on_span[None], dist, 0.0).max(axis=1) / length


def curve_runs(data: ObjectiveData) -> tuple[np.ndarray, ...]:
    """The design's curves that run through smooth critical points: ordered global vertex indices of each.

    Consecutive spans of a piece (:func:`span_sagitta`) are joined where the
    critical point between them turns the design's outline by less than
    :data:`SMOOTH_DEG` (a yoke's neckline through its centre-back mark).
    Only runs of two spans or more are returned: the single spans are judged
    on their own.
    """
    turn = np.degrees(np.abs(np.pi - data.angle0))
    out = []
    for p in np.unique(data.span_piece):
        spans = np.flatnonzero(data.span_piece == p)  # in outline order, the last one closing the loop
        smooth = turn[data.span_b[spans]] < SMOOTH_DEG  # the span's end continues into the next span
        if smooth.all() or not smooth.any():
            continue
        start = (int(np.flatnonzero(~smooth)[-1]) + 1) % len(spans)
        run: list[int] = []
        for i in np.roll(np.arange(len(spans)), -start):
            run.append(int(spans[i]))
            if not smooth[i]:
                if len(run) > 1:
                    verts = [int(data.span_a[run[0]])]
                    while verts[-1] != int(data.span_b[run[-1]]):  # walk the outline to the run's end
                        verts.append(int(data.nxt[verts[-1]]))
                    out.append(np.array(verts, dtype=np.int64))
                run = []
    return tuple(out)


def curve_depth(points: np.ndarray, run: np.ndarray) -> np.ndarray:
    """Depth (sagitta over chord) of the curve through the vertices ``run``, ``(n_pop,)``."""
    pts = np.asarray(points, dtype=np.float64)[:, run, :]
    chord = pts[:, -1] - pts[:, 0]
    length = np.maximum(np.linalg.norm(chord, axis=-1), 1e-9)
    rel = pts - pts[:, :1]
    dist = np.abs(rel[..., 0] * chord[:, None, 1] - rel[..., 1] * chord[:, None, 0]) / length[:, None]
    return dist.max(axis=1) / length


def design_checks(
    data: ObjectiveData,
    points: np.ndarray,
    reference: np.ndarray,
    *,
    piece_names: tuple[str, ...],
    symmetry_cm: dict[str, float] | None = None,
    cut_turn: dict[str, tuple[float, float]] | None = None,
) -> tuple[Finding, ...]:
    """Findings for one graded solution against its proportional reference.

    Parameters
    ----------
    data : the grading problem
    points : (N, 2) graded reference-line vertices, cm
    reference : (N, 2) the same under proportional scaling (per-axis), cm
    piece_names : (P,) names in piece order
    symmetry_cm : symmetric piece name -> distance from its mirror image, cm
        (:func:`~.symmetry.symmetry_error`)
    cut_turn : piece name -> turn and shear of its cut line against
        proportional scaling's, rad (:func:`cut_line_turns`), or None

    Returns
    -------
    tuple of Finding with codes ``piece-collapsed``, ``piece-stretched``,
    ``piece-turned``, ``piece-sheared``, ``curve-flattened``, ``share-moved`` and
    ``symmetry-lost`` (all warnings)
    """
    pts = np.asarray(points, dtype=np.float64)[None]
    ref = np.asarray(reference, dtype=np.float64)[None]
    return (*_extent_findings(data, pts, ref, piece_names),
            *_turn_findings(data, pts, ref, piece_names, cut_turn or {}),
            *_curve_findings(data, pts, piece_names),
            *_share_findings(data, pts),
            *_symmetry_findings(symmetry_cm or {}))


def _extent_findings(data: ObjectiveData, pts: np.ndarray, ref: np.ndarray,
                     piece_names: tuple[str, ...]) -> list[Finding]:
    """``piece-collapsed`` / ``piece-stretched``: a width or height off its proportional one.

    ``pts``, ``ref`` : (1, N, 2) graded and proportional vertices, cm.
    """
    out: list[Finding] = []
    ratio = piece_extents(data, pts)[0] / np.maximum(piece_extents(data, ref)[0], 1e-9)
    for p, name in enumerate(piece_names):
        for axis, what in ((0, "width"), (1, "height")):
            r = float(ratio[p, axis])
            if r < MIN_EXTENT_RATIO:
                out.append(Finding(code="piece-collapsed", where=name, message=(
                    f"{what} is {r:.2f} of its proportional {what} (limit {MIN_EXTENT_RATIO})")))
            elif r > 1.0 / MIN_EXTENT_RATIO:
                out.append(Finding(code="piece-stretched", where=name, message=(
                    f"{what} is {r:.2f} of its proportional {what} (limit {1.0 / MIN_EXTENT_RATIO:.2f})")))
    return out


def _turn_findings(data: ObjectiveData, pts: np.ndarray, ref: np.ndarray, piece_names: tuple[str, ...],
                   cut_turn: dict[str, tuple[float, float]]) -> list[Finding]:
    """``piece-turned`` (longest edge, then cut line) and ``piece-sheared`` against proportional scaling.

    A cut line's turn is reported only for a piece whose reference line
    does not already tell (neither turned nor sheared).
    """
    out: list[Finding] = []
    turn = np.degrees(np.abs(piece_turn(data, pts)[0] - piece_turn(data, ref)[0]))
    for p in np.flatnonzero(turn > MAX_TURN_DEG):
        out.append(Finding(code="piece-turned", where=piece_names[p], message=(
            f"its longest edge turned {turn[p]:.1f}° against proportional scaling (limit {MAX_TURN_DEG:.0f}°): "
            "the grain is lost")))
    axes = piece_axes_turn(data, pts)[0] - piece_axes_turn(data, ref)[0]
    shear = np.degrees(np.abs(axes[:, 0] - axes[:, 1]))
    seen = (turn > MAX_TURN_DEG) | (shear > MAX_SHEAR_DEG)  # the reference line already tells
    for name, (edge, skew) in cut_turn.items():
        edge, skew = float(np.degrees(abs(edge))), float(np.degrees(abs(skew)))
        if name in piece_names and not seen[piece_names.index(name)] and (
                edge > MAX_TURN_DEG or skew > MAX_SHEAR_DEG):
            out.append(Finding(code="piece-turned", where=name, message=(
                f"its cut line turned {edge:.1f}° and sheared {skew:.1f}° against proportional scaling "
                f"(limits {MAX_TURN_DEG:.0f}° and {MAX_SHEAR_DEG:.0f}°): the cut line left its piece")))
    for p in np.flatnonzero(shear > MAX_SHEAR_DEG):
        out.append(Finding(code="piece-sheared", where=piece_names[p], message=(
            f"its drawing axes turned {shear[p]:.1f}° against each other beyond proportional scaling "
            f"(limit {MAX_SHEAR_DEG:.0f}°): slanted out of its design")))
    return out


def _curve_findings(data: ObjectiveData, pts: np.ndarray, piece_names: tuple[str, ...]) -> list[Finding]:
    """``curve-flattened``: a span between critical points, then a whole curve run, under
    :data:`MIN_CURVE_RATIO` of its design depth."""
    out: list[Finding] = []
    depth0 = span_sagitta(data, data.points0[None])[0]
    depth = span_sagitta(data, pts)[0]
    curved = depth0 >= MIN_CURVE_DEPTH
    for s in np.flatnonzero(curved & (depth < MIN_CURVE_RATIO * depth0)):
        p = int(data.span_piece[s])
        first = int(np.flatnonzero(data.piece_of_point == p)[0])
        out.append(Finding(code="curve-flattened", where=piece_names[p], message=(
            f"the curve between outline points {int(data.span_a[s]) - first} and {int(data.span_b[s]) - first} is "
            f"{depth[s] / depth0[s]:.2f} as deep as in the design (limit {MIN_CURVE_RATIO})")))
    for run in curve_runs(data):
        d0, d = float(curve_depth(data.points0[None], run)[0]), float(curve_depth(pts, run)[0])
        if d0 >= MIN_CURVE_DEPTH and d < MIN_CURVE_RATIO * d0:
            p = int(data.piece_of_point[run[0]])
            first = int(np.flatnonzero(data.piece_of_point == p)[0])
            out.append(Finding(code="curve-flattened", where=piece_names[p], message=(
                f"the curve from outline point {int(run[0]) - first} through {len(run) - 2} vertices to "
                f"{int(run[-1]) - first} is {d / d0:.2f} as deep as in the design, as a whole "
                f"(limit {MIN_CURVE_RATIO})")))
    return out


def _share_findings(data: ObjectiveData, pts: np.ndarray) -> list[Finding]:
    """``share-moved``: a piece's share of a link over several pieces moved beyond :data:`MAX_SHARE_MOVE`."""
    move = share_move(data, pts)[0]
    return [Finding(code="share-moved", where=data.link_ids[k], message=(
                f"a piece's share of it moved by {move[k]:.3f} (limit {MAX_SHARE_MOVE}): the pieces it spans "
                "no longer keep the design's balance"))
            for k in np.flatnonzero(move > MAX_SHARE_MOVE)]


def _symmetry_findings(symmetry_cm: dict[str, float]) -> list[Finding]:
    """``symmetry-lost``: a symmetric piece farther than :data:`MAX_SYMMETRY_CM` from its mirror image."""
    return [Finding(code="symmetry-lost", where=name, message=(
                f"{err * 10:.1f} mm from its mirror image (limit {MAX_SYMMETRY_CM * 10:.0f} mm)"))
            for name, err in symmetry_cm.items() if err > MAX_SYMMETRY_CM]
