"""Cloth test meshes shared by the solver and untangling tests."""

from __future__ import annotations

import numpy as np


def sheet(n: int, size: float) -> tuple[np.ndarray, np.ndarray]:
    """A square sheet of 2n² triangles, ``size`` cm wide: (pattern points (P, 2), faces (F, 3))."""
    s = np.linspace(0.0, size, n + 1)
    u, v = np.meshgrid(s, s, indexing="ij")
    pts = np.stack([u.ravel(), v.ravel()], axis=1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    return pts, np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def tube(radius: float, x0: float, length: float, around: int = 24, along: int = 4):
    """A cloth tube round the x axis from ``x0``: (positions (P, 3), pattern points (P, 2), faces, the two
    columns its seam joins (each (along + 1,) local ids))."""
    s = np.linspace(0.0, 2 * np.pi * radius, around + 1)
    t = np.linspace(0.0, length, along + 1)
    u, v = np.meshgrid(s, t, indexing="ij")
    pts = np.stack([u.ravel(), v.ravel()], axis=1)
    idx = np.arange((around + 1) * (along + 1)).reshape(around + 1, along + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    faces = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    angle = pts[:, 0] / radius
    x = np.c_[x0 + pts[:, 1], radius * np.cos(angle), radius * np.sin(angle)]
    return x, pts, faces, idx[0], idx[-1]


def arm_and_mitt(radius: float = 2.5):
    """A forearm (a 48-sided cylinder along x, x in [-20, 12]) and a box mitt over its end (x in [8, 16]).

    The mitt's face x = 8 cuts through the arm: within ``radius`` of the axis it is buried in the skin, as the
    end of a hand's hull is in the wrist. Returns two trimesh meshes.
    """
    import trimesh

    arm = trimesh.creation.cylinder(radius=radius, height=32.0, sections=48)
    arm.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0.0, 1.0, 0.0]))
    arm.apply_translation([-4.0, 0.0, 0.0])
    mitt = trimesh.creation.box(extents=[8.0, 7.0, 7.0])
    mitt.apply_translation([12.0, 0.0, 0.0])
    return arm, mitt


def captured_on_a(characters_dir, name: str):
    """A patch of cloth captured on A_superhero (``tests/assemble/data/NAME.npz``): its vertices (V, 3), faces
    (F, 3), the clearance offset the finish used, and a collider of A's skin."""
    from pathlib import Path

    from patternbridge.assemble.collision import BodyCollider
    from patternbridge.mesh.load import load_character

    data = np.load(Path(__file__).parent / "data" / f"{name}.npz")
    character, _ = load_character(characters_dir / "A_superhero.obj")
    body = BodyCollider(np.asarray(character.vertices, dtype=np.float64), character.faces)
    return data["vertices"], data["faces"], float(data["offset"]), body
