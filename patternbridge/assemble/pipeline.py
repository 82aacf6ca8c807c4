"""The dressing pipeline: pose, place, sew, drape, return to the rest pose, weld, report, write.

:func:`prepare` builds the simulation (body in the dressing pose, colliders,
meshed pattern placed from its seam graph), :func:`simulate` sews and
drapes it and brings it back to the rest pose, :func:`finish` welds the seams,
clears the skin and measures; :func:`assemble` chains the three and
:func:`dress` also writes the files.
"""

from __future__ import annotations

import logging
import os
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from ..mesh.character import Character
from ..pattern.model import BodyPart, Copy, Pattern, Side
from ..report import Report
from .drape_report import DrapeReport, SeamGap, Stretch
from .garment import Garment
from .phases import Phase
from .pose import DRESS_ARM_DROP_DEG
from .strategy import ARMS, LEGS, Strategy, choose_strategy
from .verdict import Measured, VerdictLimits, edge_limits, judge, limits_for

if TYPE_CHECKING:
    from .bodyparts import BodyParts
    from .cloth import ClothSolver
    from .collision import BodyCollider
    from .drape import Cloth, DrapeSettings
    from .mesh2d import PatternMesh
    from .place.length import LengthStretch

__all__ = [
    "Simulation",
    "assemble",
    "clear_skin",
    "dress",
    "finish",
    "limb_end_seams",
    "prepare",
    "sewing_inertia",
    "simulate",
    "with_anchor_landmarks",
]

log = logging.getLogger(__name__)

Progress = Callable[[str, int, int], None] | None


@dataclass(eq=False)
class Simulation:
    """Everything the sewing and draping work on (mutable: the cloth moves, the colliders follow the pose).

    body : (V, 3) float64, cm — the body in the dressing pose
    rotvecs : bone -> rotation vector of the dressing pose (empty: dressed in the rest pose)
    proxies : helper volumes that do not move with the arms (the space between the thighs)
    hands : (V,) bool masks of the hands (their mitts follow the pose)
    seam_ids : (S,) int64 index into ``pmesh.seams`` of every sewn pair
    x_placed : (N, 3) float64, cm — the cloth as placed
    stretches : instance key -> how the copy was placed stretched to its hem's landmark (those stretched only)
    """

    character: Character
    pattern: Pattern
    strategy: Strategy
    phases: tuple[Phase, ...]
    body: np.ndarray
    parts: BodyParts
    rotvecs: dict[str, np.ndarray]
    pmesh: PatternMesh
    cloth: Cloth
    collider: BodyCollider
    cloth_collider: BodyCollider
    proxies: tuple[tuple[np.ndarray, np.ndarray], ...]
    hands: list[np.ndarray]
    names: tuple[str, ...]
    seam_ids: np.ndarray
    x_placed: np.ndarray
    settings: DrapeSettings
    stretches: Mapping[str, LengthStretch] = field(default_factory=dict)
    findings: Report = field(default_factory=Report)
    solver: ClothSolver | None = None
    t0: float = 0.0

    @property
    def posed(self) -> bool:
        """Whether the body starts in the dressing pose (arms raised)."""
        return bool(self.rotvecs)


