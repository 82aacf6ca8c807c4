"""The ``fit_report.json`` dictionary of a grading run."""

from __future__ import annotations

from typing import Any

import numpy as np

from .forcing import Forcing
from .run import FitResult
from .solution import Scores, Solution

__all__ = ["fit_report", "scores_dict"]


def _r(value: float, digits: int = 4) -> float:
    return float(round(float(value), digits))


def scores_dict(result: FitResult, scores: Scores) -> dict[str, Any]:
    """Measurements, seams and shape figures of one solution (report layout).

    ``measurements``: one entry per measurement link, ``delta_cm`` is the
    signed ``achieved - target`` and ``error_cm`` its size, 0 for an
    ``at_least`` link that is exceeded (marked ``"at_least": true``).
    ``seams``: one entry per seam, ``mismatch_mm`` is
    ``|L_b - L_a - ease|`` and ``notch_mm`` the worst notch misalignment on it.
    """
    data = result.data
    err = scores.error_cm
    measurements = [
        {
            "id": link_id,
            "measurement": meas,
            "body_cm": _r(result.measurements[meas], 3),
            "target_cm": _r(t, 3),
            "achieved_cm": _r(a, 3),
            "error_cm": _r(abs(e), 3),
            "delta_cm": _r(a - t, 3),
            **({"at_least": True} if least else {}),
        }
        for link_id, meas, t, a, e, least in zip(data.link_ids, data.link_measurements, scores.target_cm,
                                                 scores.achieved_cm, err, data.at_least, strict=True)
    ]
    seams = []
    for s, (seam_id, (a, b)) in enumerate(zip(data.seam_ids, data.seam_labels, strict=False)):
        notch = np.abs(scores.notch_cm[scores.notch_seam == s])
        seams.append({
            "id": seam_id,
            "a": a,
            "b": b,
            "mismatch_mm": _r(abs(scores.seam_mismatch_cm[s]) * 10.0, 3),
            "notch_mm": _r(notch.max() * 10.0, 3) if len(notch) else 0.0,
            "ease_cm": _r(data.seam_ease_cm[s], 3),
        })
    abs_err = np.abs(err)
    seam_mm = [max(s["mismatch_mm"], s["notch_mm"]) for s in seams]
    return {
        "measurements": measurements,
        "mean_error_cm": _r(abs_err.mean() if len(abs_err) else 0.0),
        "max_error_cm": _r(abs_err.max() if len(abs_err) else 0.0),
        "seams": seams,
        "max_seam_mm": _r(max(seam_mm) if seam_mm else 0.0),
        "shape_error": _r(scores.shape_error, 5),
        "shape_error_all_vertices": _r(scores.shape_error_all, 5),
        "objectives": {
            "measurement_cm": _r(scores.measurement_error),
            "seam": _r(scores.seam_error),
            "shape_rad": _r(scores.shape_error, 5),
        },
        "fold_free": bool(scores.fold_margin > 0),
        "simple_outlines": bool(scores.is_simple),
    }


def _solution_dict(result: FitResult, sol: Solution) -> dict[str, Any]:
    out = {"method": sol.name, "note": sol.note}
    out.update(scores_dict(result, sol.scores))
    out["seconds"] = _r(sol.seconds, 3)
    return out


def _forcing_dict(f: Forcing) -> dict[str, Any]:
    """The release test of :func:`~.forcing.shape_forcing` as JSON."""
    links = [
        {"id": lid, "scaling_miss_cm": _r(m, 3) if np.isfinite(m) else None, "shape_released": _r(sr, 5)}
        for lid, m, sr in zip(f.link_ids, f.miss_cm, f.shape_released, strict=True)
    ]
    points = [{"piece": piece, "point": name, "angle_change_deg": _r(deg, 2)} for piece, name, deg in f.points]
    return {"forced_by": list(f.forced_by), "links": links, "points": points}


def fit_report(result: FitResult, *, character: str = "", garment: str = "") -> dict[str, Any]:
    """The fit report: figures of the graded pattern, the baselines and the front.

    Keys: ``character``, ``garment``, ``measurements``, ``seams``,
    ``shape_error``, ``seconds`` (the whole grading), ``baseline``
    (proportional scaling along/across the grain, same figures),
    ``baselines`` (every baseline by name), ``nsga2`` (NSGA-II's own
    choice, before the final step), ``checks`` (findings of
    :func:`~.checks.design_checks`: a collapsed piece, a flattened curve, a
    lost symmetry) and ``design_kept`` (no finding), ``shape_forcing`` (when the shape error is
    above proportional scaling's: the links released one at a time and the shape error each then
    reaches, those that alone bring it to scaling's (``forced_by``), and the critical
    points that carry the excess; :func:`~.forcing.shape_forcing`), ``pareto_front`` (the final front:
    objectives per row, the chosen row, which rows the final step made and
    which are within tolerance) and
    run settings.
    """
    out: dict[str, Any] = {"character": character, "garment": garment or result.original.style}
    out.update(scores_dict(result, result.chosen.scores))
    out["seconds"] = _r(result.seconds, 3)
    out["method"] = result.chosen.name
    out["note"] = result.chosen.note
    out["baseline"] = _solution_dict(result, result.baselines["proportional"])
    out["baselines"] = {name: _solution_dict(result, sol) for name, sol in result.baselines.items()}
    out["nsga2"] = _solution_dict(result, result.ga_choice)
    out["checks"] = [{"code": f.code, "where": f.where, "message": f.message} for f in result.findings]
    out["design_kept"] = not result.findings
    out["shape_forcing"] = None if result.forcing is None else _forcing_dict(result.forcing)
    out["pareto_front"] = {
        "objectives": ["measurement_cm", "seam", "shape_rad"],
        "F": np.round(result.front_F, 5).tolist(),
        "chosen_index": int(result.chosen_index),
        "refined": [bool(v) for v in result.front_refined],
        "within_tolerance": [bool(v) for v in result.front_within],
    }
    out["settings"] = {
        "seed": result.seed,
        "pop_size": result.pop_size,
        "n_gen": result.n_gen,
        "n_var": int(result.grid.n_var),
        "grid": {g.name: [g.nu, g.nv] for g in result.grid.pieces},
        "deformation": result.grid.deformation,
    }
    return out
