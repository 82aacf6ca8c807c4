"""Tape correction: concave stretches become straight, convex ones stay."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.errors import MeshError
from patternbridge.geodesic import tape_correct
from patternbridge.geodesic.tape import exempt_mask


def _arc(n=41, sign=1.0):
    """A circular arc in the x-z plane bulging down (sign=1: concave under +z)."""
    t = np.linspace(-1.0, 1.0, n)
    p = np.c_[t, np.zeros(n), sign * (t**2 - 1.0) * 0.5]
    return p, np.tile([0.0, 0.0, 1.0], (n, 1))


def test_concave_arc_becomes_its_chord():
    p, n = _arc()
    out = tape_correct(p, n)
    np.testing.assert_allclose(out, p[[0, -1]])


def test_convex_arc_is_unchanged():
    p, n = _arc(sign=-1.0)
    np.testing.assert_allclose(tape_correct(p, n), p)


def test_exempt_section_stays_on_the_skin():
    p, n = _arc()
    mask = np.zeros(len(p), dtype=bool)
    mask[18:23] = True
    out = tape_correct(p, n, exempt=mask)
    for q in p[18:23]:
        assert np.min(np.linalg.norm(out - q, axis=1)) < 1e-12
    # and it is still shorter than the skin
    skin = np.linalg.norm(np.diff(p, axis=0), axis=1).sum()
    tape = np.linalg.norm(np.diff(out, axis=0), axis=1).sum()
    assert 2.0 < tape < skin


def test_exempt_fractions_match_arc_length():
    p = np.c_[np.linspace(0, 10, 11), np.zeros(11), np.zeros(11)]
    mask = exempt_mask(p, [(0.2, 0.4)])
    assert mask.tolist() == [False, False, True, True, True] + [False] * 6


def test_two_dips_with_a_bump_between():
    x = np.linspace(0, 4 * np.pi, 201)
    p = np.c_[x, np.zeros_like(x), np.cos(x)]  # bumps at 0, 2pi, 4pi; dips between
    out = tape_correct(p, np.tile([0.0, 0.0, 1.0], (len(x), 1)))
    # the tape rests on the three crests only
    np.testing.assert_allclose(out[:, 2], 1.0, atol=1e-9)


def test_bad_arguments():
    p, n = _arc(5)
    with pytest.raises(MeshError, match="must both be"):
        tape_correct(p, n[:3])
    with pytest.raises(MeshError, match="exempt mask"):
        tape_correct(p, n, exempt=np.zeros(3, dtype=bool))
    with pytest.raises(MeshError, match="fractions"):
        tape_correct(p, n, exempt=[(0.5, 0.2)])
