"""Bands on the edges they close: a ring of cloth sewn onto a tube's open edge starts on that edge, outside it.

A band (a piece going round its body part and sewn to itself: a cuff, a
collar, a neckband) is wrapped on its own landmark, and the piece it is sewn
to on its own: nothing makes the two agree. A cuff anchored at the wrist
started half a turn round from the sleeve hem it closes (its closure
opposite the underarm seam it is sewn on) and 9 cm up the forearm inside the
sleeve; the seam graph, linear, then pulled the ring through itself and
through the sleeve (A_superhero's shirt: 52 of its 56 placed crossing
triangles). So each band that lies over the pieces it is sewn to (the seam
graph's layer order, :func:`~.seam_graph.layer_ranks`) and closes tubes
round its own proxy (a cuff on its sleeve, both round the arm) is moved
after the wrap as a rigid ring about the proxy's axis:

- turned about the axis so that its seam side faces its partners' edge
  (the circular mean of the angles between sewn pairs);
- moved along the axis onto their edge, which is gathered in toward the
  axis over :data:`GATHER_CM` to lie :data:`LAYER_CM` inside the band's
  seam side (the gathered cloth is sewn into the band's shorter edge), and
  the band widened when the edge still lies closer than that (the body
  holds it out).

The band's body then lies beyond the edge (its drawing puts it there: a
cuff below its top edge), not over the tube, and its seam side lies one
layer outside its partner's. A band sewn to pieces that are not tubes round
its own proxy (a collar or a neckband on the torso's neckline, a waistband
on a skirt's fronts and backs or on trouser legs) is not moved here: their
edge is no ring about the band's axis (the torso's cylinder has no top),
its landmark already puts it in phase with them (turns of 0-1.5° on A), and
the seam graph brings the neckline in; :mod:`.openings` tilts it to follow
that edge's slope.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..mesh2d import PatternMesh
from .seam_graph import SeamGraphSettings, layer_ranks
from .wrap import Cylinder

__all__ = ["GATHER_CM", "LAYER_CM", "band_partners", "bands_on_edges", "rings", "sewn_sides"]

GATHER_CM = 5.0  # length along the axis over which a tube's edge is gathered in to its band
LAYER_CM = SeamGraphSettings().layer_cm  # a band's seam side lies this far outside its partner's edge
CLEARANCE_CM = 1.0  # kept from the skin, as the wrap keeps it


def rings(pmesh: PatternMesh, around: set[str]) -> set[str]:
    """Instance keys of the rings: copies going round their body part (``around``) and sewn to themselves.

    (A dart is a seam of a piece to itself too; a front or a back with darts
    does not go round.)
    """
    return {sp.a.key for sp in pmesh.seams if sp.a.key == sp.b.key and sp.a.key in around}


def band_partners(pmesh: PatternMesh, around: set[str]) -> dict[str, list[tuple[np.ndarray, str, np.ndarray]]]:
    """Instance key of every band over its partners -> [(its seam vertices, partner key, partner's vertices)].

    A band is a ring (:func:`rings`) whose seams to other instances all go
    to instances under it in the layer order (more cloth).
    """
    keys = [inst.key for inst in pmesh.instances]
    sizes = np.array([len(pmesh.pieces[inst.piece].points) for inst in pmesh.instances])
    rank = dict(zip(keys, layer_ranks(sizes).tolist(), strict=True))
    out: dict[str, list] = {}
    for key in rings(pmesh, around):
        sides = sewn_sides(pmesh, key)
        if sides and all(rank[other] < rank[key] for _, other, _ in sides):
            out[key] = sides
    return out


def sewn_sides(pmesh: PatternMesh, key: str) -> list[tuple[np.ndarray, str, np.ndarray]]:
    """Every seam of instance ``key`` to another instance: [(its seam vertices, partner key, partner's vertices)]."""
    sides = []
    for sp in pmesh.seams:
        if sp.a.key == sp.b.key:
            continue
        if sp.a.key == key:
            sides.append((sp.a_vertices, sp.b.key, sp.b_vertices))
        elif sp.b.key == key:
            sides.append((sp.b_vertices, sp.a.key, sp.a_vertices))
    return sides


def bands_on_edges(
    pmesh: PatternMesh,
    placed: dict[str, np.ndarray],
    proxies: dict[str, Cylinder],
    same_proxy: dict[str, str],
    around: set[str],
    scene=None,
) -> dict[str, np.ndarray]:
    """``placed`` with every band on tubes round its own proxy moved onto their edge, outside it.

    Parameters
    ----------
    pmesh : the pattern mesh (seams, instances)
    placed : instance key -> (n, 3) wrapped positions, cm
    proxies : instance key -> the cylinder of the proxy it is wrapped on (its axis and frame)
    same_proxy : instance key -> a label of its proxy (body part)
    around : instance keys of the copies that go round their body part
        (placement side ``around``); a partner that is a ring (:func:`rings`)
        on the band's proxy is a tube round the same axis as the band
    scene : a :class:`~patternbridge.assemble.collision.BodyCollider` (the gathered
        edge and the band are kept :data:`CLEARANCE_CM` outside the skin), or None

    Returns
    -------
    instance key -> (n, 3) positions, cm (a new dict; the arrays of bands and
    their gathered partners are new)
    """
    out = dict(placed)
    tubes = rings(pmesh, around)
    for key, sides in band_partners(pmesh, around).items():
        if not all(other in tubes and same_proxy[other] == same_proxy[key] for _, other, _ in sides):
            continue
        band, ring, own, them = band_and_partners(out, proxies[key], key, sides)
        th_b, h_b, r_b = ring.coordinates(band)
        th_t, h_t, _ = ring.coordinates(them)
        th_b = th_b + float(np.angle(np.sum(np.exp(1j * (th_t - th_b[own])))))
        h_b = h_b + float(np.mean(h_t - h_b[own]))
        edge_r = _gather_edges(out, sides, ring, float(np.mean(r_b[own])), scene)
        r_b = r_b * max(1.0, (edge_r + LAYER_CM) / float(np.mean(r_b[own])))
        out[key] = ring.points(th_b, h_b, r_b)
    return out


def band_and_partners(
    placed: dict[str, np.ndarray], proxy: Cylinder, key: str, sides: list
) -> tuple[np.ndarray, Cylinder, np.ndarray, np.ndarray]:
    """The band ``key`` as placed, its proxy's axis moved through it, its sewn vertices and their partners' positions.

    ``sides`` is :func:`sewn_sides`' list for the band: (its vertices, partner key, partner vertices) per seam.
    """
    band = placed[key]
    ring = dataclasses.replace(proxy, center=band.mean(axis=0))
    own = np.concatenate([v for v, _, _ in sides])
    them = np.concatenate([placed[other][vo] for _, other, vo in sides])
    return band, ring, own, them


def _gather_edges(out: dict, sides: list, ring: Cylinder, band_r: float, scene) -> float:
    """Gather each partner's edge in to :data:`LAYER_CM` inside ``band_r`` (``out`` updated); the edges' mean radius.

    The partner's vertices within :data:`GATHER_CM` of its edge along the
    axis of ``ring`` (on its own side of the edge) are drawn toward the axis,
    fully at the edge and not at all :data:`GATHER_CM` from it; none is moved
    inside the skin's clearance (``scene.radial_clearance``: that edge then
    holds the band out).
    """
    radii = []
    for _, other, vo in sides:
        x = out[other]
        th, h, r = ring.coordinates(x)
        edge_h = float(np.mean(h[vo]))
        inward = 1.0 if np.mean(h) >= edge_h else -1.0
        s = np.clip((h - edge_h) * inward, 0.0, None)
        w = np.clip(1.0 - s / GATHER_CM, 0.0, 1.0)
        scale = min(1.0, (band_r - LAYER_CM) / max(float(np.mean(r[vo])), 1e-6))
        moving = w > 0
        r_new = r * (1.0 - w * (1.0 - scale))
        if scene is not None and moving.any():
            r_new[moving] = scene.radial_clearance(ring, th[moving], h[moving], r_new[moving], CLEARANCE_CM)
        x = x.copy()
        x[moving] = ring.points(th[moving], h[moving], r_new[moving])
        out[other] = x
        radii.append(r_new[vo])
    return float(np.mean(np.concatenate(radii)))