def prepare(
    character: Character,
    pattern: Pattern,
    *,
    seed: int = 0,
    max_edge_cm: float = 2.5,
    steps: int = 160,
    progress: Progress = None,
) -> Simulation:
    """Choose the strategy, pose the body, mesh the pattern and place its pieces from the seam graph.

    Raises
    ------
    InputError
        See :func:`assemble`.
    """
    from .bodyparts import crotch_height, hand_masks, segment_body
    from .checks import check_pattern, limbs_touching
    from .collision import BodyCollider, hand_mitts, thigh_fill
    from .drape import DrapeSettings, build_cloth
    from .mesh2d import mesh_pattern
    from .phases import plan_phases
    from .place import bounding_cylinders, place_garment
    from .place.length import length_stretches, worn_lengths

    t0 = time.perf_counter()
    check_pattern(pattern)
    findings = Report()
    rng = np.random.default_rng(seed)
    strategy = choose_strategy(pattern)
    rotvecs = _dressing_pose(character, strategy, findings)
    if rotvecs:
        from ..mesh.skinning import pose_vertices
        from .pose import rotations

        body = pose_vertices(character, rotations(rotvecs, 1.0))
    else:
        body = np.array(character.vertices, dtype=np.float64)
    parts = segment_body(character, vertices=body)
    limbs_touching(body, parts, findings, character.name)
    for f in findings:
        log.warning("%s", f)
    if progress:
        progress("mesh", 0, 1)
    pmesh = mesh_pattern(pattern, max_edge_cm=max_edge_cm)
    collider = BodyCollider(body, character.faces)
    proxies: tuple = ()
    hands: list = []
    if strategy.fill_between_thighs:
        legs = parts.mask(BodyPart.LEFT_LEG) | parts.mask(BodyPart.RIGHT_LEG)
        proxies = thigh_fill(body, legs, crotch_height(character, body, parts))
    if rotvecs:
        hands = hand_masks(character, body, parts)
    helpers = proxies + hand_mitts(body, hands)
    cloth_collider = BodyCollider(body, character.faces, proxies=helpers) if helpers else collider
    pmesh, placed = place_garment(character, body, pattern, pmesh, parts, findings, scene=collider)
    stretches = length_stretches(character, body, pattern, pmesh, bounding_cylinders(body, parts))
    keys = [inst.key for inst in pmesh.instances]
    index = {k: i for i, k in enumerate(keys)}
    positions = [placed[k] + rng.normal(scale=1e-3, size=placed[k].shape) for k in keys]
    points2d = [pmesh.pieces[inst.piece].points for inst in pmesh.instances]
    faces = [
        pmesh.pieces[inst.piece].faces[:, ::-1] if inst.copy is Copy.MIRROR else pmesh.pieces[inst.piece].faces
        for inst in pmesh.instances
    ]
    seams = [(index[s.a.key], index[s.b.key], s.a_vertices, s.b_vertices) for s in pmesh.seams]
    settings = DrapeSettings()
    cloth = build_cloth(positions, points2d, faces, seams, density_kg_cm2=settings.density_kg_cm2)
    stretches = {k: v for k, v in stretches.items() if v.stretched}
    for key, ls in stretches.items():  # worn pulled down to the landmark (see place.length)
        mine = np.flatnonzero((cloth.group[cloth.edges] == index[key]).all(axis=1))
        cloth.target[mine] = worn_lengths(ls, cloth.uv, cloth.edges[mine], cloth.target[mine])
    # seam of every sewn pair (build_cloth drops the pairs of a vertex with itself, the tip of a dart)
    offsets = np.concatenate([[0], np.cumsum([len(p) for p in positions])])
    seam_ids = np.concatenate(
        [
            np.full(int(np.count_nonzero(a + offsets[ia] != b + offsets[ib])), i)
            for i, (ia, ib, a, b) in enumerate(seams)
        ]
        or [np.zeros(0, np.int64)]
    )
    return Simulation(
        character=character,
        pattern=pattern,
        strategy=strategy,
        phases=plan_phases(strategy, posed=bool(rotvecs), steps=steps),
        body=body,
        parts=parts,
        rotvecs=rotvecs,
        pmesh=pmesh,
        cloth=cloth,
        collider=collider,
        cloth_collider=cloth_collider,
        proxies=proxies,
        hands=hands,
        names=tuple(keys),
        seam_ids=seam_ids.astype(np.int64),
        x_placed=cloth.x.copy(),
        stretches=stretches,
        findings=findings,
        settings=settings,
        t0=t0,
    )


def _dressing_pose(character: Character, strategy: Strategy, findings: Report) -> dict[str, np.ndarray]:
    """Bone -> rotation vector of the dressing pose the strategy asks for (empty: the rest pose)."""
    if not strategy.raise_arms:
        return {}
    if character.skeleton is None or character.skin is None:
        findings.add("no-dressing-pose", "the character has no rig: dressed in its rest pose", where=character.name)
        return {}
    from .pose import dressing_rotvecs

    try:
        return dressing_rotvecs(character)
    except InputError as exc:
        findings.add("no-dressing-pose", f"dressed in the rest pose: {exc}", where=character.name)
        return {}


def simulate(sim: Simulation, *, progress: Progress = None) -> None:
    """Run the simulation's phases in order: sew, then settle or carry the cloth back to the rest pose (in place).

    The phases were planned once from the strategy (:func:`~patternbridge.assemble.phases.plan_phases`):
    trousers sew in the rest pose and settle; tops sew in the dressing pose
    (arms raised, no gravity, the cuffs left open) and drape while the arms
    come down over keyframes, the cloth following the skin from one to the
    next, the way cloth tools put a garment on an A-posed body.
    """
    from .drape import seam_gaps
    from .phases import run_phases

    run_phases(sim, sim.phases, progress)
    log.debug(
        "draped: cloth y %.1f..%.1f gap %.2f",
        sim.cloth.x[:, 1].min(),
        sim.cloth.x[:, 1].max(),
        seam_gaps(sim.cloth.x, sim.cloth.seams).max(initial=0.0),
    )


