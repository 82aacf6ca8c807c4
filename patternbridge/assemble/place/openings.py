"""Bands on their openings: a collar, a neckband or a waistband tilted to follow the slope of the edge it closes.

A band round the torso or the neck (:data:`~.wrap.BAND_PARTS`: a ring sewn
to itself, wrapped once round on its own length) is wrapped level, at its
anchor landmark's height, about the body's cross-section there. The edge it
is sewn to need not be level: a neckline is 6-8 cm lower at the centre
front than at the back neck point (the neck's base slopes down to the
throat), a trouser waist a little lower in front. A collar wrapped level at
the back neck point stands with its front on the throat; sewing pulls the
fronts' neckline up to it rather than the ring down, and the drape leaves the
collar's front in the throat (the demo's shirt on E: 9.8 mm deep).

So each such band is turned rigidly (its lengths kept) about its anchor
vertex (which stays on its landmark) so that its seam side follows its
partners' edge: the heights of the partners' sewn vertices over the band's
own, as a function of the band's angle θ about its axis, are fitted by
least squares with a plane, ``c + a cos θ + b sin θ``; the band's axis
is leant by the angle whose sine is ``|(a, b)| / r`` (``r`` the radius of
the band's seam side: a ring of radius r turned by that angle drops ``|(a,
b)|`` on one side and rises as much on the other) toward the side where the
edge lies lower, at most :data:`MAX_TILT_DEG`. Points then inside the skin are
moved out along their radius from the leant axis where that axis runs inside
the body; the top of a collar leant over a nape can still start inside it
(A: 3.8 cm), and the seam graph's contact rounds push it out. The heights come from the
wrap: each partner hangs from its own landmark (a shirt's fronts from the
neck-shoulder points, its yoke from the back neck point), so the slope is
the pattern's own; a level edge (a skirt's waist) leaves the band as it was.
A front's neck edge hangs straight down on the torso's cylinder, steeper
than it lies over the chest, so the fit overstates a neckline's slope (the
library shirt's collars fit 54-64°; E's neckline slopes 35° between its
neck points): the limit, 30°, is what the shirts' collars are turned. At
45° their walls, leant as far, folded the top of the collar's closure.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..mesh2d import PatternMesh
from .bands import CLEARANCE_CM, band_and_partners, rings, sewn_sides
from .wrap import BAND_PARTS, Cylinder

__all__ = ["MAX_TILT_DEG", "bands_on_openings", "opening_slope", "tilted_about"]

MAX_TILT_DEG = 30.0  # a band's axis leans at most this far from its proxy's


def opening_slope(theta: np.ndarray, dh: np.ndarray) -> np.ndarray:
    """(2,) the first harmonic ``(a, b)`` of the heights ``dh`` (n,) over the angles ``theta`` (n,), rad.

    Least squares of ``dh ≈ c + a cos θ + b sin θ``: a plane cut through a
    cylinder; the edge lies lowest at the angle of ``-(a, b)``.
    """
    A = np.stack([np.ones(len(theta)), np.cos(theta), np.sin(theta)], axis=1)
    (_, a, b), *_ = np.linalg.lstsq(A, np.asarray(dh, dtype=np.float64), rcond=None)
    return np.array([a, b])


def _rotation(u: np.ndarray, n: np.ndarray) -> np.ndarray:
    """(3, 3) rotation taking the unit vector ``u`` to the unit vector ``n`` about their common normal."""
    k = np.cross(u, n)
    s, c = float(np.linalg.norm(k)), float(u @ n)
    if s < 1e-12:
        return np.eye(3)
    k = k / s
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + s * K + (1.0 - c) * (K @ K)


def tilted_about(
    band: np.ndarray, own: np.ndarray, them: np.ndarray, ring: Cylinder, pivot: np.ndarray
) -> tuple[np.ndarray, Cylinder]:
    """``band`` (n, 3) turned rigidly about ``pivot`` so that its seam side ``own`` follows the edge ``them``.

    Parameters
    ----------
    band : (n, 3) cm, a ring about the axis of ``ring``
    own : (k,) int, the band's sewn vertices ; them : (k, 3) cm, their partners
    ring : the band's cylinder (its axis and frame; the centre on the axis)
    pivot : (3,) cm, the point kept (the band's anchor vertex)

    Returns
    -------
    the turned positions (n, 3) cm, and ``ring`` turned with them
    """
    th_b, h_b, r_b = ring.coordinates(band)
    _, h_t, _ = ring.coordinates(them)
    g = opening_slope(th_b[own], h_t - h_b[own]) / max(float(np.mean(r_b[own])), 1e-6)
    sin_t = min(float(np.linalg.norm(g)), float(np.sin(np.radians(MAX_TILT_DEG))))
    if sin_t < 1e-6:
        return band, ring
    lean = -(g[0] * ring.e0 + g[1] * ring.e1) / float(np.linalg.norm(g))  # toward the edge's lowest side
    n = np.sqrt(1.0 - sin_t**2) * ring.axis + sin_t * lean
    rot = _rotation(ring.axis, n)
    turned = dataclasses.replace(
        ring, center=(ring.center - pivot) @ rot.T + pivot, axis=n, e0=rot @ ring.e0, e1=rot @ ring.e1
    )
    return (band - pivot) @ rot.T + pivot, turned


def bands_on_openings(
    pmesh: PatternMesh,
    placed: dict[str, np.ndarray],
    proxies: dict[str, Cylinder],
    same_proxy: dict[str, str],
    around: set[str],
    anchors: dict[str, int],
    scene=None,
) -> dict[str, np.ndarray]:
    """``placed`` with every band round the torso or the neck turned to follow the edge it is sewn to.

    Parameters
    ----------
    pmesh : the pattern mesh (seams, instances)
    placed : instance key -> (n, 3) wrapped positions, cm
    proxies : instance key -> the cylinder of the proxy it is wrapped on (its axis and frame)
    same_proxy : instance key -> its proxy's body part
    around : instance keys of the copies that go round their body part (placement side ``around``)
    anchors : instance key -> its anchor mark's vertex (on its landmark; kept where it is)
    scene : a :class:`~patternbridge.assemble.collision.BodyCollider` (the turned band is kept
        :data:`~.bands.CLEARANCE_CM` outside the skin along its radius), or None

    Returns
    -------
    instance key -> (n, 3) positions, cm (a new dict; the arrays of the turned bands are new)
    """
    out = dict(placed)
    for key in sorted(rings(pmesh, around)):
        sides = sewn_sides(pmesh, key)
        if same_proxy[key] not in BAND_PARTS or not sides or key not in anchors:
            continue
        band, ring, own, them = band_and_partners(out, proxies[key], key, sides)
        x, turned = tilted_about(band, own, them, ring, band[anchors[key]])
        if scene is not None and x is not band:
            th, h, r = turned.coordinates(x)
            x = turned.points(th, h, scene.radial_clearance(turned, th, h, r, CLEARANCE_CM))
        out[key] = x
    return out
