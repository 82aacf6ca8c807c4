"""Character meshes: loading with unit/up-axis detection, skeleton, skinning, landmarks.

The submodules import their heavy dependencies (trimesh, scipy, Pillow) lazily:
``load`` (``load_character``), ``skinning`` (``pose_vertices``), ``landmarks``
(``resolve_landmarks``, ``detect_landmarks``), ``render`` (``render``, ``save_png``).
"""

from __future__ import annotations

from .character import Character, Landmark, Skeleton, Skin

__all__ = ["Character", "Landmark", "Skeleton", "Skin"]
