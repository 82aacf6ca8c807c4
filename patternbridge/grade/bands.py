"""Bands and strips: long narrow pieces whose short dimension no measurement governs.

A placket, a collar stand, a binding or a waistband is graded along its
length (a neckline, a front opening, a waist fixes it) but its width is the
design's: no measurement link runs across it. In the final step nothing
but the weak smoothing terms would hold that width, so the pieces sewn to
it drag it wider or narrower. :func:`band_axes` finds such pieces from the
pattern's own geometry (the extent across the drawing axes and the
direction of the link legs on the piece, never a name), and
:func:`band_widths` measures their short dimension; the final step holds
it at the sample's (:class:`~.step_terms.StepTerms`, ``w_band``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .objectives import ObjectiveData

__all__ = ["BAND_ASPECT", "Bands", "band_axes", "band_widths", "outline_width", "strip_width"]

BAND_ASPECT = 0.25
"""A piece at most this share as wide as it is long (a rectangle's width over its length) is a band."""


@dataclass(frozen=True, slots=True)
class Bands:
    """The band pieces of a grading problem.

    pieces : (B,) piece indices ; width0 : (B,) each band's mean width in
    the sample (:func:`band_widths`), cm
    """

    pieces: np.ndarray
    width0: np.ndarray


def _area_perimeter(data: ObjectiveData, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Area and perimeter of every piece's outline, each ``(n_pop, P)``."""
    P = len(data.centre0)
    q = points[:, data.nxt, :]
    cross = points[..., 0] * q[..., 1] - points[..., 1] * q[..., 0]
    seg = np.linalg.norm(q - points, axis=-1)
    area = np.zeros((points.shape[0], P))
    per = np.zeros((points.shape[0], P))
    np.add.at(area.T, data.piece_of_point, cross.T)
    np.add.at(per.T, data.piece_of_point, seg.T)
    return 0.5 * np.abs(area), per


def band_axes(data: ObjectiveData, *, aspect: float = BAND_ASPECT) -> Bands:
    """The long narrow pieces whose short dimension no measurement link governs.

    A piece is a band when it is as slender as a rectangle at most
    ``aspect`` as wide as long: its area over its half-perimeter squared
    (``L·w / (L + w)²`` for a rectangle) at most ``aspect / (1 + aspect)²``;
    a curved strip (a collar stand) counts by its own width, not by the
    box around its curve. A link governs its width when its legs on the
    piece (outline edges, and chords, half to the piece of each end) are
    together no longer than twice that width: they run across it (a
    cuff's height in an arm length); such a piece is graded by its
    measurement, not held. A link along the band (a collar stand's length in a neckline)
    leaves its width free.
    """
    p0 = data.points0
    P = len(data.centre0)
    area, per = (a[0] for a in _area_perimeter(data, p0[None]))
    narrow = area / np.maximum(0.5 * per, 1e-9) ** 2 <= aspect / (1.0 + aspect) ** 2
    width = strip_width(area, per)
    # the length of every link's legs on every piece (drawn, whatever the factor: a half piece
    # cut twice counts its legs double): a link measures across a band when its
    # legs there are no longer than twice the band's width (a cuff's height in an arm length)
    seg = np.linalg.norm(p0[data.nxt] - p0, axis=1)
    on_piece = np.zeros((P, data.link_edges.shape[1]))
    np.add.at(on_piece, data.piece_of_point, (data.link_edges != 0) * seg[:, None])
    if len(data.chord_a):  # a chord counts on the pieces of both its ends
        chord = np.linalg.norm(p0[data.chord_b] - p0[data.chord_a], axis=1)[:, None] * (data.link_chords != 0)
        np.add.at(on_piece, data.piece_of_point[data.chord_a], 0.5 * chord)
        np.add.at(on_piece, data.piece_of_point[data.chord_b], 0.5 * chord)
    governed = np.any((on_piece > 0) & (on_piece <= 2.0 * width[:, None]), axis=1)
    pieces = np.flatnonzero(narrow & ~governed).astype(np.int64)
    return Bands(pieces=pieces, width0=width[pieces])


def band_widths(data: ObjectiveData, bands: Bands, points: np.ndarray) -> np.ndarray:
    """Width of every band, ``(n_pop, B)`` cm: :func:`strip_width` of its area and perimeter."""
    area, per = _area_perimeter(data, np.asarray(points, dtype=np.float64))
    return strip_width(area[:, bands.pieces], per[:, bands.pieces])


def outline_width(outline: np.ndarray) -> np.ndarray:
    """Width ``(n_pop,)`` cm of one closed outline ``(n_pop, n, 2)``: :func:`strip_width` of its area and perimeter."""
    q = np.roll(outline, -1, axis=1)
    area = 0.5 * np.abs((outline[..., 0] * q[..., 1] - outline[..., 1] * q[..., 0]).sum(axis=1))
    return strip_width(area, np.linalg.norm(q - outline, axis=-1).sum(axis=1))


def strip_width(area: np.ndarray, perimeter: np.ndarray) -> np.ndarray:
    """The width ``w`` of the rectangle ``L × w`` with the given area and perimeter.

    ``L·w = A`` and ``L + w = P/2``: ``w = (P/2 − sqrt((P/2)² − 4A)) / 2``.
    Exact for a rectangle, smooth in the vertices, and blind to a band's
    curve (a collar stand bent along a neckline keeps its area and
    perimeter), unlike the box around it.
    """
    s = 0.5 * perimeter
    return 0.5 * (s - np.sqrt(np.maximum(s * s - 4.0 * area, 0.0)))