def sewing_inertia(sim: Simulation, arms: float) -> np.ndarray:
    """(N,) mass multiples while a top is sewn in the dressing pose: ``arms`` on the arm pieces, 1 elsewhere.

    The sleeve caps are placed at the shoulder points, the bodice on the
    torso's cylinder: the armhole seams start 9-23 cm open (12-30 cm when
    the cylinder was as wide as the body's widest part, where this was
    measured). With equal masses closing them
    dragged the sleeves 10-13 cm up the raised arms (C's sleeve hem), and
    left them shortened and stretched across the top (edge stretch 1.9);
    that stretch then drew the hems up the forearms while the arms came
    down. Nothing falls while sewing (no gravity), so the mass only decides
    which side of a seam moves: with heavy sleeves the bodice comes to them.
    """
    from .place import instance_part

    on_arm = [i for i, inst in enumerate(sim.pmesh.instances) if instance_part(sim.pattern, inst) in ARMS]
    return np.where(np.isin(sim.cloth.group, on_arm), float(arms), 1.0)


def _pose_name() -> str:
    lowered = f"arms {DRESS_ARM_DROP_DEG:g} degrees below horizontal" if DRESS_ARM_DROP_DEG else "T-pose"
    return f"{lowered}, then back to rest"


def limb_end_seams(pattern: Pattern, pmesh) -> np.ndarray:
    """(len(pmesh.seams),) bool: the seams between two pieces of one arm (a cuff on its sleeve).

    With the arms raised a sleeve cap is sewn into the armhole by pulling
    the sleeve toward the body (its underarm lies farther out along the arm
    than the armpit), while a cuff closed round the wrist is caught there
    between the hand and the thicker forearm: sewn at the same time, the
    sleeve tore open above the cuff (E, in the T-pose). These seams are left
    open in the dressing pose and close while the arms come down.
    """
    from .place import instance_part

    out = np.zeros(len(pmesh.seams), dtype=bool)
    for i, sp in enumerate(pmesh.seams):
        part = instance_part(pattern, sp.a)
        out[i] = sp.a.key != sp.b.key and part in ARMS and instance_part(pattern, sp.b) == part
    return out


SMOOTH_ROUNDS = 6  # neighbour averaging rounds of the skinning transforms carrying the cloth back to rest


def smooth_over_cloth(cloth, values: np.ndarray, rounds: int = SMOOTH_ROUNDS) -> np.ndarray:
    """Average per-vertex ``values`` (N, ...) with their cloth neighbours (edges and seam pairs), ``rounds`` times.

    The skin weights of the nearest body points change sharply where the
    skin does (an inner elbow between the upper arm and the forearm); two
    cloth neighbours taking the transforms of different bones would be torn
    apart (a 2.3 cm edge became 15 cm). Smoothed transforms move the cloth
    as a whole; linear blend skinning is linear in the weights, so this is
    smoothing the weights.
    """
    from scipy.sparse import coo_matrix, diags

    n = len(cloth.x)
    pairs = np.concatenate([cloth.edges, cloth.seams])
    a = coo_matrix((np.ones(2 * len(pairs)), (pairs.ravel(), pairs[:, ::-1].ravel())), shape=(n, n)).tocsr()
    a = a + diags(np.ones(n))
    a = diags(1.0 / np.asarray(a.sum(axis=1)).ravel()) @ a
    flat = values.reshape(n, -1)
    for _ in range(rounds):
        flat = a @ flat
    return flat.reshape(values.shape)


ANCHOR_WEIGHT = 2.0  # pin strength while sewing, in units of the vertex's mass / h²
ANCHOR_FREE_CM = (6.0, 18.0)  # pattern distance from an open seam: free below, fully pinned above


