"""Assemble a garment on a character: place, sew, drape and write rigged-ready meshes.

The pipeline follows the source method (thesis, section 4.3): the body is
split into parts (:mod:`.bodyparts`), each part gets a bounding cylinder and
the triangulated pieces (:mod:`.mesh2d`) are wrapped onto it by their
placement hints (:mod:`.placement`); a cloth solver sews and drapes them
against the body (:mod:`.drape`, :mod:`.collision`). A rigged character is
dressed in a T-pose (upper arms raised, elbows straight) so that the arms are
clear of the torso, then the cloth is carried back to the rest pose by the skin
weights of the nearest body points and settled there. The result carries skin weights transferred from the nearest
body points (:mod:`.export_gltf` writes it).

Public entry points: :func:`assemble` returns a :class:`Garment`;
:func:`dress` also writes ``garment.glb``, ``garment.obj``/``.mtl`` and the
``fit_*.png`` pictures and returns the ``drape`` report.
"""

from __future__ import annotations

import itertools
import logging
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..mesh.character import Character, Skeleton
from ..pattern.model import Copy, Pattern
from ..report import Report

__all__ = ["Garment", "assemble", "dress"]

log = logging.getLogger(__name__)

Progress = Callable[[str, int, int], None] | None

POSE_STAGES = 1  # stages of the T-pose -> rest-pose return (more stages with gravity let sleeves slide up)
POSE_STEPS = 8  # cloth steps per stage


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Garment:
    """A draped garment in the character's rest pose.

    vertices : (N, 3) float64, cm — one vertex per pattern vertex of every cut
        copy; sewn vertices sit at exactly the same position (welded)
    faces : (F, 3) int64, outward (counter-clockwise seen from outside)
    uv : (N, 2) float64, cm — pattern coordinates of each vertex
    instance : (N,) int64 index into ``instance_names`` (``"front"``,
        ``"sleeve~mirror"`` for the mirrored copy of ``sleeve``...)
    weld : (N,) int64 — vertices sewn together share an id
    joints, weights : (N, 4) int64 / float64 — skin weights on ``skeleton``
        (-1 / 0 for unused slots), rows summing to 1; empty without a rig
    skeleton : the character's skeleton, or None
    report : the ``drape`` report (see :func:`dress`)
    findings : recoverable problems met on the way
    """

    vertices: np.ndarray
    faces: np.ndarray
    uv: np.ndarray
    instance: np.ndarray
    instance_names: tuple[str, ...]
    weld: np.ndarray
    joints: np.ndarray
    weights: np.ndarray
    skeleton: Skeleton | None
    report: dict = field(default_factory=dict)
    findings: Report = field(default_factory=Report)

    def welded(self) -> tuple[np.ndarray, np.ndarray]:
        """Welded mesh: (M, 3) vertices and (F, 3) faces over the weld ids."""
        ids, inv = np.unique(self.weld, return_inverse=True)
        v = np.zeros((len(ids), 3))
        v[inv] = self.vertices
        return v, inv[self.faces]


# --------------------------------------------------------------------------- checks
def _check_pattern(pattern: Pattern) -> None:
    missing = [p.name for p in pattern.pieces if p.placement is None]
    if missing:
        raise InputError(
            f"{pattern.style}: piece(s) {', '.join(missing)} have no placement hint (body part, side, anchor); "
            "add them to the pattern's bridge data (see docs/assembly.md) or use a library garment"
        )
    if not pattern.seams:
        raise InputError(
            f"{pattern.style}: the pattern has no seams, so its pieces cannot be sewn; add the seam table "
            "to the bridge data (see docs/assembly.md)"
        )


