"""Write the dressed character as a USD stage (``.usda`` text or ``.usdc`` crate).

Layout (names made valid USD identifiers, the original kept as ``displayName``)::

    /<character>            SkelRoot (Xform when nothing is skinned), the defaultPrim
        Skeleton            UsdSkel.Skeleton: joints as paths (parents first), jointNames as
                            in the rig, bind and rest transforms at the bone heads
                            (translation only, as in the GLB)
        Body                Mesh of the character, bound to the Skeleton with its own weights
        Garment             Mesh of the garment, welded (sewn vertices share one point),
                            bound to the Skeleton with the garment's four weights a vertex;
            <piece>         GeomSubset per cut piece, family ``materialBind`` (a partition)
        Looks/Body          UsdPreviewSurface material of the body
        Looks/Garment/<piece>  one per piece (the pictures' colours)

- Stage metadata: ``upAxis = "Y"``, ``metersPerUnit = 0.01``: points stay in
  centimetres as inside PatternBridge.
- ``primvars:st`` on the garment: face-varying, indexed (one value per garment
  vertex, so a seam is a UV seam), in USD's convention, origin bottom-left:
  ``st = uv / 100`` of the fabric coordinates (mirrored copies turned over,
  see :mod:`.export_attributes`), the same as the OBJ.
- ``normals``: vertex normals of the welded surface; ``subdivisionScheme =
  "none"`` (the meshes are final polygons, not subdivision cages).
- The same inputs give the same bytes: no time stamps, prims and properties
  written in a fixed order.
"""

from __future__ import annotations

import os

import numpy as np
from pxr import Gf, Sdf, Tf, Usd, UsdGeom, UsdShade, UsdSkel, Vt

from ..atomic import atomic_path
from .export_attributes import SKIN_SLOTS, fabric_uv, skin_slots, texcoords_bottom_left, vertex_normals

__all__ = ["METERS_PER_UNIT", "usd_stage", "write_usd"]

METERS_PER_UNIT = 0.01
"""Points are written in centimetres."""

_BODY_RGB = (0.80, 0.66, 0.56)


def _identifiers(names) -> list[str]:
    """Valid, unique USD prim names for ``names`` (``sleeve~mirror`` → ``sleeve_mirror``)."""
    out: list[str] = []
    for name in names:
        base = Tf.MakeValidIdentifier(name) or "_"
        ident, k = base, 1
        while ident in out:
            ident, k = f"{base}_{k}", k + 1
        out.append(ident)
    return out


def _parent_first(parents: np.ndarray) -> np.ndarray:
    """(B,) int64 order of the bones with every parent before its children (UsdSkel's rule), stable otherwise.

    Raises
    ------
    ValueError
        The parents form a cycle.
    """
    parents = np.asarray(parents, dtype=np.int64)
    placed = np.zeros(len(parents), dtype=bool)
    order: list[int] = []
    while len(order) < len(parents):
        ready = ~placed & ((parents < 0) | placed[np.maximum(parents, 0)])
        if not ready.any():
            raise ValueError("skeleton: the bone parents form a cycle; cannot write UsdSkel joints")
        order += [int(j) for j in np.flatnonzero(ready)]
        placed |= ready
    return np.array(order, dtype=np.int64)


def _joint_paths(skel, order: np.ndarray) -> list[str]:
    """UsdSkel joint paths (``root/pelvis_L/...``) of the bones in ``order``."""
    idents = _identifiers(skel.names)
    path_of: dict[int, str] = {}
    for j in order:
        p = int(skel.parents[j])
        path_of[int(j)] = idents[j] if p < 0 else f"{path_of[p]}/{idents[j]}"
    return [path_of[int(j)] for j in order]


def _translations(offsets: np.ndarray) -> Vt.Matrix4dArray:
    mats = np.tile(np.eye(4), (len(offsets), 1, 1))
    mats[:, 3, :3] = offsets  # USD matrices are row-major with the translation in the last row
    return Vt.Matrix4dArray.FromNumpy(mats)


