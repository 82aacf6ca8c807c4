"""Place a garment's cut copies on the body from its seam graph and the body's landmarks.

The steps, all driven by data only (placement hints, seams, landmarks):

1. :mod:`.wrap` lays every cut copy on its body part's proxy surface (a
   bounding cylinder; a ring round the hips above the crotch) with its anchor
   mark on its anchor landmark;
2. :mod:`.handedness` wears a piece cut in pairs on a limb (a sleeve) the way
   round its seams face their partners (its front cap on the front);
3. :mod:`.seam_graph` moves and bends all copies at once so that each seam's
   two sides meet, keeping every piece's wrapped shape, with the body as an
   obstacle;
4. :mod:`.bindings` lays each binding again along the edge the seam graph
   closed, as the cloth's continuation beyond it, and the seam graph settles
   it.

:func:`place_garment` chains them; ``benchmarks/placement.py`` measures the
seam gaps it leaves on every library garment and character.
"""

from __future__ import annotations

import numpy as np

from ...pattern.model import Pattern, Side
from ...report import Report
from ..bodyparts import BodyParts
from ..mesh2d import PatternMesh
from .bands import bands_on_edges
from .bindings import binding_keys, lay_bindings
from .handedness import choose_mirrored, paired_limb_pieces, sewn_turned, with_mirrored
from .openings import bands_on_openings
from .seam_graph import SeamGraphSettings, close_seam_graph, layer_ranks
from .wrap import LIMBS, Cylinder, bounding_cylinders, instance_part, landmark_position, mirror_name, place_instances

__all__ = [
    "Cylinder",
    "SeamGraphSettings",
    "bounding_cylinders",
    "close_seam_graph",
    "close_seams",
    "instance_part",
    "landmark_position",
    "layer_ranks",
    "mirror_name",
    "place_garment",
    "place_instances",
    "wrap_worn_side",
]


def close_seams(
    pmesh: PatternMesh,
    placed: dict[str, np.ndarray],
    scene=None,
    settings: SeamGraphSettings | None = None,
) -> dict[str, np.ndarray]:
    """The placed copies (instance key -> (n, 3) cm) moved and bent together along the seam graph.

    Every copy's layer comes from the cloth it holds (:func:`~.seam_graph.layer_ranks`).
    """
    keys = [inst.key for inst in pmesh.instances]
    sizes = [len(placed[k]) for k in keys]
    offsets = dict(zip(keys, np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(int).tolist(), strict=True))
    faces = np.concatenate([pmesh.pieces[inst.piece].faces + offsets[inst.key] for inst in pmesh.instances])
    pairs = np.concatenate(
        [np.stack([sp.a_vertices + offsets[sp.a.key], sp.b_vertices + offsets[sp.b.key]], axis=1) for sp in pmesh.seams]
        or [np.zeros((0, 2), np.int64)]
    )
    layers = np.repeat(layer_ranks(np.array(sizes)), sizes)
    x = close_seam_graph(
        np.concatenate([placed[k] for k in keys]),
        faces,
        pairs,
        scene=scene,
        settings=settings,
        layers=layers,
    )
    return {k: x[offsets[k] : offsets[k] + len(placed[k])] for k in keys}