def anchor_weights(sim: Simulation) -> np.ndarray:
    """(N,) soft-pin weights: vertices far (in the pattern) from seams that start open are held while sewing.

    Called for the strategies that pin (:attr:`Strategy.pin_far_from_open_seams`).

    Seams whose pairs start more than 1 cm apart must move cloth; the
    vertices near them are free, the others are held on their placed
    positions so that closing a seam does not turn a whole tube round its
    limb. The weight ramps over :data:`ANCHOR_FREE_CM`.
    """
    from scipy.spatial import cKDTree

    from .drape import seam_gaps

    cloth = sim.cloth
    n = len(cloth.x)
    gaps = seam_gaps(cloth.x, cloth.seams)
    open_pairs = cloth.seams[gaps > 1.0]
    open_v = np.zeros(n, dtype=bool)
    open_v[open_pairs.ravel()] = True
    dist = np.full(n, np.inf)
    for g in np.unique(cloth.group):
        mine = cloth.group == g
        src = np.flatnonzero(mine & open_v)
        if len(src) == 0:
            continue
        d, _ = cKDTree(cloth.uv[src]).query(cloth.uv[mine])
        dist[mine] = d
    lo, hi = ANCHOR_FREE_CM
    return ANCHOR_WEIGHT * np.clip((dist - lo) / (hi - lo), 0.0, 1.0)


HEM_HOLD_WEIGHT = 5.0  # how firmly a hem stretched to its landmark is held there, in units of the vertex's mass / h²


def hem_hold_weights(sim: Simulation) -> np.ndarray:
    """(N,) weights holding the hem of every copy placed stretched to its landmark where it was placed.

    A knit drafted short of its landmark (leggings) is worn pulled down to
    it (:mod:`.place.length`): the placement lays it stretched, its springs
    rest at that worn length (:func:`~.place.length.worn_lengths`), and the
    hem is held there while the seams close and the cloth settles, as the
    wearer's hand holds it (5 × mass / h², as a waistband: 30 gave E's
    leggings a hem 0.6 cm lower).
    """
    from .place.length import hem_vertices
    from .place.wrap import instance_points2d

    w = np.zeros(len(sim.cloth.x))
    offsets = np.searchsorted(sim.cloth.group, np.arange(len(sim.pmesh.instances)))
    for i, inst in enumerate(sim.pmesh.instances):
        ls = sim.stretches.get(inst.key)
        if ls is None:
            continue
        hem = hem_vertices(ls, instance_points2d(sim.pmesh, inst), sim.pmesh.pieces[inst.piece].n_boundary)
        w[offsets[i] + hem] = HEM_HOLD_WEIGHT
    return w


HOLD_SHARE = 1.0  # share of the sewing pins kept on leg pieces (at their sewn positions) while gravity acts
HOLD_WEIGHT = 5.0  # how firmly a waistband stays where it was sewn, in units of the vertex's mass / h²


def hold_weights(sim: Simulation, pins: np.ndarray) -> np.ndarray | None:
    """(N,) weights holding the cloth where the sewing left them while gravity acts, or None (nothing held).

    A band going round the torso of a garment with pieces on the legs is
    worn buttoned at the waist: with the ease the grading gives it, the
    simulated band would otherwise slide down to the hips and the legs
    would pile up on the feet. The leg pieces keep their sewing pins
    (:func:`anchor_weights`), now on the sewn positions: released, the
    stress left by closing the crotch turns the leg tubes round the legs
    and reopens the side seams across the shin.
    """
    from .place import instance_part

    w = np.zeros(len(sim.cloth.x))
    for i, inst in enumerate(sim.pmesh.instances):
        pl = sim.pattern.piece(inst.piece).placement
        part = instance_part(sim.pattern, inst)
        mine = sim.cloth.group == i
        if part is BodyPart.TORSO and pl.side is Side.AROUND:
            w[mine] = HOLD_WEIGHT
        elif part in LEGS:
            w[mine] = HOLD_SHARE * pins[mine]
    return w if w.any() else None


def seam_gap_table(sim: Simulation) -> list[dict]:
    """Per seam: the largest gap between its sewn pairs now (mm) and where it is (pair index, height cm)."""
    from .drape import seam_gaps

    g = seam_gaps(sim.cloth.x, sim.cloth.seams)
    out = []
    for i, sp in enumerate(sim.pmesh.seams):
        sel = np.flatnonzero(sim.seam_ids[: len(g)] == i) if len(sim.seam_ids) == len(g) else np.zeros(0, int)
        if len(sel) == 0:
            continue
        j = sel[np.argmax(g[sel])]
        a, b = sim.cloth.seams[j]
        out.append(
            {
                "seam": sp.seam,
                "max_mm": float(g[j] * 10.0),
                "median_mm": float(np.median(g[sel]) * 10.0),
                "at": (int(a), int(b)),
                "position_cm": [round(float(v), 1) for v in 0.5 * (sim.cloth.x[a] + sim.cloth.x[b])],
            }
        )
    return out


WELDED_OPEN_MM = 5.0  # a seam the simulation left wider than this is listed in the report