def _define_skeleton(stage: Usd.Stage, path: Sdf.Path, skel, order: np.ndarray) -> UsdSkel.Skeleton:
    """The Skeleton prim with the bones in ``order`` (parents first)."""
    usd_skel = UsdSkel.Skeleton.Define(stage, path)
    heads = np.asarray(skel.heads, dtype=np.float64)
    parents = np.asarray(skel.parents)
    local = heads - np.where(parents[:, None] >= 0, heads[np.maximum(parents, 0)], 0.0)
    usd_skel.CreateJointsAttr(Vt.TokenArray(_joint_paths(skel, order)))
    usd_skel.CreateJointNamesAttr(Vt.TokenArray([skel.names[j] for j in order]))
    usd_skel.CreateBindTransformsAttr(_translations(heads[order]))
    usd_skel.CreateRestTransformsAttr(_translations(local[order]))
    return usd_skel


def _define_mesh(stage: Usd.Stage, path: Sdf.Path, vertices: np.ndarray, faces: np.ndarray) -> UsdGeom.Mesh:
    mesh = UsdGeom.Mesh.Define(stage, path)
    points = np.asarray(vertices, dtype=np.float32)
    mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(points))
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(len(faces), 3, dtype=np.int32)))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(np.asarray(faces, dtype=np.int32).ravel()))
    mesh.CreateNormalsAttr(Vt.Vec3fArray.FromNumpy(vertex_normals(vertices, faces).astype(np.float32)))
    mesh.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
    mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    mesh.CreateOrientationAttr(UsdGeom.Tokens.rightHanded)
    lo, hi = points.min(axis=0), points.max(axis=0)
    mesh.CreateExtentAttr(Vt.Vec3fArray([Gf.Vec3f(*map(float, lo)), Gf.Vec3f(*map(float, hi))]))
    return mesh


def _bind_skin(mesh: UsdGeom.Mesh, usd_skel: UsdSkel.Skeleton, joints: np.ndarray, weights: np.ndarray, slot) -> None:
    """Bind ``mesh`` to the skeleton with (n, k) rig joints/weights; ``slot[rig joint]`` is its USD joint index."""
    k = max(joints.shape[1], SKIN_SLOTS)
    j, w = skin_slots(np.where(joints >= 0, slot[np.maximum(joints, 0)], -1), weights, n_slots=k)
    binding = UsdSkel.BindingAPI.Apply(mesh.GetPrim())
    binding.CreateSkeletonRel().SetTargets([usd_skel.GetPath()])
    binding.CreateJointIndicesPrimvar(False, k).Set(Vt.IntArray.FromNumpy(j.astype(np.int32).ravel()))
    binding.CreateJointWeightsPrimvar(False, k).Set(Vt.FloatArray.FromNumpy(w.astype(np.float32).ravel()))


def _material(stage: Usd.Stage, path: Sdf.Path, rgb) -> UsdShade.Material:
    material = UsdShade.Material.Define(stage, path)
    shader = UsdShade.Shader.Define(stage, path.AppendChild("PreviewSurface"))
    shader.CreateIdAttr("UsdPreviewSurface")
    shader.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).Set(Gf.Vec3f(*map(float, rgb)))
    shader.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(0.9)
    shader.CreateInput("metallic", Sdf.ValueTypeNames.Float).Set(0.0)
    material.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
    return material


def _bind_material(prim: Usd.Prim, material: UsdShade.Material) -> None:
    UsdShade.MaterialBindingAPI.Apply(prim).Bind(material)


