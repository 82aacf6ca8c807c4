"""USD export: every validator usd-core registers, read back with pxr, posed with UsdSkel."""

from __future__ import annotations

import numpy as np
import pytest
from pxr import Gf, Usd, UsdGeom, UsdShade, UsdSkel, UsdValidation, Vt

from patternbridge.assemble import Garment
from patternbridge.assemble.export_obj import obj_text
from patternbridge.assemble.export_usd import write_usd
from patternbridge.mesh.character import Character, Skeleton


def _problems(stage: Usd.Stage) -> list[tuple[str, str, str]]:
    """(type, name, message) of what every registered validator reports on ``stage``."""
    validators = UsdValidation.ValidationRegistry().GetOrLoadAllValidators()
    assert len(validators) >= 25  # the core, geom, shade, skel, utils... plugins are loaded
    found = UsdValidation.ValidationContext(validators).Validate(stage)
    return [(str(e.GetType()).rsplit(".", 1)[-1], e.GetName(), e.GetMessage()) for e in found]


def _errors(stage: Usd.Stage) -> list[tuple[str, str, str]]:
    problems = _problems(stage)
    print(f"usd-core {Usd.GetVersion()}: {len(problems)} validation issues {problems[:5]}")
    return [p for p in problems if p[0] == "Error"]


@pytest.fixture(scope="module")
def dressed_usda(draped_tshirt, character_e, tmp_path_factory):
    path = tmp_path_factory.mktemp("usd") / "garment.usda"
    write_usd(path, draped_tshirt, character_e)
    return path


def _small_garment() -> Garment:
    a = np.array([[0.0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0]])
    return Garment(
        vertices=np.concatenate([a, a + [10.0, 0, 0]]),
        faces=np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]]),
        uv=np.concatenate([a[:, :2], a[:, :2] + [3.0, 0]]),
        instance=np.array([0, 0, 0, 0, 1, 1, 1, 1]),
        instance_names=("front", "sleeve~mirror"),
        weld=np.array([0, 1, 2, 3, 1, 5, 6, 2]),
        joints=np.zeros((8, 0), np.int64),
        weights=np.zeros((8, 0)),
        skeleton=None,
    )


def test_unskinned_garment_alone_passes_every_validator(tmp_path):
    path = tmp_path / "garment.usda"
    write_usd(path, _small_garment())
    stage = Usd.Stage.Open(str(path))
    assert _errors(stage) == []
    root = stage.GetDefaultPrim()
    assert root.GetTypeName() == "Xform"
    mesh = UsdGeom.Mesh(root.GetChild("Garment"))
    assert len(mesh.GetPointsAttr().Get()) == 6  # welded
    names = {s.GetPrim().GetName(): s.GetPrim().GetDisplayName() for s in UsdGeom.Subset.GetAllGeomSubsets(mesh)}
    assert names == {"front": "front", "sleeve_mirror": "sleeve~mirror"}


