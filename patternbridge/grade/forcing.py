"""Which measurements force a graded pattern's shape error above proportional scaling's.

Proportional scaling (each piece scaled along and across the grain) changes
few angles because it does not fit: it misses girths and lengths by
centimetres. A grading that meets every measurement and every seam can
change the design more than scaling does when the body asks for it (a
chest-to-waist drop deeper than the design's, on a shirt without darts, can
only be taken by turning the side seams at the waist). When the chosen
grading's shape error is above scaling's, :func:`shape_forcing` says which
measurement is to blame and where the excess sits, so the report names it
instead of passing a worse shape silently.

The evidence is a **release test**: the final step is run again from the
chosen grading with one measurement let go (:func:`released`: its target no
longer binds), for the measurements scaling misses most; the shape error it
then reaches, against scaling's, is what that measurement costs. A
first-order estimate (the constraints' shadow prices at the solution) was
tried first and ranked the library shirt's shoulder length first on
E_average_male, where letting it go changes nothing (0.0050 rad against
0.0052) while letting the chest or the waist go brings the shape error under
scaling's (0.0013 and 0.0015 against 0.0029 and 0.0027, whole fits): the
shape error is a mean of absolute angle changes and the fit moves far from
where a linear model holds.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from .grid import PatternGrid
from .objectives import ObjectiveData, _edge_lengths, angle_change, link_error, link_lengths, shape_error

__all__ = ["Forcing", "describe_forcing", "excess_points", "released", "scaling_miss", "shape_forcing"]

RELEASE_FLOOR_CM = -1e6
"""Target of a released link, taken as ``at_least``: any length meets it."""


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Forcing:
    """What holds a graded solution's shape error above proportional scaling's.

    shape, shape_ref : shape error of the graded solution and of scaling, rad
    link_ids : (n,) the links released, one at a time, then (when none of them alone is enough) the two
        that helped most together as ``"a+b"``; by the shape error reached, least first
    miss_cm : (n,) where scaling leaves each link against its target (achieved − target), cm; NaN for a pair
    shape_released : (n,) shape error of the final step from the graded solution with that link let go, rad
    points : critical points carrying the excess over scaling, ``(piece, mark or vertex, Δ°)``, largest first
    """

    shape: float
    shape_ref: float
    link_ids: tuple[str, ...]
    miss_cm: np.ndarray
    shape_released: np.ndarray
    points: tuple[tuple[str, str, float], ...]

    @property
    def forced_by(self) -> tuple[str, ...]:
        """The links (or pairs) whose release brings the shape error to scaling's or below."""
        return tuple(lid for lid, s in zip(self.link_ids, self.shape_released, strict=True) if s <= self.shape_ref)


def released(data: ObjectiveData, link: int | Sequence[int]) -> ObjectiveData:
    """``data`` with link ``link`` (or every link in it) let go: an ``at_least`` target every length meets.

    Its legs stay (the link's share terms and the level of its chords are
    geometry, not fit), only its target stops binding.
    """
    idx = np.atleast_1d(np.asarray(link, dtype=np.int64))
    target = data.target_cm.copy()
    target[idx] = RELEASE_FLOOR_CM
    at_least = data.at_least.copy()
    at_least[idx] = True
    return dataclasses.replace(data, target_cm=target, at_least=at_least)


def scaling_miss(grid: PatternGrid, data: ObjectiveData, x_ref: np.ndarray) -> np.ndarray:
    """(L,) ``achieved − target`` of every link under ``x_ref`` (0 for an exceeded ``at_least`` link), cm."""
    pts = grid.outlines(np.asarray(x_ref, dtype=np.float64)[None, :])
    return link_error(data, link_lengths(data, pts, _edge_lengths(data, pts))[0])


def _critical_weights(data: ObjectiveData) -> np.ndarray:
    """(K,) weight of every critical point in :func:`~.objectives.shape_error` (per-piece means, pieces alike)."""
    piece = data.piece_of_point[data.critical]
    counts = np.bincount(piece, minlength=len(data.centre0)).astype(np.float64)
    n_pieces = max(int((counts > 0).sum()), 1)
    return 1.0 / (n_pieces * counts[piece])