def finish(sim: Simulation, limits: VerdictLimits | None = None) -> Garment:
    """Weld the seams, clear the skin, transfer skin weights, measure and judge (the ``drape`` report).

    Parameters
    ----------
    sim : the sewn and draped simulation, in the rest pose
    limits : the verdict's limits (:class:`~patternbridge.assemble.verdict.VerdictLimits`;
        default: those of the pattern's fabric, :func:`~patternbridge.assemble.verdict.limits_for`)
    """
    from .drape import seam_gaps, weld_groups
    from .weights import transfer_weights

    cloth, collider, settings, character = sim.cloth, sim.collider, sim.settings, sim.character
    gaps_before = seam_gaps(cloth.x, cloth.seams)
    table = seam_gap_table(sim) if len(gaps_before) else []

    # weld the seams, then make sure nothing is left inside the skin
    weld = weld_groups(len(cloth.x), cloth.seams)
    ids, inv = np.unique(weld, return_inverse=True)
    wf = inv[cloth.faces]  # the triangles on the welded vertices
    cnt = np.bincount(inv, minlength=len(ids))[:, None]
    wx = np.zeros((len(ids), 3))
    np.add.at(wx, inv, cloth.x)
    wx /= cnt
    wx = clear_skin(collider, wx, wf, settings.offset_cm)
    inside = collider.inside(wx)
    x = wx[inv]

    rigged = character.skeleton is not None and character.skin is not None
    if rigged:
        joints, weights = transfer_weights(collider, character, x)
    else:
        joints = np.zeros((len(x), 0), np.int64)
        weights = np.zeros((len(x), 0))
    report, flagged = _measure(sim, table, x, wx, wf, inside, limits or limits_for(sim.pattern.fabric_class))
    return Garment(
        vertices=x,
        faces=cloth.faces,
        uv=cloth.uv,
        instance=cloth.group,
        instance_names=sim.names,
        weld=weld,
        joints=joints,
        weights=weights,
        skeleton=character.skeleton if rigged else None,
        report=report,
        flagged=flagged,
        findings=sim.findings,
    )


def clear_skin(collider, wx: np.ndarray, wf: np.ndarray, offset_cm: float) -> np.ndarray:
    """The welded cloth ``wx`` moved out of the skin (vertices, then triangles, then skin tips).

    Every push carries the cloth layers over the pushed vertices along
    (:func:`~patternbridge.assemble.collision.carry_layers`): a fold lying on
    the skin is lifted as a whole instead of its inner layer pushed through
    the outer one.
    """
    gap = 0.5 * offset_cm

    def carried(y: np.ndarray) -> np.ndarray:
        nonlocal wx
        wx = _keep_layers(collider, wx, y, wf, gap)
        return wx

    for _ in range(3):
        y, moved = collider.push_out(wx, 0.5 * offset_cm, robust=True)
        carried(y)
        if not moved.any():
            break
    # no triangle may cut the skin either (a long edge over a thin limb)
    carried(collider.clear_triangles(wx, wf, offset_cm))
    carried(collider.push_out(wx, 0.5 * offset_cm, robust=True)[0])
    inside = collider.inside(wx)
    if inside.any():  # caught where two body parts touch: out the shortest straight way
        y = wx.copy()
        y[inside] = collider.escape(wx[inside], 0.5 * offset_cm)
        carried(y)
    # pushing single vertices out can leave an edge between them grazing the
    # skin where two body parts meet (an armpit): clear the triangles again
    carried(collider.clear_triangles(wx, wf, 0.5 * offset_cm))
    # and no tip of the skin may poke through a triangle between its corners
    return carried(collider.lift_over_skin(wx, wf, offset_cm))


