"""Input checks before dressing: bridge data present, limbs clear of the torso."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..pattern.model import Pattern
from ..report import Report
from .bodyparts import BodyParts

__all__ = ["check_pattern", "limbs_touching"]

ARM_TOUCH_CM = 0.5  # arm skin closer than this to the torso (away from the shoulder) touches it
LEG_TOUCH_CM = 0.3  # leg skin closer than this to the other leg touches it
SHOULDER_ZONE_CM = 12.0  # arm vertices this close to the arm's root are not checked


def check_pattern(pattern: Pattern) -> None:
    """Raise unless every piece has a placement hint and the pattern has seams.

    Raises
    ------
    InputError
        Pieces without placement hints (named), or no seam table.
    """
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


def limbs_touching(vertices: np.ndarray, parts: BodyParts, report: Report, name: str) -> int:
    """Add a ``limbs-touching`` warning to ``report`` for arms against the torso or legs against each other.

    Parameters
    ----------
    vertices : (V, 3) float64, cm — the body in the dressing pose
    parts : body-part labels
    report : findings, appended to
    name : the character's name (``where`` of the finding)

    Returns
    -------
    int, the number of warnings added
    """
    from scipy.spatial import cKDTree

    added = 0
    torso = vertices[parts.mask("torso")]
    if len(torso) == 0:
        return 0
    tree = cKDTree(torso)
    for side in ("left", "right"):
        arm = vertices[parts.mask(f"{side}_arm")]
        if len(arm) == 0:
            continue
        # the arm's part away from the shoulder should not touch the torso
        root = arm[np.argmin(tree.query(arm)[0])]
        far = arm[np.linalg.norm(arm - root, axis=1) > SHOULDER_ZONE_CM]
        d = tree.query(far)[0] if len(far) else np.array([np.inf])
        if np.min(d) < ARM_TOUCH_CM:
            report.add(
                "limbs-touching",
                f"the {side} arm touches the torso ({int(np.sum(d < ARM_TOUCH_CM))} vertices closer than "
                f"{ARM_TOUCH_CM * 10:.0f} mm); dressed as best it can, expect cloth caught between them",
                where=name,
            )
            added += 1
    legs = [vertices[parts.mask(f"{s}_leg")] for s in ("left", "right")]
    if all(len(leg) for leg in legs):
        d = cKDTree(legs[0]).query(legs[1])[0]
        if np.min(d) < LEG_TOUCH_CM:
            report.add(
                "limbs-touching",
                f"the legs touch each other ({int(np.sum(d < LEG_TOUCH_CM))} vertices closer than "
                f"{LEG_TOUCH_CM * 10:.0f} mm); dressed as best it can",
                where=name,
            )
            added += 1
    return added
