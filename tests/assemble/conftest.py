"""Fixtures for the assembler tests: a hand-made T-shirt pattern with bridge data."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.pattern.model import (
    BodyPart,
    Copy,
    EdgeRange,
    Pattern,
    Piece,
    Placement,
    Quantity,
    Seam,
    Side,
)


def _arc(p0, p1, bulge, n=6):
    """Points strictly between p0 and p1 on a curve bulging ``bulge`` cm to the left."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    t = np.linspace(0, 1, n + 2)[1:-1]
    d = p1 - p0
    normal = np.array([-d[1], d[0]]) / np.hypot(*d)
    return p0 + t[:, None] * d + (bulge * 4 * t * (1 - t))[:, None] * normal


def _body(neck_depth: float, side: str) -> tuple[np.ndarray, dict[str, int]]:
    """Front or back outline (CCW, seen from outside) and its marks."""
    w, h = 27.0, 68.0
    left, right = ("r", "l") if side == "front" else ("l", "r")  # character sides on the drawing's left/right
    pts, marks = [], {}

    def add(name, p):
        if name:
            marks[name] = len(pts)
        pts.append(p)

    add(f"hem_{left}", (-w, 0.0))
    add(f"hem_{right}", (w, 0.0))
    add(f"underarm_{right}", (w, 44.0))
    for p in _arc((w, 44.0), (20.0, 64.0), 3.5):
        add(None, tuple(p))
    add(f"shoulder_{right}", (20.0, 64.0))
    add(f"neck_{right}", (8.0, h))
    for p in _arc((8.0, h), (0.0, h - neck_depth), -2.0, 3):
        add(None, tuple(p))
    add("neck_centre", (0.0, h - neck_depth))
    for p in _arc((0.0, h - neck_depth), (-8.0, h), -2.0, 3):
        add(None, tuple(p))
    add(f"neck_{left}", (-8.0, h))
    add(f"shoulder_{left}", (-20.0, 64.0))
    for p in _arc((-20.0, 64.0), (-w, 44.0), 3.5):
        add(None, tuple(p))
    add(f"underarm_{left}", (-w, 44.0))
    return np.array(pts), marks


def _sleeve() -> tuple[np.ndarray, dict[str, int]]:
    pts, marks = [], {}

    def add(name, p):
        if name:
            marks[name] = len(pts)
        pts.append(p)

    add("hem_a", (-17.0, -12.0))
    add("hem_b", (17.0, -12.0))
    add("under_b", (20.0, 0.0))
    for p in _arc((20.0, 0.0), (0.0, 14.0), 3.0):
        add(None, tuple(p))
    add("top", (0.0, 14.0))
    for p in _arc((0.0, 14.0), (-20.0, 0.0), 3.0):
        add(None, tuple(p))
    add("under_a", (-20.0, 0.0))
    return np.array(pts), marks


