"""The typed ``drape`` report: what the finished drape measures, its verdict and the reasons.

:class:`DrapeReport` is what :func:`~patternbridge.assemble.finish` returns
on the garment; :meth:`DrapeReport.to_dict` is its JSON form, stored by
``patternbridge fit`` under ``drape`` in ``fit_report.json``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..pattern.fabric import FabricClass
from .verdict import Reason, Verdict, VerdictLimits

__all__ = ["DrapeReport", "SeamGap", "Stretch"]


@dataclass(frozen=True, slots=True, kw_only=True)
class SeamGap:
    """The widest gap between the sewn vertices of one seam before welding."""

    seam: str
    max_mm: float

    def to_dict(self) -> dict:
        """JSON form."""
        return {"seam": self.seam, "max_mm": round(self.max_mm, 1)}


@dataclass(frozen=True, slots=True, kw_only=True)
class Stretch:
    """Edge length / pattern length over the garment.

    percentiles : p1, p5, p50, p95, p99 ; worst_pieces : (piece, p95), highest first ;
    beyond_limit_share : share of the edges beyond the fabric's limit ;
    short_edges : edges under 1 mm in the pattern (not measured)
    """

    percentiles: dict[str, float]
    max: float
    worst_pieces: tuple[tuple[str, float], ...]
    beyond_limit_share: float
    short_edges: int

    def to_dict(self) -> dict:
        """JSON form."""
        return {
            "percentiles": dict(self.percentiles),
            "max": self.max,
            "worst_pieces": [{"piece": n, "p95": v} for n, v in self.worst_pieces],
            "beyond_limit_share": round(self.beyond_limit_share, 4),
            "short_edges": self.short_edges,
        }


@dataclass(frozen=True, slots=True, kw_only=True)
class DrapeReport:
    """The drape of one garment on one character, measured.

    verdict, reasons : see :mod:`.verdict`; the reasons are worst first
    penetrating_vertices, crossing_triangles, crossing_pieces : skin
        crossings after the final clean-up, by the solver's collider
    skin_depth_mm, skin_triangles : the independent signed-distance check
        (:mod:`.skin_check`): deepest point inside the skin, triangles with a
        point deeper than the verdict's tolerance
    self_crossing_triangles, self_crossing_pieces : cloth through itself
    max_seam_gap_mm : after welding ; max_seam_gap_before_weld_mm,
        worst_seam_before_weld, seam_gaps_before_weld : before it, per seam
        widest first ; seams_open_before_weld : those wider than 5 mm
    levels_cm : piece -> vertical distance of its anchor mark from its landmark
    girth_strain, girth_height_cm : the tightest girth of the garment (a
        horizontal cut, drape length / pattern length) and its height
    unchecked : checks that could not run, with why (a character without
        the landmarks the pieces hang from cannot have its levels checked)
    hem_rise_cm : piece -> how much nearer its hem hangs to its anchor than
        in the pattern (:func:`~.defects.hem_rise_cm`; 0 when it hangs lower)
    turned_cm2 : piece -> area of the largest patch of its cloth worn turned
        over, its outside facing the body (:mod:`.turned`); pieces with none left out
    limits, fabric_why, piece_fabrics : the fabric judged against, its
        limits, the evidence for it, and the pieces of another fabric (a rib)
    """

    verdict: Verdict
    reasons: tuple[Reason, ...]
    penetrating_vertices: int
    crossing_triangles: int
    crossing_pieces: tuple[str, ...]
    skin_depth_mm: float
    skin_triangles: int
    self_crossing_triangles: int
    self_crossing_pieces: dict[str, int]
    max_seam_gap_mm: float
    max_seam_gap_before_weld_mm: float
    worst_seam_before_weld: str
    seam_gaps_before_weld: tuple[SeamGap, ...]
    seams_open_before_weld: tuple[SeamGap, ...]
    levels_cm: dict[str, float]
    stretch: Stretch
    seconds: float
    vertices: int
    triangles: int
    pieces: tuple[str, ...]
    pose: str
    max_placement_move_cm: float
    girth_strain: float = 1.0
    girth_height_cm: float = 0.0
    hem_rise_cm: dict[str, float] = field(default_factory=dict)
    turned_cm2: dict[str, float] = field(default_factory=dict)
    unchecked: tuple[str, ...] = ()
    warnings: tuple[str, ...] = ()
    files: tuple[str, ...] = field(default=())
    limits: VerdictLimits = field(default_factory=VerdictLimits)
    fabric_why: str = ""
    piece_fabrics: dict[str, FabricClass] = field(default_factory=dict)

    def to_dict(self) -> dict:
        """JSON form: the ``drape`` entry of ``fit_report.json``."""
        return {
            "verdict": self.verdict.value,
            "verdict_reasons": [r.to_dict() for r in self.reasons],
            "unchecked": list(self.unchecked),
            "penetrating_vertices": self.penetrating_vertices,
            "crossing_triangles": self.crossing_triangles,
            "crossing_pieces": list(self.crossing_pieces),
            "skin_depth_mm": round(self.skin_depth_mm, 2),
            "skin_triangles": self.skin_triangles,
            "self_crossing_triangles": self.self_crossing_triangles,
            "self_crossing_pieces": dict(self.self_crossing_pieces),
            "max_seam_gap_mm": self.max_seam_gap_mm,
            "max_seam_gap_before_weld_mm": self.max_seam_gap_before_weld_mm,
            "worst_seam_before_weld": self.worst_seam_before_weld,
            "seam_gaps_before_weld": [g.to_dict() for g in self.seam_gaps_before_weld],
            "seams_open_before_weld": [g.to_dict() for g in self.seams_open_before_weld],
            "levels_cm": {k: round(v, 2) for k, v in self.levels_cm.items()},
            "hem_rise_cm": {k: round(v, 2) for k, v in self.hem_rise_cm.items()},
            "turned_cm2": {k: round(v, 1) for k, v in self.turned_cm2.items()},
            "stretch": self.stretch.to_dict(),
            "girth": {"strain": round(self.girth_strain, 4), "height_cm": round(self.girth_height_cm, 1)},
            "fabric": {
                **self.limits.to_dict(),
                "why": self.fabric_why,
                "pieces": {k: v.value for k, v in self.piece_fabrics.items()},
            },
            "seconds": self.seconds,
            "vertices": self.vertices,
            "triangles": self.triangles,
            "pieces": list(self.pieces),
            "pose": self.pose,
            "max_placement_move_cm": self.max_placement_move_cm,
            "warnings": list(self.warnings),
            "files": list(self.files),
        }