def excess_points(
    grid: PatternGrid, data: ObjectiveData, x: np.ndarray, x_ref: np.ndarray, n: int = 3
) -> tuple[tuple[str, str, float], ...]:
    """The ``n`` critical points that add most to the shape error of ``x`` beyond ``x_ref``'s.

    Returns ``(piece, mark name or "vertex i", |Δ inner angle| in degrees)``
    per point, by their weighted excess, largest first.
    """
    X = np.stack([np.asarray(x, dtype=np.float64), np.asarray(x_ref, dtype=np.float64)])
    d = np.abs(angle_change(data, grid.outlines(X)))[:, data.critical]
    excess = (d[0] - d[1]) * _critical_weights(data)
    out = []
    for j in np.argsort(-excess, kind="stable")[:n]:
        if excess[j] <= 0:
            break
        i = int(data.critical[j])
        k = int(data.piece_of_point[i])
        local = i - int(grid.point_offsets[k])
        piece = grid.pattern.pieces[k]
        names = sorted(name for name, v in piece.marks.items() if v == local)
        out.append((piece.name, names[0] if names else f"vertex {local}", float(np.degrees(d[0, j]))))
    return tuple(out)


def shape_forcing(
    grid: PatternGrid,
    data: ObjectiveData,
    x: np.ndarray,
    x_ref: np.ndarray,
    finish: Callable[[ObjectiveData, np.ndarray], np.ndarray],
    *,
    n_release: int = 2,
    band_cm: float = 0.15,
) -> Forcing:
    """Release test of the links that hold the shape error of ``x`` above that of ``x_ref``.

    Parameters
    ----------
    grid, data : the grading problem
    x : (n_var,) the graded solution
    x_ref : (n_var,) proportional scaling
    finish : ``finish(data, x_start) -> x``: the final step with the fit's settings
    n_release : how many links to release, one at a time: those scaling misses
        most (in cm) beyond ``band_cm``, the largest miss first, stopping at the
        first whose release brings the shape error to scaling's; when none is
        enough alone, the two that helped most are released together
    band_cm : the final step's measurement band; a link scaling meets within it forces nothing

    Returns
    -------
    Forcing
    """
    x = np.asarray(x, dtype=np.float64)
    x_ref = np.asarray(x_ref, dtype=np.float64)
    miss = scaling_miss(grid, data, x_ref)
    order = [int(i) for i in np.argsort(-np.abs(miss), kind="stable") if abs(miss[i]) > band_cm][:n_release]
    pts = grid.outlines(np.stack([x, x_ref]))
    shape, shape_ref = (float(v) for v in shape_error(data, pts))

    def shape_without(links: list[int]) -> float:
        x_i = finish(released(data, links), x)
        return float(shape_error(data, grid.outlines(x_i[None, :]))[0])

    tried: list[tuple[list[int], float]] = []
    for i in order:  # the largest miss first; stop at the first release that explains the excess
        tried.append(([i], shape_without([i])))
        if tried[-1][1] <= shape_ref:
            break
    if len(tried) >= 2 and min(s for _, s in tried) > shape_ref:
        # no single link: the two whose release helps most, together (a girth pair such as chest and waist)
        best = sorted(tried, key=lambda t: t[1])[:2]
        pair = best[0][0] + best[1][0]
        tried.append((pair, shape_without(pair)))
    tried.sort(key=lambda t: t[1])
    return Forcing(
        shape=shape,
        shape_ref=shape_ref,
        link_ids=tuple("+".join(data.link_ids[i] for i in links) for links, _ in tried),
        miss_cm=np.array([miss[links[0]] if len(links) == 1 else np.nan for links, _ in tried]),
        shape_released=np.array([value for _, value in tried], dtype=np.float64),
        points=excess_points(grid, data, x, x_ref),
    )


def describe_forcing(forcing: Forcing) -> str:
    """One line: the shape error against scaling's, what forces it, where the excess sits."""
    tried = ", ".join(
        f"{lid} (scaling misses it by {m:+.2f} cm; let go: {s:.4f})" if np.isfinite(m) else f"{lid} together: {s:.4f}"
        for lid, m, s in zip(forcing.link_ids, forcing.miss_cm, forcing.shape_released, strict=True)
    )
    forced = forcing.forced_by
    verdict = f"forced by {' or '.join(forced)}" if forced else "no release tried brings it to scaling's"
    where = ", ".join(f"{piece}:{name} turns {deg:.1f}°" for piece, name, deg in forcing.points)
    return (
        f"shape error {forcing.shape:.4f} rad against proportional scaling's {forcing.shape_ref:.4f}, "
        f"which misses the fit: {verdict} (released: {tried or 'none'}); "
        f"the excess is at {where or 'no critical point'}"
    )
