"""Block constructions shared by the library garments: armholes, necklines, sleeve caps.

The shapes follow the standard blocks of pattern-cutting textbooks (Aldrich,
*Metric Pattern Cutting*; Armstrong, *Patternmaking for Fashion Design*):

- **armhole**: from the shoulder point down to the across-back/chest point
  (vertical tangent there), then out to the side seam at the chest line,
  arriving horizontally, so the armhole bottom meets the side seam square;
- **neckline**: from the side-neck point, leaving square to the shoulder line,
  to the centre line, arriving square to it;
- **sleeve cap**: an S-curve from each underarm point (hollow near the
  underarm, round at the crown); its height and the crown's offset are solved
  so the front and back cap lengths equal the front and back armholes plus the
  declared cap ease (Aldrich fits the crown to the measured armhole the same way).

All functions return Bézier control polygons (4, 2) or sampled (n + 1, 2)
polylines in cm.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import fsolve

from .draft import bezier_length

__all__ = ["armhole_controls", "neckline_controls", "sleeve_cap_controls"]


def armhole_controls(shoulder, across, underarm) -> tuple[np.ndarray, np.ndarray]:
    """Two Bézier control polygons: shoulder point → across point → underarm.

    Parameters
    ----------
    shoulder, across, underarm : (2,) cm; the underarm lies on the chest line
        and further from the centre line than ``across``.
    """
    s, a, u = (np.asarray(p, dtype=np.float64) for p in (shoulder, across, underarm))
    drop = s[1] - a[1]
    upper = np.array(
        [
            s,
            [s[0] + (a[0] - s[0]) * 0.35, s[1] - drop * 0.35],
            [a[0], a[1] + drop * 0.4],
            a,
        ]
    )
    rise = a[1] - u[1]
    lower = np.array(
        [a, [a[0], u[1] + rise * 0.35], [u[0] - (u[0] - a[0]) * 0.45, u[1]], u]
    )
    return upper, lower


def neckline_controls(centre, side_neck, shoulder_dir) -> np.ndarray:
    """Bézier controls from the centre-line neck point to the side-neck point.

    The curve leaves the centre line square (horizontally) and arrives at the
    side-neck point square to the shoulder line ``shoulder_dir`` (a (2,) vector
    pointing from the side-neck point to the shoulder point).
    """
    c, n = np.asarray(centre, float), np.asarray(side_neck, float)
    d = np.asarray(shoulder_dir, float)
    d = d / np.hypot(*d)
    perp = np.array([-d[1], d[0]])
    if perp[1] > 0:  # the curve arrives going up
        perp = -perp
    width, depth = abs(n[0] - c[0]), abs(n[1] - c[1])
    return np.array(
        [
            c,
            [c[0] + np.sign(n[0] - c[0]) * width * 0.6, c[1]],
            n + perp * depth * 0.55,
            n,
        ]
    )


def _cap(a: float, xt: float, h: float) -> tuple[np.ndarray, np.ndarray]:
    front = np.array(
        [[a, 0.0], [xt + 0.72 * (a - xt), 0.14 * h], [xt + 0.45 * (a - xt), h], [xt, h]]
    )
    b = -a
    back = np.array(
        [[xt, h], [xt + 0.45 * (b - xt), h], [xt + 0.72 * (b - xt), 0.14 * h], [b, 0.0]]
    )
    return front, back


def sleeve_cap_controls(
    half_bicep: float, front_cm: float, back_cm: float
) -> tuple[np.ndarray, np.ndarray, float]:
    """Sleeve-cap curves whose lengths are ``front_cm`` and ``back_cm``.

    The front underarm sits at ``(+half_bicep, 0)``, the back at
    ``(-half_bicep, 0)`` (front on the right: the right sleeve seen from
    outside). Solves the crown height and its x offset.

    Returns
    -------
    front (4, 2) from the front underarm to the crown, back (4, 2) from the
    crown to the back underarm, crown height (cm).

    Raises
    ------
    ValueError
        When no cap of those lengths exists over that bicep (cap shorter than
        the bicep).
    """
    a = float(half_bicep)
    if min(front_cm, back_cm) <= a * 1.02:
        raise ValueError(
            f"cap lengths {front_cm:.1f}/{back_cm:.1f} cm too short for half bicep {a:.1f} cm"
        )

    def resid(v):
        xt, h = v
        f, b = _cap(a, xt, h)
        return [bezier_length(f) - front_cm, bezier_length(b) - back_cm]

    guess = [0.0, float(np.sqrt(max(((front_cm + back_cm) / 2) ** 2 - a**2, 1.0)))]
    sol, _info, ier, msg = fsolve(resid, guess, full_output=True, xtol=1e-10)
    if ier != 1 or max(abs(r) for r in resid(sol)) > 1e-4:
        raise ValueError(f"sleeve cap did not converge ({msg})")
    f, b = _cap(a, sol[0], sol[1])
    return f, b, float(sol[1])