def _limbs_touching(vertices: np.ndarray, parts, report: Report, name: str) -> None:
    """Warn when arm or leg skin lies against the torso or the other leg away from the joints."""
    from scipy.spatial import cKDTree

    torso = vertices[parts.mask("torso")]
    if len(torso) == 0:
        return
    tree = cKDTree(torso)
    for side in ("left", "right"):
        arm = vertices[parts.mask(f"{side}_arm")]
        if len(arm) == 0:
            continue
        # the arm's half far from the shoulder should not touch the torso
        root = arm[np.argmin(tree.query(arm)[0])]
        far = arm[np.linalg.norm(arm - root, axis=1) > 12.0]
        d = tree.query(far)[0] if len(far) else np.array([np.inf])
        if np.min(d) < 0.5:
            report.add(
                "limbs-touching",
                f"the {side} arm touches the torso ({int(np.sum(d < 0.5))} vertices closer than 5 mm); "
                "dressed as best it can, expect cloth caught between them",
                where=name,
            )
    legs = [vertices[parts.mask(f"{s}_leg")] for s in ("left", "right")]
    if all(len(leg) for leg in legs):
        d = cKDTree(legs[0]).query(legs[1])[0]
        if np.min(d) < 0.3:
            report.add(
                "limbs-touching",
                f"the legs touch each other ({int(np.sum(d < 0.3))} vertices closer than 3 mm); dressed as best it can",
                where=name,
            )


# --------------------------------------------------------------------------- posing
def _pose_rotvecs(character: Character) -> dict[str, np.ndarray]:
    """Rotation vectors taking the rest pose to a T-pose with straight elbows."""
    from ..mesh.skinning import find_bone, rotation_between

    skel = character.skeleton
    out: dict[str, np.ndarray] = {}
    for side, sx in (("left", 1.0), ("right", -1.0)):
        ua = find_bone(skel, "upperarm", side)
        la = find_bone(skel, "lowerarm", side)
        wr = find_bone(skel, "wrist", side)
        target = np.array([sx, 0.0, 0.0])
        r_up = rotation_between(skel.heads[la] - skel.heads[ua], target)
        fore = r_up @ (skel.heads[wr] - skel.heads[la])
        r_fore = rotation_between(
            fore, target
        )  # in the world frame after the upper arm turned
        # the forearm rotation is given in the rest frame and carried by the upper arm's
        r_fore_rest = r_up.T @ r_fore @ r_up
        out[skel.names[ua]] = _rotvec(r_up)
        out[skel.names[la]] = _rotvec(r_fore_rest)
    return out


