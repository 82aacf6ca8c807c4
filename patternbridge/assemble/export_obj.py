"""Write the draped garment as Wavefront OBJ + MTL.

- positions in centimetres, +Y up, as the character files are; sewn vertices
  share one ``v`` (one per welded vertex), so the surface is connected across
  seams;
- ``vn``: one unit normal per welded vertex, area-weighted over the welded
  surface (the same normals as the GLB's ``NORMAL``);
- ``vt``: one per garment vertex, the fabric coordinates in metres of cloth in
  OBJ's convention (origin bottom-left, v up: ``u = x / 100``, ``v = y / 100``,
  mirrored copies turned over, see :mod:`.export_attributes`); a seam is a UV
  seam;
- ``f v/vt/vn`` counter-clockwise seen from outside, a ``g`` + ``usemtl`` per
  cut piece, and the MTL with one diffuse colour per piece.
"""

from __future__ import annotations

import os

import numpy as np

from ..atomic import write_text
from .export_attributes import fabric_uv, texcoords_bottom_left, vertex_normals

__all__ = ["obj_text", "write_obj"]


def _name(piece: str) -> str:
    """A group/material name without white space (OBJ splits on it)."""
    return "_".join(piece.split())


def obj_text(garment, mtl_name: str = "garment.mtl") -> tuple[str, str]:
    """OBJ and MTL texts of ``garment`` (see the module notes).

    Parameters
    ----------
    garment : :class:`~patternbridge.assemble.garment.Garment`
    mtl_name : the MTL file name the OBJ refers to

    Returns
    -------
    (obj, mtl) : str, str with ``\\n`` line ends
    """
    from .pictures import PIECE_COLOURS

    wv, wf = garment.welded()
    vn = vertex_normals(wv, wf)
    lines = [
        "# patternbridge garment: positions in cm, +Y up; vt = pattern coordinates / 100 (origin bottom-left)",
        f"mtllib {mtl_name}",
    ]
    lines += [f"v {x:.5f} {y:.5f} {z:.5f}" for x, y, z in wv]
    lines += [f"vn {x:.6f} {y:.6f} {z:.6f}" for x, y, z in vn]
    vt = texcoords_bottom_left(fabric_uv(garment.uv, garment.faces, garment.instance))
    lines += [f"vt {u:.6f} {v:.6f}" for u, v in vt]
    mtl = ["# patternbridge garment materials"]
    for i, name in enumerate(garment.instance_names):
        pick = garment.instance[garment.faces[:, 0]] == i
        safe = _name(name)
        lines += [f"g {safe}", f"usemtl {safe}"]
        corners = np.stack([wf[pick] + 1, garment.faces[pick] + 1], axis=2)  # (f, 3, [v, vt])
        lines += [f"f {a}/{ta}/{a} {b}/{tb}/{b} {c}/{tc}/{c}" for (a, ta), (b, tb), (c, tc) in corners]
        rgb = PIECE_COLOURS[i % len(PIECE_COLOURS)] / 255.0
        mtl += [
            f"newmtl {safe}",
            f"Kd {rgb[0]:.4f} {rgb[1]:.4f} {rgb[2]:.4f}",
            "Ka 0 0 0",
            "Ks 0 0 0",
            "d 1",
            "illum 1",
            "",
        ]
    return "\n".join(lines) + "\n", "\n".join(mtl) + "\n"


def write_obj(path: str | os.PathLike, garment) -> None:
    """Write ``garment`` as ``path`` (OBJ) and the ``.mtl`` beside it, each atomically."""
    path = os.fspath(path)
    mtl_path = os.path.splitext(path)[0] + ".mtl"
    obj, mtl = obj_text(garment, os.path.basename(mtl_path))
    write_text(mtl_path, mtl)
    write_text(path, obj)
