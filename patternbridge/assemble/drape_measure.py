"""The finished drape measured and judged: skin and self crossings, edge stretch, girths, levels, the report.

:func:`measure_drape` takes the welded, cleaned garment of a
:class:`~patternbridge.assemble.pipeline.Simulation` and returns its
:class:`~patternbridge.assemble.drape_report.DrapeReport` (measures, verdict
and the reasons for it) and the faces the pictures mark in red.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .drape_report import DrapeReport, SeamGap, Stretch
from .pose import DRESS_ARM_DROP_DEG
from .verdict import Measured, VerdictLimits, edge_limits, judge

if TYPE_CHECKING:
    from .pipeline import SeamGapRow, Simulation
    from .turned import TurnedCloth

__all__ = ["WELDED_OPEN_MM", "measure_drape", "skin_crossing"]

WELDED_OPEN_MM = 5.0  # a seam the simulation left wider than this is listed in the report


def _pose_name() -> str:
    lowered = f"arms {DRESS_ARM_DROP_DEG:g} degrees below horizontal" if DRESS_ARM_DROP_DEG else "T-pose"
    return f"{lowered}, then back to rest"


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _Surface:
    """Where the welded garment passes through the skin and through itself.

    face_piece : (F,) int64 — instance of every face
    crossing : (F,) bool — faces crossing the skin either way
    folded : (F,) bool — faces passing through the cloth (any piece)
    skin_depth_mm : deepest garment point inside the skin
    skin_bad : (F,) bool — faces with a point inside deeper than the flawed limit
    """

    face_piece: np.ndarray
    crossing: np.ndarray
    folded: np.ndarray
    skin_depth_mm: float
    skin_bad: np.ndarray


def _surface(sim: Simulation, wx: np.ndarray, wf: np.ndarray, limits: VerdictLimits) -> _Surface:
    """The skin and self-crossing checks of the welded garment ``wx``, ``wf``."""
    from .selfcross import self_crossing
    from .skin_check import skin_check

    body = np.asarray(sim.character.vertices, dtype=np.float64)
    skin = skin_check(body, sim.character.faces, wx, wf)
    return _Surface(
        face_piece=sim.cloth.group[sim.cloth.faces[:, 0]],
        crossing=skin_crossing(sim.collider, wx, wf),
        folded=self_crossing(wx, wf),  # the whole garment: a piece through another piece counts too
        skin_depth_mm=float(10.0 * skin.depth_cm.max(initial=0.0)),
        skin_bad=skin.inside(0.1 * limits.skin_depth_flawed_mm),
    )


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _EdgeStrain:
    """The stretch of the garment's measured edges against its fabrics' limits.

    ratio : (E',) float64 — length / pattern length of the measured edges
    measured : (E,) bool — the edges measured (see :func:`~.defects.edge_stretch`)
    edges : (E', 2) int64 — the measured edges ; group : (E',) int64 — their instance
    beyond, torn : (E',) bool — beyond the worn and the tearing limit
    """

    ratio: np.ndarray
    measured: np.ndarray
    edges: np.ndarray
    group: np.ndarray
    beyond: np.ndarray
    torn: np.ndarray


def _edge_strain(sim: Simulation, x: np.ndarray, grain: np.ndarray, limits: VerdictLimits) -> _EdgeStrain:
    """The stretch of the edges of the cloth ``x`` and which pass the limits of their piece's fabric and grain."""
    from .defects import edge_stretch

    cloth = sim.cloth
    ratio, measured = edge_stretch(x, cloth.edges, cloth.rest)
    egroup = cloth.group[cloth.edges[measured, 0]]
    fabrics = tuple(
        sim.pattern.piece(inst.piece).fabric_class or sim.pattern.fabric_class for inst in sim.pmesh.instances
    )
    e = cloth.edges[measured]
    worn_limit, torn_limit = edge_limits(limits, fabrics, egroup, grain, cloth.uv[e[:, 1]] - cloth.uv[e[:, 0]])
    return _EdgeStrain(
        ratio=ratio, measured=measured, edges=e, group=egroup, beyond=ratio > worn_limit, torn=ratio > torn_limit
    )


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _Girth:
    """The garment's tightest girth: its strain, height and (F,) bool faces (None when the garment has none)."""

    strain: float
    height_cm: float
    faces: np.ndarray | None


def _tightest_girth(sim: Simulation, x: np.ndarray) -> _Girth:
    from .defects import girth_strain
    from .drape import weld_groups

    cloth = sim.cloth
    heights, girths, girth_faces = girth_strain(
        x, cloth.uv, cloth.faces, weld_groups(len(x), cloth.seams), skin_offset_cm=sim.settings.offset_cm
    )
    if not len(girths):
        return _Girth(strain=1.0, height_cm=0.0, faces=None)
    tight = int(np.argmax(girths))
    return _Girth(strain=float(girths[tight]), height_cm=float(heights[tight]), faces=girth_faces[tight])


def _turned(sim: Simulation, x: np.ndarray) -> TurnedCloth:
    """The cloth worn turned over, its outside facing the nearest skin (:mod:`.turned`)."""
    from .drape import weld_groups
    from .turned import turned_cloth

    body = np.asarray(sim.character.vertices, dtype=np.float64)
    return turned_cloth(x, sim.cloth.faces, weld_groups(len(x), sim.cloth.seams), body, sim.character.faces)


def _turned_by_piece(
    patch: np.ndarray, area_cm2: np.ndarray, face_piece: np.ndarray, names: tuple[str, ...]
) -> dict[str, float]:
    """Piece -> area of the largest patch of turned-over cloth it holds most of, cm² (pieces with none left out)."""
    out: dict[str, float] = {}
    for p in np.argsort(-area_cm2):
        owner = names[int(np.bincount(face_piece[patch == p]).argmax())]
        out.setdefault(owner, float(area_cm2[p]))
    return out


def _measured(
    sim: Simulation,
    table: tuple[SeamGapRow, ...],
    x: np.ndarray,
    grain: np.ndarray,
    surface: _Surface,
    strain: _EdgeStrain,
    girth: _Girth,
    turned: TurnedCloth,
) -> Measured:
    """The quantities the verdict judges."""
    from .defects import anchor_levels_cm, hem_rise_cm, seam_excess_cm

    names, face_piece = sim.names, surface.face_piece
    folded_pieces, folded_counts = np.unique(face_piece[surface.folded], return_counts=True)
    body = np.asarray(sim.character.vertices, dtype=np.float64)
    over = {names[g]: int(c) for g, c in zip(*np.unique(strain.group[strain.beyond], return_counts=True), strict=True)}
    rises = hem_rise_cm(sim.pattern, sim.pmesh, x, sim.cloth.group, grain, sim.stretches)
    return Measured(
        seam_gaps_mm={r.seam: r.max_mm for r in table},
        seam_excess_cm=seam_excess_cm(sim.pattern, sim.pmesh),
        self_crossing={names[g]: int(c) for g, c in zip(folded_pieces, folded_counts, strict=True)},
        skin_depth_mm=surface.skin_depth_mm,
        skin_share=float(np.mean(surface.skin_bad)) if len(surface.skin_bad) else 0.0,
        skin_pieces=tuple(sorted({names[g] for g in face_piece[surface.skin_bad]})),
        stretch_share=float(np.mean(strain.beyond)) if len(strain.ratio) else 0.0,
        torn_share=float(np.mean(strain.torn)) if len(strain.ratio) else 0.0,
        stretch_pieces=tuple(sorted(over, key=lambda k: -over[k])),
        levels_cm=anchor_levels_cm(sim.character, body, sim.pattern, sim.pmesh, x, sim.cloth.group),
        hem_rise_cm={k: max(0.0, r) for k, r in rises.items()},
        girth_strain=girth.strain,
        girth_height_cm=girth.height_cm,
        girth_pieces=tuple(sorted({names[g] for g in face_piece[girth.faces]})) if girth.faces is not None else (),
        turned_cm2=_turned_by_piece(turned.patch, turned.area_cm2, face_piece, names),
    )


def _drape_report(
    sim: Simulation,
    m: Measured,
    x: np.ndarray,
    wx: np.ndarray,
    inside: np.ndarray,
    surface: _Surface,
    strain: _EdgeStrain,
    limits: VerdictLimits,
) -> DrapeReport:
    """The drape report: the verdict on ``m`` and the measures behind it."""
    from .drape import seam_gaps

    cloth, names, ratio = sim.cloth, sim.names, strain.ratio
    verdict, reasons = judge(m, limits)
    per = {
        n: float(np.percentile(ratio[strain.group == i], 95)) for i, n in enumerate(names) if np.any(strain.group == i)
    }
    by_gap = sorted((SeamGap(seam=s, max_mm=g) for s, g in m.seam_gaps_mm.items()), key=lambda g: -g.max_mm)
    return DrapeReport(
        verdict=verdict,
        reasons=reasons,
        penetrating_vertices=int(np.count_nonzero(inside)),
        crossing_triangles=int(np.count_nonzero(surface.crossing)),
        crossing_pieces=tuple(sorted({names[g] for g in surface.face_piece[surface.crossing]})),
        skin_depth_mm=m.skin_depth_mm,
        skin_triangles=int(np.count_nonzero(surface.skin_bad)),
        self_crossing_triangles=int(np.count_nonzero(surface.folded)),
        self_crossing_pieces=m.self_crossing,
        max_seam_gap_mm=float(seam_gaps(x, cloth.seams).max(initial=0.0) * 10.0),
        max_seam_gap_before_weld_mm=by_gap[0].max_mm if by_gap else 0.0,
        worst_seam_before_weld=by_gap[0].seam if by_gap else "",
        seam_gaps_before_weld=tuple(by_gap),
        seams_open_before_weld=tuple(g for g in by_gap if g.max_mm > WELDED_OPEN_MM),
        levels_cm=m.levels_cm,
        hem_rise_cm=m.hem_rise_cm,
        girth_strain=m.girth_strain,
        girth_height_cm=m.girth_height_cm,
        turned_cm2=m.turned_cm2,
        stretch=Stretch(
            percentiles={f"p{q}": float(np.percentile(ratio, q)) for q in (1, 5, 50, 95, 99)},
            max=float(ratio.max()),
            worst_pieces=tuple(sorted(per.items(), key=lambda kv: -kv[1])[:3]),
            beyond_limit_share=m.stretch_share,
            short_edges=int(np.count_nonzero(~strain.measured)),
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
            if inst.key not in m.levels_cm
        ),
        warnings=tuple(str(f) for f in sim.findings),
        limits=limits,
        fabric_why=sim.pattern.fabric_why,
        piece_fabrics={
            p.name: p.fabric_class for p in sim.pattern.pieces if p.fabric_class not in (None, limits.fabric)
        },
    )


def _flagged(
    sim: Simulation,
    surface: _Surface,
    strain: _EdgeStrain,
    girth: _Girth,
    turned: TurnedCloth,
    limits: VerdictLimits,
) -> np.ndarray:
    """(F,) bool: what the verdict names, marked red in the pictures.

    Open seams, the cloth through itself or the skin, cloth stretched beyond tearing, cloth turned over, and the
    girth the garment does not close round.
    """
    from .defects import faces_touching
    from .drape import seam_gaps

    cloth = sim.cloth
    g = seam_gaps(cloth.x, cloth.seams) if len(cloth.seams) else np.zeros(0)
    open_pairs = cloth.seams[g * 10.0 > limits.seam_gap_flawed_mm]
    flagged = (
        surface.folded
        | surface.crossing
        | surface.skin_bad
        | faces_touching(cloth.faces, open_pairs, len(cloth.x))
        | faces_touching(cloth.faces, strain.edges[strain.torn], len(cloth.x))
        | turned.faces(limits.turned_flawed_cm2)
    )
    if girth.strain > limits.girth_failed:
        flagged |= girth.faces  # the girth the garment does not close round
    return flagged


def measure_drape(
    sim: Simulation,
    table: tuple[SeamGapRow, ...],
    x: np.ndarray,
    wx: np.ndarray,
    wf: np.ndarray,
    inside: np.ndarray,
    limits: VerdictLimits,
) -> tuple[DrapeReport, np.ndarray]:
    """The drape report of the finished garment and the (F,) faces to mark red in the pictures."""
    from .defects import grain_directions

    grain = grain_directions(sim.pattern, sim.pmesh)
    surface = _surface(sim, wx, wf, limits)
    strain = _edge_strain(sim, x, grain, limits)
    girth = _tightest_girth(sim, x)
    turned = _turned(sim, x)
    measured = _measured(sim, table, x, grain, surface, strain, girth, turned)
    report = _drape_report(sim, measured, x, wx, inside, surface, strain, limits)
    return report, _flagged(sim, surface, strain, girth, turned, limits)


def skin_crossing(collider, x: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(F,) bool: garment triangles crossing the skin either way (an edge through the body, the skin through them)."""
    crossing = collider.crossing_triangles(x, faces)
    crossing[collider.skin_through(x, faces)[0]] = True
    return crossing