def _keep_layers(collider, x: np.ndarray, y: np.ndarray, wf: np.ndarray, gap_cm: float) -> np.ndarray:
    """The clean-up move of the welded cloth from ``x`` to ``y``, kept from passing the cloth through itself.

    The layers over each moved vertex are carried along
    (:func:`~patternbridge.assemble.collision.carry_layers`); the corners of
    triangles that then cross the cloth and did not before go back where
    they were (up to 3 rounds), unless that leaves them inside the body; the
    round with the fewest crossing triangles is kept. The skin comes first:
    triangles through it that the move had cleared get their corners' moves
    back.
    """
    from .collision import carry_layers
    from .selfcross import self_crossing

    was = self_crossing(x, wf)
    z0 = carry_layers(x, y, wf, gap_cm, body=collider)
    z, best = z0.copy(), z0
    crossed = self_crossing(z, wf)
    fewest = np.count_nonzero(crossed)
    for _ in range(3):
        back = np.unique(wf[crossed & ~was])
        back = back[np.any(z[back] != x[back], axis=1)]
        back = back[~collider.inside(x[back])]
        if len(back) == 0:
            break
        z[back] = x[back]
        crossed = self_crossing(z, wf)
        if np.count_nonzero(crossed) < fewest:
            best, fewest = z.copy(), np.count_nonzero(crossed)
    z = best.copy()
    allowed = int(np.count_nonzero(_crossing(collider, y, wf)))
    for ref in (z0, y):  # through the skin: the carried move back, else the plain one
        skin = _crossing(collider, z, wf)
        if np.count_nonzero(skin) <= allowed:
            break
        corners = np.unique(wf[skin])
        z[corners] = ref[corners]
    return z if np.count_nonzero(_crossing(collider, z, wf)) <= allowed else y