def test_a_character_without_a_rig_passes_every_validator(tmp_path):
    body = Character(
        vertices=[[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        faces=[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        name="bare body",
    )
    path = tmp_path / "garment.usdc"
    write_usd(path, _small_garment(), body)
    stage = Usd.Stage.Open(str(path))
    assert _errors(stage) == []
    assert stage.GetDefaultPrim().GetName() == "bare_body"
    assert not stage.GetDefaultPrim().GetChild("Body").HasAPI(UsdSkel.BindingAPI)


@pytest.mark.shared
def test_validators_see_a_subset_family_without_its_type(dressed_usda):
    stage = Usd.Stage.Open(str(dressed_usda))
    stage.GetDefaultPrim().GetChild("Garment").RemoveProperty("subsetFamily:materialBind:familyType")
    assert any(p[0] == "Error" and p[1] == "InvalidFamilyType" for p in _problems(stage))


@pytest.mark.shared
def test_dressed_stage_passes_every_registered_validator(dressed_usda):
    assert _errors(Usd.Stage.Open(str(dressed_usda))) == []


@pytest.mark.shared
def test_units_axes_and_the_body(dressed_usda, character_e):
    stage = Usd.Stage.Open(str(dressed_usda))
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y
    mpu = UsdGeom.GetStageMetersPerUnit(stage)
    assert mpu == 0.01
    root = stage.GetDefaultPrim()
    assert root.IsA(UsdSkel.Root)
    box = UsdGeom.BBoxCache(Usd.TimeCode.Default(), [UsdGeom.Tokens.default_]).ComputeWorldBound(root.GetChild("Body"))
    size = box.ComputeAlignedRange().GetSize()
    assert size[1] * mpu == pytest.approx(1.778, abs=0.005)  # E stands 177.8 cm tall
    body = UsdGeom.Mesh(root.GetChild("Body"))
    np.testing.assert_allclose(np.array(body.GetPointsAttr().Get()), character_e.vertices, atol=1e-4)
    assert UsdShade.MaterialBindingAPI(body.GetPrim()).ComputeBoundMaterial()[0]


@pytest.mark.shared
def test_garment_surface_uvs_and_pieces_read_back(dressed_usda, draped_tshirt):
    g = draped_tshirt
    stage = Usd.Stage.Open(str(dressed_usda))
    mesh = UsdGeom.Mesh(stage.GetDefaultPrim().GetChild("Garment"))
    points = np.array(mesh.GetPointsAttr().Get())
    corners = np.array(mesh.GetFaceVertexIndicesAttr().Get()).reshape(-1, 3)
    assert set(mesh.GetFaceVertexCountsAttr().Get()) == {3}
    # the same triangles as the garment's, over welded points
    np.testing.assert_allclose(points[corners], g.vertices[g.faces], atol=1e-4)
    assert len(points) == len(np.unique(g.weld))
    assert mesh.GetSubdivisionSchemeAttr().Get() == UsdGeom.Tokens.none
    # st per face corner: the same numbers as the OBJ's vt (both have the origin bottom-left)
    st = UsdGeom.PrimvarsAPI(mesh).GetPrimvar("st")
    assert st.GetInterpolation() == UsdGeom.Tokens.faceVarying
    obj, _ = obj_text(g)
    vt = np.array([ln.split()[1:] for ln in obj.splitlines() if ln.startswith("vt ")], dtype=np.float64)
    obj_corners = [[int(c.split("/")[1]) - 1 for c in ln.split()[1:]] for ln in obj.splitlines() if ln.startswith("f ")]
    np.testing.assert_allclose(np.array(st.ComputeFlattened()), vt[np.array(obj_corners).ravel()], atol=1e-6)
    # one GeomSubset per cut piece, partitioning the faces, each with its material
    subsets = UsdGeom.Subset.GetGeomSubsets(mesh, UsdGeom.Tokens.face, UsdShade.Tokens.materialBind)
    assert UsdGeom.Subset.ValidateFamily(mesh, UsdGeom.Tokens.face, UsdShade.Tokens.materialBind)[0]
    assert [s.GetPrim().GetDisplayName() for s in subsets] == list(g.instance_names)
    piece_of_face = g.instance[g.faces[:, 0]]
    for i, subset in enumerate(subsets):
        np.testing.assert_array_equal(subset.GetIndicesAttr().Get(), np.flatnonzero(piece_of_face == i))
        material = UsdShade.MaterialBindingAPI(subset.GetPrim()).GetDirectBinding().GetMaterial()
        assert material.GetPrim().GetDisplayName() == g.instance_names[i]


def _pose(skel: UsdSkel.Skeleton, joint: str, angle_deg: float) -> Vt.Matrix4dArray:
    """Skinning transforms with ``joint`` turned about the z axis at its head (row vectors, as USD)."""
    names = list(skel.GetJointNamesAttr().Get())
    topology = UsdSkel.Topology(skel.GetJointsAttr().Get())
    parents = np.array(topology.GetParentIndices())
    local = np.array(skel.GetRestTransformsAttr().Get())
    bind = np.array(skel.GetBindTransformsAttr().Get())
    turn = np.eye(4)
    turn[:3, :3] = np.array(Gf.Matrix3d(Gf.Rotation(Gf.Vec3d(0, 0, 1), angle_deg)))
    k = names.index(joint)
    local[k] = turn @ local[k]
    world = np.zeros_like(local)
    for j, p in enumerate(parents):  # parents come first
        world[j] = local[j] if p < 0 else local[j] @ world[p]
    return Vt.Matrix4dArray.FromNumpy(np.linalg.inv(bind) @ world)


def _skinned(cache: UsdSkel.Cache, prim: Usd.Prim, xforms: Vt.Matrix4dArray) -> np.ndarray:
    query = cache.GetSkinningQuery(prim)
    assert query and query.HasJointInfluences()
    points = UsdGeom.Mesh(prim).GetPointsAttr().Get()
    assert query.ComputeSkinnedPoints(xforms, points, Usd.TimeCode.Default())
    return np.array(points, dtype=np.float64)


@pytest.mark.shared
def test_posing_the_right_upper_arm_moves_the_right_sleeve_and_not_the_hem(dressed_usda):
    stage = Usd.Stage.Open(str(dressed_usda))
    root = stage.GetDefaultPrim()
    cache = UsdSkel.Cache()
    cache.Populate(UsdSkel.Root(root), Usd.PrimDefaultPredicate)
    skel = UsdSkel.Skeleton(root.GetChild("Skeleton"))
    assert cache.GetSkelQuery(skel).GetTopology().Validate()[0]
    garment = root.GetChild("Garment")
    rest = np.array(UsdGeom.Mesh(garment).GetPointsAttr().Get(), dtype=np.float64)
    rest_xforms = Vt.Matrix4dArray.FromNumpy(np.tile(np.eye(4), (len(skel.GetJointsAttr().Get()), 1, 1)))
    np.testing.assert_allclose(_skinned(cache, garment, rest_xforms), rest, atol=1e-4)
    raised = _skinned(cache, garment, _pose(skel, "upperarm01.R", 60.0)) - rest
    faces = np.array(UsdGeom.Mesh(garment).GetFaceVertexIndicesAttr().Get()).reshape(-1, 3)
    piece = {
        s.GetPrim().GetDisplayName(): np.unique(faces[np.array(s.GetIndicesAttr().Get())])
        for s in UsdGeom.Subset.GetAllGeomSubsets(UsdGeom.Mesh(garment))
    }
    moved = np.linalg.norm(raised, axis=1)
    right, left = sorted(("sleeve", "sleeve~mirror"), key=lambda n: rest[piece[n], 0].mean())  # right is -x
    assert np.median(moved[piece[right]]) > 5.0  # cm
    assert moved[piece[left]].max() < 0.01
    front = piece["front"]
    hem = front[rest[front, 1] < rest[front, 1].min() + 3.0]
    assert len(hem) > 5 and moved[hem].max() < 0.01
    # the body's right hand goes with the arm
    body = root.GetChild("Body")
    body_rest = np.array(UsdGeom.Mesh(body).GetPointsAttr().Get(), dtype=np.float64)
    body_moved = np.linalg.norm(_skinned(cache, body, _pose(skel, "upperarm01.R", 60.0)) - body_rest, axis=1)
    hand = body_rest[:, 0] < body_rest[:, 0].min() + 5.0
    assert body_moved[hand].min() > 10.0


@pytest.mark.shared
def test_same_inputs_same_bytes(draped_tshirt, character_e, tmp_path):
    for suffix in ("usda", "usdc"):
        write_usd(tmp_path / f"a.{suffix}", draped_tshirt, character_e)
        write_usd(tmp_path / f"b.{suffix}", draped_tshirt, character_e)
        assert (tmp_path / f"a.{suffix}").read_bytes() == (tmp_path / f"b.{suffix}").read_bytes()
    assert (tmp_path / "a.usdc").read_bytes()[:8] == b"PXR-USDC"
    assert (tmp_path / "a.usda").read_text().startswith("#usda 1.0")
    assert not list(tmp_path.glob(".*"))  # no temporary file left behind


def _rigged_garment(names, parents, heads) -> Garment:
    g = _small_garment()
    skel = Skeleton(names=names, parents=parents, heads=heads, tails=np.asarray(heads) + [0.0, 1, 0])
    return Garment(
        vertices=g.vertices,
        faces=g.faces,
        uv=g.uv,
        instance=g.instance,
        instance_names=g.instance_names,
        weld=g.weld,
        joints=np.array([[0, -1]] * 4 + [[1, 2]] * 4),
        weights=np.array([[1.0, 0]] * 4 + [[0.25, 0.75]] * 4),
        skeleton=skel,
    )


def test_a_rig_listing_children_before_parents_is_written_parents_first(tmp_path):
    # bones: hand (child of arm), arm (child of root), root
    g = _rigged_garment(("hand", "arm", "root"), [1, 2, -1], [[20.0, 10, 0], [10, 10, 0], [0, 0, 0]])
    write_usd(tmp_path / "g.usda", g)
    stage = Usd.Stage.Open(str(tmp_path / "g.usda"))
    assert _errors(stage) == []
    skel = UsdSkel.Skeleton(stage.GetDefaultPrim().GetChild("Skeleton"))
    assert list(skel.GetJointsAttr().Get()) == ["root", "root/arm", "root/arm/hand"]
    assert UsdSkel.Topology(skel.GetJointsAttr().Get()).Validate()[0]
    names = np.array(skel.GetJointNamesAttr().Get())
    bind = np.array(skel.GetBindTransformsAttr().Get())
    np.testing.assert_allclose(bind[list(names).index("hand"), 3, :3], [20.0, 10, 0])
    binding = UsdSkel.BindingAPI(stage.GetDefaultPrim().GetChild("Garment"))
    joints = np.array(binding.GetJointIndicesPrimvar().Get()).reshape(-1, 4)
    weights = np.array(binding.GetJointWeightsPrimvar().Get()).reshape(-1, 4)
    # welded points 0..3 are the front's (all on "hand"), 4 and 5 the back's free corners (arm 1/4, root 3/4)
    assert [names[j[w > 0]].tolist() for j, w in zip(joints, weights, strict=True)] == [["hand"]] * 4 + [
        ["arm", "root"]
    ] * 2


def test_a_rig_with_a_cycle_is_refused_and_nothing_is_written(tmp_path):
    g = _rigged_garment(("a", "b"), [1, 0], [[0.0, 0, 0], [0, 1, 0]])
    with pytest.raises(ValueError, match="cycle"):
        write_usd(tmp_path / "x.usda", g)
    assert not list(tmp_path.iterdir())
