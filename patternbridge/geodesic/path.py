"""Point-to-point geodesic paths: the public entry points.

Pipeline per path: a neighbourhood-limited Dijkstra edge path
(:mod:`.initial`), geodesic curvature flow (:mod:`.flow`), projection onto the
mesh by a face walk (:mod:`.project`), exact straightening in the unfolded
strip with swings over vertices (:mod:`.straighten`) and, optionally, tape
correction (:mod:`.tape`).
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import MeshError
from .initial import edge_paths
from .straighten import Endpoint, _Local, straighten, strip_from_vertex_path
from .surface import SurfaceMesh, SurfacePoint

__all__ = ["METHODS", "GeodesicPath", "geodesic_path", "geodesic_paths"]

log = logging.getLogger(__name__)

#: ``"lsq"``: least-squares curvature flow, projection, exact straightening;
#: ``"euler"``: the same with implicit-Euler flow; ``"exact"``: straightening
#: straight from the Dijkstra strip; ``"flow"``: the thesis method alone (flow
#: and projection, no straightening); ``"dijkstra"``: the edge path.
#: straighten the second route when its scaled edge length is within this of
#: the straightened best route
_TRY_ALT = 0.05

METHODS = ("lsq", "euler", "exact", "flow", "dijkstra")


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class GeodesicPath:
    """A path on the surface.

    points : (k, 3) float64, cm; the first and last are the end points
    faces : (k,) int64, a face each point lies on (either face for edge points)
    edges : (k, 2) int64, the edge's vertex pair for points on edges,
        (-1, -1) for vertex and face points
    length : float, cm, sum of the segment lengths of ``points``
    surface_length : float, cm, length of the path on the surface before tape
        correction (equal to ``length`` without ``tape``)
    method : str, the method that produced it
    """

    points: np.ndarray
    faces: np.ndarray
    edges: np.ndarray
    length: float
    surface_length: float
    method: str

    def __post_init__(self) -> None:
        for name in ("points", "faces", "edges"):
            getattr(self, name).flags.writeable = False


#: a face point on an edge of its face is moved this share of the way to the face's centre
_OFF_EDGE = 1e-6


def _endpoint(mesh: SurfaceMesh, p: SurfacePoint) -> tuple[Endpoint, int]:
    """The path end and the vertex its edge path starts from.

    A face point lying on (or within :data:`_OFF_EDGE` / 3 of) an edge of its
    face (a weight of 0: a plane section's point) is moved
    :data:`_OFF_EDGE` of the way into the face
    (1e-6 cm on a 1 cm face): exactly on the edge, it lay on the strip's
    first portal whenever the path left through that edge, the funnel opened
    to a straight angle there and the path was bent round a far corner (a back
    width between two section points came out 2 cm long).
    """
    if p.vertex_id is None and min(p.bary) < _OFF_EDGE / 3.0:
        b = (np.asarray(p.bary) + _OFF_EDGE / 3.0) / (1.0 + _OFF_EDGE)
        p = SurfacePoint(face=p.face, bary=tuple(b))
    xyz = mesh.point_position(p)
    if p.vertex_id is not None:
        return Endpoint(
            vertex=p.vertex_id, face=None, xyz=tuple(xyz.tolist())
        ), p.vertex_id
    k = int(np.argmax(p.bary))
    return (
        Endpoint(vertex=None, face=p.face, xyz=tuple(xyz.tolist())),
        int(mesh.faces[p.face, k]),
    )


def _polyline(points: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(points, axis=0), axis=1).sum())


def geodesic_path(
    mesh: SurfaceMesh, a, b, *, tape: bool = False, exempt=None, method: str = "lsq"
) -> GeodesicPath:
    """Geodesic path between two surface points.

    Parameters
    ----------
    mesh : SurfaceMesh
    a, b : SurfacePoint or int vertex id
    tape : bool
        Straighten concave stretches where a tape would leave the skin.
    exempt : sequence of (start, stop) fractions of the path length in [0, 1]
        (or a (k,) bool mask over the surface points) kept on the skin by the tape
        correction, e.g. a bent elbow.
    method : one of :data:`METHODS`

    Returns
    -------
    GeodesicPath

    Raises
    ------
    MeshError
        Unknown points, points on different components, unknown method.
    """
    if not isinstance(mesh, SurfaceMesh):
        raise MeshError(
            f"geodesic: expected a SurfaceMesh, got {type(mesh).__name__}; "
            "wrap the arrays with SurfaceMesh(vertices, faces)"
        )
    if method not in METHODS:
        raise MeshError(
            f"geodesic: unknown method {method!r} (expected one of "
            f"{', '.join(METHODS)}); pick a listed method"
        )
    pa = mesh.check_point(a, "from")
    pb = mesh.check_point(b, "to")
    ea, va = _endpoint(mesh, pa)
    eb, vb = _endpoint(mesh, pb)
    routes = edge_paths(mesh, va, vb, alternative=method not in ("dijkstra", "flow"))
    vpath, graph_len = routes[0]
    result = _one_route(mesh, vpath, ea, eb, method)
    if result is None:
        log.warning("no face strip around the edge path; returning the edge path")
        return geodesic_path(mesh, pa, pb, tape=tape, exempt=exempt, method="dijkstra")
    if len(routes) > 1:
        # another way around: worth straightening when its edge length, scaled
        # like the best route's, could come out shorter
        best_len = _polyline(result[0])
        alt_path, alt_len = routes[1]
        ratio = graph_len / best_len if best_len > 0 else 1.0
        if alt_len / ratio < best_len * (1.0 + _TRY_ALT):
            other = _one_route(mesh, alt_path, ea, eb, method)
            if other is not None and _polyline(other[0]) < best_len:
                result = other
    pts, fcs, eds = result
    surface_length = _polyline(pts)
    if tape and len(pts) > 2:
        from .tape import tape_correct

        normals = mesh.normals_of(fcs)
        pts = tape_correct(pts, normals, exempt=exempt)
        # tape points off the skin keep the face of the nearest surface point
        fcs, eds = _relabel(pts, result)
    return GeodesicPath(
        points=pts,
        faces=fcs,
        edges=eds,
        length=_polyline(pts),
        surface_length=surface_length,
        method=method,
    )


def _one_route(mesh: SurfaceMesh, vpath, ea: Endpoint, eb: Endpoint, method: str):
    """(points, faces, edges) of one route by ``method``; None when no strip."""
    loc = _Local.of(mesh)
    if method == "dijkstra":
        V = mesh.vertices
        pts = np.vstack([ea.xyz, V[vpath], eb.xyz])
        keep = np.ones(len(pts), dtype=bool)
        keep[1:] = np.linalg.norm(np.diff(pts, axis=0), axis=1) > 0
        indptr, fl = mesh.vertex_faces
        fcs = fl[indptr[vpath]]
        fcs = np.concatenate(
            [
                [ea.face if ea.face is not None else fcs[0]],
                fcs,
                [eb.face if eb.face is not None else fcs[-1]],
            ]
        )
        return pts[keep], fcs[keep], np.full((int(keep.sum()), 2), -1, dtype=np.int64)
    strip = None
    if method in ("lsq", "euler", "flow"):
        from .flow import flow_path
        from .project import project_walk

        fl = flow_path(
            mesh, vpath, ea, eb, scheme="euler" if method == "euler" else "lsq"
        )
        walk = project_walk(mesh, fl, ea, eb, local=loc)
        if walk is not None:
            if method == "flow":
                return walk.points, walk.faces, walk.edges
            strip = walk.strip
        else:
            log.info("projection walk failed; straightening the edge path's strip")
    if strip is None:
        strip = strip_from_vertex_path(mesh, vpath, ea.face, eb.face, local=loc)
    if strip is None:
        return None
    try:
        sp_ = straighten(mesh, strip, ea, eb, local=loc)
    except ValueError as exc:
        log.warning("straightening failed (%s)", exc)
        return None
    return sp_.points, sp_.faces, sp_.edges


def _relabel(pts: np.ndarray, result) -> tuple[np.ndarray, np.ndarray]:
    src_pts, src_f, src_e = result
    from scipy.spatial import cKDTree

    _, idx = cKDTree(src_pts).query(pts)
    same = np.linalg.norm(src_pts[idx] - pts, axis=1) < 1e-9
    eds = np.where(same[:, None], src_e[idx], -1)
    return src_f[idx].copy(), eds


def geodesic_paths(
    mesh: SurfaceMesh,
    pairs: Iterable[Sequence],
    *,
    tape: bool = False,
    method: str = "lsq",
    progress: Callable[[str, int, int], None] | None = None,
) -> list[GeodesicPath]:
    """Geodesic paths for many ``(a, b)`` pairs on one mesh (preparation shared).

    Parameters
    ----------
    mesh : SurfaceMesh
    pairs : iterable of (a, b), each a SurfacePoint or vertex id
    tape, method : as in :func:`geodesic_path`
    progress : optional ``progress(stage, done, total)`` callback

    Returns
    -------
    list of GeodesicPath, in the order of ``pairs``
    """
    pairs = list(pairs)
    out = []
    for i, (a, b) in enumerate(pairs):
        out.append(geodesic_path(mesh, a, b, tape=tape, method=method))
        if progress is not None:
            progress("geodesic", i + 1, len(pairs))
    return out