def _rotvec(r: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    return Rotation.from_matrix(r).as_rotvec()


def _rotations(rotvecs: dict[str, np.ndarray], s: float) -> dict[str, np.ndarray]:
    from scipy.spatial.transform import Rotation

    return {k: Rotation.from_rotvec(s * v).as_matrix() for k, v in rotvecs.items()}


def _blend(
    character: Character, rotations: dict, joints: np.ndarray, weights: np.ndarray
) -> np.ndarray:
    """(N, 3, 4) per-vertex blended bone transforms."""
    from ..mesh.skinning import bone_transforms

    g = bone_transforms(character.skeleton, rotations)[:, :3, :]
    w = np.where(joints >= 0, weights, 0.0)
    return np.einsum("vk,vkij->vij", w, g[np.maximum(joints, 0)])


def _apply(b: np.ndarray, x: np.ndarray) -> np.ndarray:
    return np.einsum("vij,vj->vi", b[:, :, :3], x) + b[:, :, 3]


def _unapply(b: np.ndarray, x: np.ndarray) -> np.ndarray:
    return np.einsum("vij,vj->vi", np.linalg.inv(b[:, :, :3]), x - b[:, :, 3])


def transfer_weights(
    collider, character: Character, points: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Skin weights at ``points`` from the nearest body surface points.

    The weights of the three corners of the closest body triangle are blended
    with the barycentric coordinates of the closest point; the four largest
    are kept and renormalised.

    Returns
    -------
    joints : (n, 4) int64 (-1 unused) ; weights : (n, 4) float64, rows sum to 1
    """
    _, _, _, tri, uv = collider.closest(points)
    corners = character.faces[tri]  # (n, 3)
    bary = np.stack([1.0 - uv[:, 0] - uv[:, 1], uv[:, 0], uv[:, 1]], axis=1)
    idx = character.skin.bone_indices[corners]  # (n, 3, K)
    w = np.where(idx >= 0, character.skin.weights[corners], 0.0) * bary[:, :, None]
    n, _, k = idx.shape
    idx = idx.reshape(n, 3 * k)
    w = w.reshape(n, 3 * k)
    # merge duplicate bones: sort by bone, sum runs
    order = np.argsort(idx, axis=1, kind="stable")
    idx = np.take_along_axis(idx, order, axis=1)
    w = np.take_along_axis(w, order, axis=1)
    start = np.ones_like(idx, dtype=bool)
    start[:, 1:] = idx[:, 1:] != idx[:, :-1]
    run = np.cumsum(start, axis=1) - 1
    summed = np.zeros_like(w)
    np.add.at(summed, (np.repeat(np.arange(n), 3 * k), run.ravel()), w.ravel())
    bones = np.full_like(idx, -1)
    bones[np.repeat(np.arange(n), 3 * k)[start.ravel()], run[start]] = idx[start]
    summed = np.where(bones >= 0, summed, 0.0)
    top = np.argsort(-summed, axis=1, kind="stable")[:, :4]
    joints = np.take_along_axis(bones, top, axis=1)
    weights = np.take_along_axis(summed, top, axis=1)
    weights = np.where(joints >= 0, weights, 0.0)
    total = weights.sum(axis=1, keepdims=True)
    bad = total[:, 0] <= 0
    weights = weights / np.where(total > 0, total, 1.0)
    if bad.any():  # no weight at all: bind to the root
        joints[bad] = -1
        joints[bad, 0] = 0
        weights[bad] = 0.0
        weights[bad, 0] = 1.0
    return joints.astype(np.int64), weights


def _thigh_fill(
    character: Character, body: np.ndarray, parts, pattern: Pattern
) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
    """A closed volume filling the space between the thighs, for tops that reach below the crotch.

    A shirt hangs straight down from the hips; without it the hem is drawn
    in between the legs like a bodysuit. The volume is the convex hull of
    the leg vertices from 2 cm above the crotch to 30 cm below it. Garments
    with pieces on the legs get none.
    """
    import trimesh

    if any("leg" in str(p.placement.body_part) for p in pattern.pieces):
        return ()
    legs = parts.mask("left_leg") | parts.mask("right_leg")
    if not legs.any():
        return ()
    lm = character.landmarks.get("crotch_point")
    crotch_y = (
        float(body[lm.vertex][1])
        if lm is not None and lm.vertex is not None
        else float(body[legs, 1].max())
    )
    band = body[legs & (body[:, 1] > crotch_y - 30.0) & (body[:, 1] < crotch_y + 2.0)]
    if len(band) < 10:
        return ()
    hull = trimesh.convex.convex_hull(band)
    return ((np.asarray(hull.vertices), np.asarray(hull.faces)),)


# --------------------------------------------------------------------------- main
def assemble(
    character: Character,
    pattern: Pattern,
    *,
    seed: int = 0,
    progress: Progress = None,
    max_edge_cm: float = 2.5,
    steps: int = 160,
) -> Garment:
    """Place, sew and drape ``pattern`` on ``character``.

    Parameters
    ----------
    character : the body (cm, +Y up, facing +Z), rigged or with landmarks
    pattern : pieces with placement hints and seams (bridge data)
    seed : seeds the tiny jitter that breaks the symmetry of the start
    progress : ``progress(stage, done, total)`` callback
    max_edge_cm : cloth triangle edge length, cm
    steps : time steps of the main drape

    Returns
    -------
    :class:`Garment` in the character's rest pose.

    Raises
    ------
    InputError
        A piece has no placement hint, the pattern has no seams, a seam names
        unknown marks, or the body lacks a part a piece goes on.
    """
    from .bodyparts import segment_body
    from .collision import BodyCollider
    from .drape import DrapeSettings, build_cloth, drape, seam_gaps, weld_groups
    from .mesh2d import mesh_pattern
    from .placement import (
        bounding_cylinders,
        instance_part,
        place_instances,
    )

    t0 = time.perf_counter()
    _check_pattern(pattern)
    findings = Report()
    rng = np.random.default_rng(seed)
    rigged = character.skeleton is not None and character.skin is not None
    on_legs = any("leg" in str(p.placement.body_part) for p in pattern.pieces)
    rotvecs: dict[str, np.ndarray] = {}
    if rigged and not on_legs:
        try:
            rotvecs = _pose_rotvecs(character)
        except InputError as exc:
            findings.add(
                "no-t-pose", f"dressed in the rest pose: {exc}", where=character.name
            )
    elif not rigged and not on_legs:
        findings.add(
            "no-t-pose",
            "the character has no rig: dressed in its rest pose",
            where=character.name,
        )
    if rotvecs:
        from ..mesh.skinning import pose_vertices

        body = pose_vertices(character, _rotations(rotvecs, 1.0))
    else:
        body = np.array(character.vertices)
    parts = segment_body(character, vertices=body)
    _limbs_touching(body, parts, findings, character.name)
    for f in findings:
        log.warning("%s", f)
    if progress:
        progress("mesh", 0, 1)
    pmesh = mesh_pattern(pattern, max_edge_cm=max_edge_cm)
    widths: dict[str, float] = {}
    for inst in pmesh.instances:
        p2 = pmesh.pieces[inst.piece].points
        part = instance_part(pattern, inst)
        widths[part] = widths.get(part, 0.0) + float(np.ptp(p2[:, 0])) + 1.0
    cylinders = bounding_cylinders(body, parts, widths)
    collider = BodyCollider(body, character.faces)
    proxies = _thigh_fill(character, body, parts, pattern)
    cloth_collider = (
        BodyCollider(body, character.faces, proxies=proxies) if proxies else collider
    )
    placed = place_instances(
        character, body, pattern, pmesh, cylinders, findings, scene=collider
    )
    keys = [inst.key for inst in pmesh.instances]
    index = {k: i for i, k in enumerate(keys)}
    positions = [placed[k] + rng.normal(scale=1e-3, size=placed[k].shape) for k in keys]
    points2d = [pmesh.pieces[inst.piece].points for inst in pmesh.instances]
    faces = [
        pmesh.pieces[inst.piece].faces[:, ::-1]
        if inst.copy is Copy.MIRROR
        else pmesh.pieces[inst.piece].faces
        for inst in pmesh.instances
    ]
    seams = [
        (index[s.a.key], index[s.b.key], s.a_vertices, s.b_vertices)
        for s in pmesh.seams
    ]
    settings = DrapeSettings()
    cloth = build_cloth(
        positions, points2d, faces, seams, density_kg_cm2=settings.density_kg_cm2
    )
    x_placed = cloth.x.copy()
    sew_steps = int(0.55 * steps)
    solver = drape(
        cloth,
        cloth_collider,
        steps=steps,
        sew_steps=sew_steps,
        settings=settings,
        progress=progress,
        stage="drape",
    )

    log.debug(
        "draped: cloth y %.1f..%.1f gap %.2f",
        cloth.x[:, 1].min(),
        cloth.x[:, 1].max(),
        seam_gaps(cloth.x, cloth.seams).max(),
    )
    if rotvecs:
        # back to the rest pose in POSE_STAGES stages: at each the cloth follows the
        # skin (weights of the nearest body points) from the previous pose to
        # the next, then settles against the body in that pose
        from ..mesh.skinning import pose_vertices

        levels = np.linspace(1.0, 0.0, POSE_STAGES + 1)
        for k, (s0, s1) in enumerate(itertools.pairwise(levels)):
            joints, weights = transfer_weights(collider, character, cloth.x)
            b0 = _blend(character, _rotations(rotvecs, s0), joints, weights)
            b1 = _blend(character, _rotations(rotvecs, s1), joints, weights)
            cloth.x = _apply(b1, _unapply(b0, cloth.x))
            cloth.v[:] = 0.0
            posed = (
                np.array(character.vertices)
                if s1 == 0.0
                else pose_vertices(character, _rotations(rotvecs, s1))
            )
            collider = BodyCollider(posed, character.faces)
            drape(
                cloth,
                BodyCollider(posed, character.faces, proxies=proxies)
                if proxies
                else collider,
                steps=POSE_STEPS,
                sew_steps=0,
                settings=settings,
                solver=solver,
                gravity_scale=0.0,
                stage="pose",
            )
            if progress:
                progress("pose", k + 1, POSE_STAGES)
    gaps_before = seam_gaps(cloth.x, cloth.seams)

    # weld the seams, then make sure nothing is left inside the skin
    weld = weld_groups(len(cloth.x), cloth.seams)
    ids, inv = np.unique(weld, return_inverse=True)
    cnt = np.bincount(inv, minlength=len(ids))[:, None]
    wx = np.zeros((len(ids), 3))
    np.add.at(wx, inv, cloth.x)
    wx /= cnt
    for _ in range(3):
        wx, moved = collider.push_out(wx, 0.5 * settings.offset_cm, robust=True)
        if not moved.any():
            break
    # no triangle may cut the skin either (a long edge over a thin limb)
    wx = collider.clear_triangles(wx, inv[cloth.faces], settings.offset_cm)
    wx, _ = collider.push_out(wx, 0.5 * settings.offset_cm, robust=True)
    x = wx[inv]
    inside = collider.inside(wx)
    seconds = time.perf_counter() - t0

    if rigged:
        joints, weights = transfer_weights(collider, character, x)
    else:
        joints = np.zeros((len(x), 0), np.int64)
        weights = np.zeros((len(x), 0))
    names = tuple(keys)
    # edges shorter than 1 mm in the pattern (a corner collapsed by grading)
    # would make any ratio meaningless: they are counted, not measured
    measured = cloth.rest >= 0.1
    if not measured.any():
        measured[:] = True
    ratio = np.linalg.norm(
        x[cloth.edges[measured, 0]] - x[cloth.edges[measured, 1]], axis=1
    ) / np.maximum(cloth.rest[measured], 1e-9)
    per = {}
    egroup = cloth.group[cloth.edges[measured, 0]]
    for i, n in enumerate(names):
        r = ratio[egroup == i]
        if len(r):
            per[n] = float(np.percentile(r, 95))
    worst = sorted(per.items(), key=lambda kv: -kv[1])[:3]
    report = {
        "penetrating_vertices": int(np.count_nonzero(inside)),
        "crossing_triangles": int(
            np.count_nonzero(collider.crossing_triangles(wx, inv[cloth.faces]))
        ),
        "max_seam_gap_mm": float(seam_gaps(x, cloth.seams).max(initial=0.0) * 10.0),
        "max_seam_gap_before_weld_mm": float(gaps_before.max(initial=0.0) * 10.0),
        "stretch": {
            "percentiles": {
                f"p{q}": float(np.percentile(ratio, q)) for q in (1, 5, 50, 95, 99)
            },
            "max": float(ratio.max()),
            "worst_pieces": [{"piece": n, "p95": v} for n, v in worst],
            "short_edges": int(np.count_nonzero(~measured)),
        },
        "seconds": round(seconds, 2),
        "vertices": len(ids),
        "triangles": len(cloth.faces),
        "pieces": list(names),
        "pose": "T-pose, then back to rest" if rotvecs else "rest",
        "max_placement_move_cm": float(np.linalg.norm(x - x_placed, axis=1).max()),
        "warnings": [str(f) for f in findings],
    }
    return Garment(
        vertices=x,
        faces=cloth.faces,
        uv=cloth.uv,
        instance=cloth.group,
        instance_names=names,
        weld=weld,
        joints=joints,
        weights=weights,
        skeleton=character.skeleton if rigged else None,
        report=report,
        findings=findings,
    )


def dress(
    character: Character,
    pattern: Pattern,
    out_dir: str | os.PathLike,
    *,
    seed: int = 0,
    progress: Progress = None,
    max_edge_cm: float = 2.5,
) -> dict:
    """Dress ``character`` in ``pattern`` and write the results to ``out_dir``.

    Writes (each atomically) ``garment.glb`` (skinned glTF 2.0, one primitive
    per cut piece, UVs from the pattern), ``garment.obj`` + ``garment.mtl``
    and ``fit_front.png``, ``fit_back.png``, ``fit_side.png``.

    Returns
    -------
    dict, the ``drape`` report: ``penetrating_vertices`` (garment vertices
    inside the skin), ``max_seam_gap_mm`` (after welding),
    ``max_seam_gap_before_weld_mm``, ``stretch`` (edge length / rest length:
    ``percentiles``, ``max``, ``worst_pieces``), ``seconds``, ``files``, and
    counts and warnings.

    Raises
    ------
    InputError
        See :func:`assemble`.
    """
    from .export_gltf import write_glb, write_obj
    from .pictures import write_pictures

    t0 = time.perf_counter()
    garment = assemble(
        character, pattern, seed=seed, progress=progress, max_edge_cm=max_edge_cm
    )
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_glb(out / "garment.glb", garment, character)
    write_obj(out / "garment.obj", garment)
    pics = write_pictures(out, garment, character)
    report = dict(garment.report)
    report["seconds"] = round(time.perf_counter() - t0, 2)
    report["files"] = [
        str(out / n) for n in ("garment.glb", "garment.obj", "garment.mtl", *pics)
    ]
    return report
