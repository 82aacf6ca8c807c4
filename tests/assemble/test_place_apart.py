"""The placement lays the pieces without passing through each other: the legs' hems, the folds where proxies meet."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.assemble.place.wrap import _held_widths, _widths


def test_the_rows_by_a_slanted_hem_keep_the_piece_s_width():
    # a leg piece 20 cm wide whose hem rises 3 cm from one side to the other:
    # its lowest rows barely cross the outline
    b = np.array([[0.0, 0.0], [20.0, 3.0], [20.0, 40.0], [0.0, 40.0]])
    ys = np.array([0.1, 1.0, 2.0, 10.0])
    assert _widths(b, ys)[0] < 1.0  # as drawn: the tip of the slant only
    np.testing.assert_allclose(_held_widths(b, ys, at_hem=True), [20.0, 20.0, 20.0, 20.0])
    # below the piece (a partner's hem hangs lower) it still counts, once sewn beside it
    assert _held_widths(b, np.array([-2.0]), at_hem=True)[0] == pytest.approx(20.0)
    # above the hold the outline's own width
    assert _held_widths(b, np.array([30.0]), at_hem=True)[0] == pytest.approx(20.0)


@pytest.mark.shared
def test_the_library_shorts_are_placed_without_passing_through_themselves(characters_dir):
    # the library shorts (sample size) placed on B_slim_female, counted as the
    # benchmark counts it (the sides of every seam averaged, the whole garment):
    # before the hems were held and the folds smoothed, 90 triangles through
    # other cloth (the hems folded in across the legs, the backs' crotch
    # extensions through themselves; the hems held alone, 89); now 31
    from patternbridge.assemble.cloth import weld_groups
    from patternbridge.assemble.pipeline import prepare, with_anchor_landmarks
    from patternbridge.assemble.selfcross import self_crossing
    from patternbridge.library import load_garment
    from patternbridge.mesh.load import load_character

    character, _ = load_character(characters_dir / "B_slim_female.obj")
    pattern = load_garment("shorts")
    character, _ = with_anchor_landmarks(character, pattern)
    cloth = prepare(character, pattern, seed=0).cloth
    weld = weld_groups(len(cloth.x), cloth.seams)
    ids, inv = np.unique(weld, return_inverse=True)
    x = np.zeros((len(ids), 3))
    np.add.at(x, inv, cloth.x)
    x /= np.bincount(inv, minlength=len(ids))[:, None]
    crossing = self_crossing(x, inv[cloth.faces])
    assert np.count_nonzero(crossing) <= 40, np.count_nonzero(crossing)
    # nothing crosses by the hems (the lowest 5 cm of the legs)
    centroid_y = x[inv[cloth.faces]].mean(axis=1)[:, 1]
    assert not crossing[centroid_y < x[:, 1].min() + 5.0].any()