def place_garment(
    character,
    vertices: np.ndarray,
    pattern: Pattern,
    pmesh: PatternMesh,
    parts: BodyParts,
    report: Report,
    *,
    scene=None,
) -> tuple[PatternMesh, dict[str, np.ndarray]]:
    """Every cut copy placed on the body: wrapped on its proxy the way round it is worn, then the seam graph closed.

    Parameters
    ----------
    character : the character (landmarks)
    vertices : (V, 3) float64, cm — the body in the dressing pose
    pattern, pmesh : the pattern and its mesh
    parts : body-part labels of ``vertices``
    report : findings (a missing anchor) are added here
    scene : a :class:`~patternbridge.assemble.collision.BodyCollider` of that body (the obstacle)

    Returns
    -------
    pmesh : ``pmesh`` with each piece worn mirrored replaced by its mirror image (:func:`wrap_worn_side`)
    positions : dict instance key -> (n, 3) float64 positions, cm

    Raises
    ------
    InputError
        A piece has no placement hint, or its body part has no vertices.
    """
    pmesh, wrapped = wrap_worn_side(character, vertices, pattern, pmesh, parts, report, scene=scene)
    closed = close_seams(pmesh, wrapped, scene)
    bindings = binding_keys(pattern, pmesh)
    if not bindings:
        return pmesh, closed
    # the bindings laid again along the edges the seam graph closed, then settled with the rest (.bindings)
    return pmesh, close_seams(pmesh, lay_bindings(pmesh, closed, bindings), scene)


def wrap_worn_side(
    character,
    vertices: np.ndarray,
    pattern: Pattern,
    pmesh: PatternMesh,
    parts: BodyParts,
    report: Report,
    *,
    scene=None,
) -> tuple[PatternMesh, dict[str, np.ndarray]]:
    """Every cut copy wrapped on its proxy; a piece cut in pairs on a limb the way round its seams face their
    partners (:mod:`.handedness`).

    Returns ``pmesh`` with each piece worn mirrored replaced by its mirror image, and the
    wrapped positions (instance key -> (n, 3) cm). A ``worn-mirrored`` finding
    names each such piece.
    """
    cylinders = bounding_cylinders(vertices, parts)  # (place_instances widens them to carry the pieces)
    part = {inst.key: instance_part(pattern, inst) for inst in pmesh.instances}
    proxies = {k: cylinders[p] for k, p in part.items()}
    around = {i.key for i in pmesh.instances if pattern.piece(i.piece).placement.side is Side.AROUND}
    candidates = paired_limb_pieces(pmesh, {k: p in LIMBS for k, p in part.items()})
    turned = sewn_turned(pmesh) - candidates  # a pair on the limbs is worn the way round its seams start closer
    for name in sorted(turned):
        report.add(
            "cut-other-side-up",
            "every seam to other pieces sews it on turned over (its sewn edges run the same way round as theirs): "
            "it is cut the other side up, its mirror image",
            where=name,
        )
    pmesh = with_mirrored(pmesh, turned)
    # a band turned to its opening's slope keeps its anchor; the bindings, laid again along their edges once the
    # seam graph has closed the pieces (``lay_bindings``), are left as wrapped
    laid_later = binding_keys(pattern, pmesh)
    anchors = {
        i.key: marks[pl.anchor_mark]
        for i in pmesh.instances
        if (pl := pattern.piece(i.piece).placement).anchor_mark in (marks := pmesh.pieces[i.piece].marks)
        and i.key not in laid_later
    }
    drawn = place_instances(character, vertices, pattern, pmesh, cylinders, report, scene=scene, parts=parts)
    if not candidates:
        wrapped = bands_on_edges(pmesh, drawn, proxies, part, around, scene)
        return pmesh, bands_on_openings(pmesh, wrapped, proxies, part, around, anchors, scene)
    flipped_mesh = with_mirrored(pmesh, candidates)
    flipped = place_instances(character, vertices, pattern, flipped_mesh, cylinders, Report(), scene=scene, parts=parts)
    chosen = choose_mirrored(pmesh, candidates, drawn, flipped, part)
    for name in sorted(chosen):
        report.add(
            "worn-mirrored",
            "wrapped as drawn on its limb, its seams to other pieces start on the far side of it: "
            "the drawing is worn on the mirrored side and its mirror image on the other",
            where=name,
        )
    pick = {inst.key: (flipped if inst.piece in chosen else drawn)[inst.key] for inst in pmesh.instances}
    worn = with_mirrored(pmesh, chosen)
    wrapped = bands_on_edges(worn, pick, proxies, part, around, scene)
    return worn, bands_on_openings(worn, wrapped, proxies, part, around, anchors, scene)