def _garment_mesh(stage: Usd.Stage, root: Sdf.Path, garment, colours) -> UsdGeom.Mesh:
    """The welded garment mesh with its UVs, a GeomSubset and a material per cut piece."""
    wv, wf = garment.welded()
    mesh = _define_mesh(stage, root.AppendChild("Garment"), wv, wf)
    mesh.CreateDoubleSidedAttr(True)
    st = UsdGeom.PrimvarsAPI(mesh).CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.faceVarying)
    fabric = fabric_uv(garment.uv, garment.faces, garment.instance)
    st.Set(Vt.Vec2fArray.FromNumpy(texcoords_bottom_left(fabric).astype(np.float32)))
    st.SetIndices(Vt.IntArray.FromNumpy(np.asarray(garment.faces, dtype=np.int32).ravel()))
    piece_of_face = garment.instance[garment.faces[:, 0]]
    looks = UsdGeom.Scope.Define(stage, root.AppendChild("Looks").AppendChild("Garment")).GetPath()
    for i, (name, ident) in enumerate(zip(garment.instance_names, _identifiers(garment.instance_names), strict=True)):
        faces = np.flatnonzero(piece_of_face == i)
        if len(faces) == 0:
            continue
        subset = UsdGeom.Subset.Define(stage, mesh.GetPath().AppendChild(ident))
        subset.CreateElementTypeAttr(UsdGeom.Tokens.face)
        subset.CreateFamilyNameAttr(UsdShade.Tokens.materialBind)
        subset.CreateIndicesAttr(Vt.IntArray.FromNumpy(faces.astype(np.int32)))
        subset.GetPrim().SetDisplayName(name)
        material = _material(stage, looks.AppendChild(ident), colours[i % len(colours)] / 255.0)
        material.GetPrim().SetDisplayName(name)
        _bind_material(subset.GetPrim(), material)
    UsdGeom.Subset.SetFamilyType(mesh, UsdShade.Tokens.materialBind, UsdGeom.Tokens.partition)
    return mesh


def usd_stage(garment, character=None, *, colours: np.ndarray | None = None) -> Usd.Stage:
    """An in-memory USD stage with ``character``'s body and ``garment`` (see the module notes).

    Parameters
    ----------
    garment : :class:`~patternbridge.assemble.garment.Garment`, in the character's rest pose
    character : :class:`~patternbridge.mesh.character.Character` or None (the garment alone)
    colours : (k, 3) uint8 piece colours, cycled; default ``pictures.PIECE_COLOURS``

    Returns
    -------
    pxr.Usd.Stage
        Its root layer holds everything (no sublayers, no references).
    """
    from .pictures import PIECE_COLOURS

    colours = PIECE_COLOURS if colours is None else colours
    body_skinned = character is not None and character.skeleton is not None and character.skin is not None
    garment_skinned = garment.skeleton is not None and garment.joints.shape[1] > 0
    skel = garment.skeleton if garment_skinned else (character.skeleton if body_skinned else None)
    stage = Usd.Stage.CreateInMemory()
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, METERS_PER_UNIT)
    name = character.name if character is not None else "garment"
    root = Sdf.Path.absoluteRootPath.AppendChild(_identifiers([name])[0])
    root_prim = (UsdSkel.Root if skel is not None else UsdGeom.Xform).Define(stage, root).GetPrim()
    root_prim.SetDisplayName(name)
    Usd.ModelAPI(root_prim).SetKind("component")
    stage.SetDefaultPrim(root_prim)
    UsdGeom.Scope.Define(stage, root.AppendChild("Looks"))
    usd_skel, slot = None, None
    if skel is not None:
        order = _parent_first(skel.parents)
        slot = np.argsort(order)  # rig joint -> USD joint index
        usd_skel = _define_skeleton(stage, root.AppendChild("Skeleton"), skel, order)
    if character is not None:
        body = _define_mesh(stage, root.AppendChild("Body"), character.vertices, character.faces)
        _bind_material(body.GetPrim(), _material(stage, root.AppendChild("Looks").AppendChild("Body"), _BODY_RGB))
        if body_skinned:
            _bind_skin(body, usd_skel, character.skin.bone_indices, character.skin.weights, slot)
    mesh = _garment_mesh(stage, root, garment, colours)
    if garment_skinned:
        first = np.unique(garment.weld, return_index=True)[1]  # sewn vertices carry the same weights
        _bind_skin(mesh, usd_skel, garment.joints[first], garment.weights[first], slot)
    return stage


def write_usd(path: str | os.PathLike, garment, character=None) -> None:
    """Write ``garment`` (and ``character``'s body) as a USD file, atomically.

    The format follows the suffix: ``.usda`` text, ``.usdc`` crate (``.usd``: crate).
    """
    stage = usd_stage(garment, character)
    with atomic_path(path) as tmp:
        if not stage.GetRootLayer().Export(os.fspath(tmp)):
            raise OSError(f"{path}: USD could not write the stage")