def make_tshirt(*, placement: bool = True) -> Pattern:
    """A short-sleeved T-shirt: whole front, whole back, a pair of sleeves."""
    fo, fm = _body(8.0, "front")
    bo, bm = _body(2.0, "back")
    so, sm = _sleeve()
    front = Piece(
        name="front",
        outline=fo,
        marks=fm,
        landmarks={
            "front_neck_point": "neck_centre",
            "shoulder_point_left": "shoulder_l",
        },
        placement=Placement(
            body_part=BodyPart.TORSO,
            side=Side.FRONT,
            anchor="front_neck_point",
            anchor_mark="neck_centre",
        )
        if placement
        else None,
    )
    back = Piece(
        name="back",
        outline=bo,
        marks=bm,
        landmarks={"back_neck_point": "neck_centre"},
        placement=Placement(
            body_part=BodyPart.TORSO,
            side=Side.BACK,
            anchor="back_neck_point",
            anchor_mark="neck_centre",
        )
        if placement
        else None,
    )
    sleeve = Piece(
        name="sleeve",
        outline=so,
        marks=sm,
        quantity=Quantity(right=1, left=1),
        landmarks={"shoulder_point_right": "top"},
        placement=Placement(
            body_part=BodyPart.RIGHT_ARM,
            side=Side.AROUND,
            anchor="shoulder_point_right",
            anchor_mark="top",
        )
        if placement
        else None,
    )

    def er(piece, a, b, copy=Copy.PRIMARY):
        return EdgeRange(piece=piece, start=a, end=b, copy=copy)

    M = Copy.MIRROR
    seams = (
        Seam(
            id="side_l",
            a=er("front", "hem_l", "underarm_l"),
            b=er("back", "underarm_l", "hem_l"),
        ),
        Seam(
            id="side_r",
            a=er("front", "underarm_r", "hem_r"),
            b=er("back", "hem_r", "underarm_r"),
        ),
        Seam(
            id="shoulder_l",
            a=er("front", "shoulder_l", "neck_l"),
            b=er("back", "neck_l", "shoulder_l"),
        ),
        Seam(
            id="shoulder_r",
            a=er("front", "neck_r", "shoulder_r"),
            b=er("back", "shoulder_r", "neck_r"),
        ),
        Seam(
            id="armhole_r_front",
            a=er("front", "shoulder_r", "underarm_r"),
            b=er("sleeve", "under_b", "top"),
        ),
        Seam(
            id="armhole_r_back",
            a=er("back", "underarm_r", "shoulder_r"),
            b=er("sleeve", "top", "under_a"),
        ),
        Seam(
            id="armhole_l_front",
            a=er("front", "underarm_l", "shoulder_l"),
            b=er("sleeve", "under_b", "top", M),
            reverse=False,
        ),
        Seam(
            id="armhole_l_back",
            a=er("back", "shoulder_l", "underarm_l"),
            b=er("sleeve", "top", "under_a", M),
            reverse=False,
        ),
        Seam(
            id="underarm_r",
            a=er("sleeve", "hem_b", "under_b"),
            b=er("sleeve", "under_a", "hem_a"),
        ),
        Seam(
            id="underarm_l",
            a=er("sleeve", "hem_b", "under_b", M),
            b=er("sleeve", "under_a", "hem_a", M),
        ),
    )
    return Pattern(style="test-tshirt", pieces=(front, back, sleeve), sample_size="M", seams=seams)


@pytest.fixture(scope="session")
def tshirt() -> Pattern:
    return make_tshirt()


@pytest.fixture(scope="session")
def character_e(characters_dir):
    from patternbridge.mesh.load import load_character

    character, _ = load_character(characters_dir / "E_average_male.obj")
    return character


@pytest.fixture(scope="session")
def tshirt_factory():
    """The T-shirt builder (``placement=False`` drops the placement hints)."""
    return make_tshirt


@pytest.fixture(scope="session")
def draped_tshirt(character_e):
    """The T-shirt draped on E and skinned to E's rig, read from ``data/tshirt_e_draped.npz``.

    Captured from ``assemble(character_e, make_tshirt(), seed=1, max_edge_cm=5.0, steps=20)``
    (645 vertices, 4 cut pieces), so the exporters are tested on a real drape without draping.
    """
    from pathlib import Path

    from patternbridge.assemble import Garment

    d = np.load(Path(__file__).parent / "data" / "tshirt_e_draped.npz")
    return Garment(
        vertices=d["vertices"],
        faces=d["faces"],
        uv=d["uv"],
        instance=d["instance"],
        instance_names=tuple(str(n) for n in d["instance_names"]),
        weld=d["weld"],
        joints=d["joints"],
        weights=d["weights"],
        skeleton=character_e.skeleton,
    )


class NoBody:
    """A collider with nothing to collide with (far away): the cloth tests' free space."""

    def closest(self, points):
        n = len(points)
        q = np.tile([0.0, -1e4, 0.0], (n, 1))
        return q, np.tile([0.0, 1.0, 0.0], (n, 1)), np.full(n, 1e4), np.zeros(n, np.int64), np.zeros((n, 2))

    def inside(self, points):
        return np.zeros(len(points), dtype=bool)

    def sweep(self, start, end, offset_cm, *, min_move_cm=0.0):
        return np.array(end, dtype=np.float64), np.zeros(len(end), dtype=bool)


@pytest.fixture
def no_body() -> NoBody:
    return NoBody()