def _measure(
    sim: Simulation,
    table: list[dict],
    x: np.ndarray,
    wx: np.ndarray,
    wf: np.ndarray,
    inside: np.ndarray,
    limits: VerdictLimits,
) -> tuple[DrapeReport, np.ndarray]:
    """The drape report of the finished garment and the (F,) faces to mark red in the pictures."""
    from .defects import (
        anchor_levels_cm,
        edge_stretch,
        faces_touching,
        girth_strain,
        grain_directions,
        hem_rise_cm,
        seam_excess_cm,
    )
    from .drape import seam_gaps, weld_groups
    from .selfcross import self_crossing
    from .skin_check import skin_check
    from .turned import turned_cloth

    cloth, names = sim.cloth, sim.names
    face_piece = cloth.group[cloth.faces[:, 0]]
    crossing = _crossing(sim.collider, wx, wf)
    folded = self_crossing(wx, wf)  # the whole garment: a piece through another piece counts too
    folded_pieces, folded_counts = np.unique(face_piece[folded], return_counts=True)
    body = np.asarray(sim.character.vertices, dtype=np.float64)
    skin = skin_check(body, sim.character.faces, wx, wf)
    skin_bad = skin.inside(0.1 * limits.skin_depth_flawed_mm)
    ratio, measured = edge_stretch(x, cloth.edges, cloth.rest)
    egroup = cloth.group[cloth.edges[measured, 0]]
    grain = grain_directions(sim.pattern, sim.pmesh)
    fabrics = tuple(
        sim.pattern.piece(inst.piece).fabric_class or sim.pattern.fabric_class for inst in sim.pmesh.instances
    )
    e = cloth.edges[measured]
    worn_limit, torn_limit = edge_limits(limits, fabrics, egroup, grain, cloth.uv[e[:, 1]] - cloth.uv[e[:, 0]])
    beyond, torn = ratio > worn_limit, ratio > torn_limit
    per = {n: float(np.percentile(ratio[egroup == i], 95)) for i, n in enumerate(names) if np.any(egroup == i)}
    over = {names[g]: int(c) for g, c in zip(*np.unique(egroup[beyond], return_counts=True), strict=True)}
    gaps = {r["seam"]: r["max_mm"] for r in table}
    levels = anchor_levels_cm(sim.character, body, sim.pattern, sim.pmesh, x, cloth.group)
    rises = {
        k: max(0.0, r) for k, r in hem_rise_cm(sim.pattern, sim.pmesh, x, cloth.group, grain, sim.stretches).items()
    }
    heights, girths, girth_faces = girth_strain(
        x, cloth.uv, cloth.faces, weld_groups(len(x), cloth.seams), skin_offset_cm=sim.settings.offset_cm
    )
    tight = int(np.argmax(girths)) if len(girths) else -1
    turned = turned_cloth(x, cloth.faces, weld_groups(len(x), cloth.seams), body, sim.character.faces)
    turned_cm2 = _turned_by_piece(turned.patch, turned.area_cm2, face_piece, names)
    measured_defects = Measured(
        seam_gaps_mm=gaps,
        seam_excess_cm=seam_excess_cm(sim.pattern, sim.pmesh),
        self_crossing={names[g]: int(c) for g, c in zip(folded_pieces, folded_counts, strict=True)},
        skin_depth_mm=float(10.0 * skin.depth_cm.max(initial=0.0)),
        skin_share=float(np.mean(skin_bad)) if len(skin_bad) else 0.0,
        skin_pieces=tuple(sorted({names[g] for g in face_piece[skin_bad]})),
        stretch_share=float(np.mean(beyond)) if len(ratio) else 0.0,
        torn_share=float(np.mean(torn)) if len(ratio) else 0.0,
        stretch_pieces=tuple(sorted(over, key=lambda k: -over[k])),
        levels_cm=levels,
        hem_rise_cm=rises,
        girth_strain=float(girths[tight]) if tight >= 0 else 1.0,
        girth_height_cm=float(heights[tight]) if tight >= 0 else 0.0,
        girth_pieces=tuple(sorted({names[g] for g in face_piece[girth_faces[tight]]})) if tight >= 0 else (),
        turned_cm2=turned_cm2,
    )
    verdict, reasons = judge(measured_defects, limits)
    by_gap = sorted((SeamGap(seam=s, max_mm=g) for s, g in gaps.items()), key=lambda g: -g.max_mm)
    report = DrapeReport(
        verdict=verdict,
        reasons=reasons,
        penetrating_vertices=int(np.count_nonzero(inside)),
        crossing_triangles=int(np.count_nonzero(crossing)),
        crossing_pieces=tuple(sorted({names[g] for g in face_piece[crossing]})),
        skin_depth_mm=measured_defects.skin_depth_mm,
        skin_triangles=int(np.count_nonzero(skin_bad)),
        self_crossing_triangles=int(np.count_nonzero(folded)),
        self_crossing_pieces=measured_defects.self_crossing,
        max_seam_gap_mm=float(seam_gaps(x, cloth.seams).max(initial=0.0) * 10.0),
        max_seam_gap_before_weld_mm=by_gap[0].max_mm if by_gap else 0.0,
        worst_seam_before_weld=by_gap[0].seam if by_gap else "",
        seam_gaps_before_weld=tuple(by_gap),
        seams_open_before_weld=tuple(g for g in by_gap if g.max_mm > WELDED_OPEN_MM),
        levels_cm=levels,
        hem_rise_cm=rises,
        girth_strain=measured_defects.girth_strain,
        girth_height_cm=measured_defects.girth_height_cm,
        turned_cm2=turned_cm2,
        stretch=Stretch(
            percentiles={f"p{q}": float(np.percentile(ratio, q)) for q in (1, 5, 50, 95, 99)},
            max=float(ratio.max()),
            worst_pieces=tuple(sorted(per.items(), key=lambda kv: -kv[1])[:3]),
            beyond_limit_share=measured_defects.stretch_share,
            short_edges=int(np.count_nonzero(~measured)),
        ),
        seconds=round(time.perf_counter() - sim.t0, 2),
        vertices=len(wx),
        triangles=len(cloth.faces),
        pieces=names,
        pose=_pose_name() if sim.posed else "rest",
        max_placement_move_cm=float(np.linalg.norm(x - sim.x_placed, axis=1).max()),
        unchecked=tuple(
            f"level of {inst.key}: no landmark {sim.pattern.piece(inst.piece).placement.anchor!r} "
            "(or its mirror) on the character"
            for inst in sim.pmesh.instances
            if inst.key not in levels
        ),
        warnings=tuple(str(f) for f in sim.findings),
        limits=limits,
        fabric_why=sim.pattern.fabric_why,
        piece_fabrics={
            p.name: p.fabric_class for p in sim.pattern.pieces if p.fabric_class not in (None, limits.fabric)
        },
    )
    # the pictures mark in red what the verdict names: open seams, the cloth
    # through itself or the skin, cloth stretched beyond tearing, cloth turned over
    g = seam_gaps(cloth.x, cloth.seams) if len(cloth.seams) else np.zeros(0)
    open_pairs = cloth.seams[g * 10.0 > limits.seam_gap_flawed_mm]
    flagged = (
        folded
        | crossing
        | skin_bad
        | faces_touching(cloth.faces, open_pairs, len(cloth.x))
        | faces_touching(cloth.faces, e[torn], len(cloth.x))
        | turned.faces(limits.turned_flawed_cm2)
    )
    if measured_defects.girth_strain > limits.girth_failed:
        flagged |= girth_faces[tight]  # the girth the garment does not close round
    return report, flagged


def _turned_by_piece(
    patch: np.ndarray, area_cm2: np.ndarray, face_piece: np.ndarray, names: tuple[str, ...]
) -> dict[str, float]:
    """Piece -> area of the largest patch of turned-over cloth it holds most of, cm² (pieces with none left out)."""
    out: dict[str, float] = {}
    for p in np.argsort(-area_cm2):
        owner = names[int(np.bincount(face_piece[patch == p]).argmax())]
        out.setdefault(owner, float(area_cm2[p]))
    return out


def _crossing(collider, x: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(F,) bool: garment triangles crossing the skin either way (an edge through the body, the skin through them)."""
    crossing = collider.crossing_triangles(x, faces)
    crossing[collider.skin_through(x, faces)[0]] = True
    return crossing


def with_anchor_landmarks(character: Character, pattern: Pattern) -> tuple[Character, list[str]]:
    """``character`` with the landmarks the pieces hang from completed as the measuring completes them.

    A character without a sidecar (a glTF from another tool, a bare OBJ)
    is measured with landmarks found from its rig or its geometry
    (:func:`~patternbridge.mesh.landmarks.resolve_landmarks`); placed
    without them, every piece fell back to the middle of its body part and
    a pair of trousers went round one leg. Returns the character and the
    names of the landmarks added (none when every anchor is present).
    """
    anchors = {p.placement.anchor for p in pattern.pieces if p.placement is not None}
    if anchors <= set(character.landmarks):
        return character, []
    from ..mesh.landmarks import resolve_landmarks

    marks = resolve_landmarks(character, detect=True)
    added = sorted(set(marks) - set(character.landmarks))
    return (replace(character, landmarks=marks), added) if added else (character, [])


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
    :class:`~patternbridge.assemble.garment.Garment` in the character's rest pose.

    Raises
    ------
    InputError
        A piece has no placement hint, the pattern has no seams, a seam names
        unknown marks, or the body lacks a part a piece goes on.
    """
    character, found = with_anchor_landmarks(character, pattern)
    posing = character
    if (character.skeleton is None or character.skin is None) and choose_strategy(pattern).raise_arms:
        from .landmark_rig import landmark_rig

        posing = landmark_rig(character) or character
    sim = prepare(posing, pattern, seed=seed, max_edge_cm=max_edge_cm, steps=steps, progress=progress)
    if posing is not character:
        sim.findings.add(
            "landmark-rig",
            "the character has no rig: posed for dressing by an arm rig built from its shoulder, armpit, "
            "elbow and wrist landmarks; the garment carries no skin weights",
            where=character.name,
        )
        log.warning("%s", sim.findings.findings[-1])
    if found:
        sim.findings.add(
            "landmarks-detected",
            f"the character lacks landmarks the pieces hang from; {len(found)} found from its rig or "
            f"geometry as the measuring finds them ({', '.join(found[:4])}{', ...' if len(found) > 4 else ''})",
            where=character.name,
        )
        log.warning("%s", sim.findings.findings[-1])
    simulate(sim, progress=progress)
    garment = finish(sim)
    if posing is not character:  # the rig was for posing only: nothing to bind the garment to
        n = len(garment.vertices)
        garment = replace(garment, joints=np.zeros((n, 0), np.int64), weights=np.zeros((n, 0)), skeleton=None)
    return garment


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
    per cut piece, UVs from the pattern), ``garment.obj`` + ``garment.mtl``,
    ``garment.usda`` (the body and the garment, skinned with UsdSkel)
    and ``fit_front.png``, ``fit_back.png``, ``fit_side.png``.

    Returns
    -------
    dict, the ``drape`` report (:meth:`DrapeReport.to_dict
    <patternbridge.assemble.drape_report.DrapeReport.to_dict>`): ``verdict``
    (``"ok"``, ``"flawed"`` or ``"failed"``) and ``verdict_reasons`` (one
    dict per check beyond its limit: ``check``, ``verdict``, ``value``,
    ``limit``, ``unit``, ``where``, ``message``), the measures they judge,
    ``seconds`` and ``files``. The files are written whatever the verdict.

    Raises
    ------
    InputError
        See :func:`assemble`.
    """
    from .export_gltf import write_glb
    from .export_obj import write_obj
    from .export_usd import write_usd
    from .pictures import write_pictures

    t0 = time.perf_counter()
    garment = assemble(character, pattern, seed=seed, progress=progress, max_edge_cm=max_edge_cm)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_glb(out / "garment.glb", garment, character)
    write_obj(out / "garment.obj", garment)
    write_usd(out / "garment.usda", garment, character)
    pics = write_pictures(out, garment, character)
    report = replace(
        garment.report,
        seconds=round(time.perf_counter() - t0, 2),
        files=tuple(str(out / n) for n in ("garment.glb", "garment.obj", "garment.mtl", "garment.usda", *pics)),
    )
    return report.to_dict()
