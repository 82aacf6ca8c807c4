"""Headless software renderer: shaded meshes with 3D polylines and labels, in numpy.

Orthographic cameras look at the character from the front (+Z, its left on
the picture's right), the back (-Z) or its left side (+X). Triangles are
rasterised into a z-buffer at twice the output resolution (the supersampling
smooths the edges), shaded per pixel with interpolated vertex normals
(Lambert + ambient) and the per-face colour. Polylines are depth-tested
against the surface, so the parts hidden behind the body are not drawn, then
drawn with Pillow together with their labels.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["VIEWS", "render", "render_views", "save_png"]

#: view name -> (screen right, screen up, toward the viewer), rest frame +Y up
VIEWS: dict[str, tuple[tuple[float, float, float], ...]] = {
    "front": ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
    "back": ((-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0)),
    "side": ((0.0, 0.0, -1.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0)),
    "right": ((0.0, 0.0, 1.0), (0.0, 1.0, 0.0), (-1.0, 0.0, 0.0)),
    "top": ((1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0)),
}

_PALETTE = np.array(
    [
        (214, 39, 40),
        (31, 119, 180),
        (44, 160, 44),
        (255, 127, 14),
        (148, 103, 189),
        (140, 86, 75),
        (227, 119, 194),
        (23, 190, 207),
        (188, 189, 34),
        (127, 127, 127),
    ],
    dtype=np.uint8,
)
_SKIN = np.array([222.0, 196.0, 178.0])


def _camera(view: str, up: int) -> np.ndarray:
    if view not in VIEWS:
        raise ValueError(f"view: expected one of {sorted(VIEWS)}, got {view!r}")
    basis = np.array(VIEWS[view], dtype=np.float64)
    if up == 2:  # Z-up data: express the basis in (x, y, z) with z up, facing -y
        basis = basis[:, [0, 2, 1]] * np.array([1.0, -1.0, 1.0])
    elif up != 1:
        raise ValueError(f"up: expected 1 (Y) or 2 (Z), got {up!r}")
    return basis


def _vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    tri = vertices[faces]
    fn = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    idx = faces.ravel()
    w = np.repeat(fn, 3, axis=0)
    vn = np.column_stack([np.bincount(idx, weights=w[:, k], minlength=len(vertices)) for k in range(3)])
    norm = np.linalg.norm(vn, axis=1, keepdims=True)
    return vn / np.where(norm > 0, norm, 1.0)


def _rasterise(p: np.ndarray, faces: np.ndarray, width: int, height: int):
    """Z-buffer: per pixel the nearest face id (-1 = background) and its depth.

    p : (V, 3) screen coordinates (x px, y px down, depth: larger = nearer).
    """
    n_pix = width * height
    zbuf = np.full(n_pix, -np.inf)
    fbuf = np.full(n_pix, -1, dtype=np.int64)
    tri = p[faces]  # (F, 3, 3)
    zmin = float(p[:, 2].min())
    zscale = 0.999 / max(float(p[:, 2].max()) - zmin, 1e-12)
    lo = np.floor(tri[:, :, :2].min(axis=1) - 0.5).astype(np.int64) + 1
    hi = np.floor(tri[:, :, :2].max(axis=1) - 0.5).astype(np.int64)
    lo = np.maximum(lo, 0)
    hi[:, 0] = np.minimum(hi[:, 0], width - 1)
    hi[:, 1] = np.minimum(hi[:, 1], height - 1)
    size = hi - lo + 1
    ok = (size[:, 0] > 0) & (size[:, 1] > 0)
    # signed area, skip degenerate triangles
    x0, y0 = tri[:, 0, 0], tri[:, 0, 1]
    x1, y1 = tri[:, 1, 0], tri[:, 1, 1]
    x2, y2 = tri[:, 2, 0], tri[:, 2, 1]
    area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    ok &= np.abs(area) > 1e-12
    # bucket triangles by the power-of-two size of their bounding box
    bw = 1 << np.ceil(np.log2(np.maximum(size[:, 0], 1))).astype(np.int64)
    bh = 1 << np.ceil(np.log2(np.maximum(size[:, 1], 1))).astype(np.int64)
    keys = bw * 100003 + bh
    for key in np.unique(keys[ok]):
        sel = np.flatnonzero(ok & (keys == key))
        w_b, h_b = int(key // 100003), int(key % 100003)
        chunk = max(1, 4_000_000 // (w_b * h_b))
        ox, oy = np.meshgrid(np.arange(w_b), np.arange(h_b))
        ox, oy = ox.ravel(), oy.ravel()
        for start in range(0, len(sel), chunk):
            f = sel[start : start + chunk]
            px = lo[f, 0][:, None] + ox[None]
            py = lo[f, 1][:, None] + oy[None]
            cx, cy = px + 0.5, py + 0.5
            a = area[f][:, None]
            w0 = ((x1[f][:, None] - cx) * (y2[f][:, None] - cy) - (x2[f][:, None] - cx) * (y1[f][:, None] - cy)) / a
            w1 = ((x2[f][:, None] - cx) * (y0[f][:, None] - cy) - (x0[f][:, None] - cx) * (y2[f][:, None] - cy)) / a
            w2 = 1.0 - w0 - w1
            inside = (
                (w0 >= -1e-9) & (w1 >= -1e-9) & (w2 >= -1e-9) & (px <= hi[f, 0][:, None]) & (py <= hi[f, 1][:, None])
            )
            if not inside.any():
                continue
            z = w0 * tri[f, 0, 2][:, None] + w1 * tri[f, 1, 2][:, None] + w2 * tri[f, 2, 2][:, None]
            rows, cols = np.nonzero(inside)
            pix = py[rows, cols] * width + px[rows, cols]
            depth = z[rows, cols]
            face = f[rows]
            # one float key: pixel index, then nearer first (depth scaled into [0, 1))
            dn = (depth - zmin) * zscale
            order = np.argsort(pix - dn)
            pix, depth, face = pix[order], depth[order], face[order]
            first = np.ones(pix.size, dtype=bool)
            first[1:] = pix[1:] != pix[:-1]
            pix, depth, face = pix[first], depth[first], face[first]
            better = depth > zbuf[pix]
            zbuf[pix[better]] = depth[better]
            fbuf[pix[better]] = face[better]
    return fbuf, zbuf


def _font(size: int):
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow < 10.1
        return ImageFont.load_default()


_SS = 2  # supersampling factor: the picture is drawn at twice its size, then reduced
_MARGIN = 0.06  # blank border, as a fraction of the picture
_LIGHT = np.array([-0.35, 0.45, 1.0])
_DENSIFY_CM = 0.5  # polylines are depth-tested at about this spacing


@dataclass(frozen=True, slots=True, kw_only=True)
class _Camera:
    """An orthographic camera framing a world box on a (width, height) px canvas.

    basis : (3, 3) rows: screen right, screen up, toward the viewer
    centre : (2,) the framed box's centre in (right, up), cm
    scale : px per cm
    """

    basis: np.ndarray
    centre: np.ndarray
    scale: float
    width: int
    height: int


def _framing_box(vertices: np.ndarray, polylines: Sequence[np.ndarray]) -> np.ndarray:
    """(2, 3) min and max corner of the mesh and the polylines together."""
    pts = [vertices] + [np.asarray(pl, dtype=np.float64).reshape(-1, 3) for pl in polylines]
    allp = np.concatenate(pts)
    return np.array([allp.min(axis=0), allp.max(axis=0)])


def _frame(basis: np.ndarray, bounds: np.ndarray, width: int, height: int) -> _Camera:
    """The camera that fits the eight corners of ``bounds`` inside the margin."""
    corners = np.array([[bounds[i][0], bounds[j][1], bounds[k][2]] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    cc = corners @ basis.T
    lo2, hi2 = cc[:, :2].min(axis=0), cc[:, :2].max(axis=0)
    span = np.maximum(hi2 - lo2, 1e-9)
    scale = min(width * (1 - 2 * _MARGIN) / span[0], height * (1 - 2 * _MARGIN) / span[1])
    return _Camera(basis=basis, centre=(lo2 + hi2) / 2, scale=scale, width=width, height=height)


def _to_screen(cam: _Camera, q: np.ndarray) -> np.ndarray:
    """(n, 3) screen coordinates of world points: x px, y px down, depth (larger = nearer)."""
    c = q @ cam.basis.T
    return np.column_stack(
        [
            cam.width / 2 + (c[:, 0] - cam.centre[0]) * cam.scale,
            cam.height / 2 - (c[:, 1] - cam.centre[1]) * cam.scale,
            c[:, 2],
        ]
    )


def _pixel_normals(
    cam: _Camera,
    screen: np.ndarray,
    vertices: np.ndarray,
    faces: np.ndarray,
    hit: np.ndarray,
    fid: np.ndarray,
) -> np.ndarray:
    """(n, 3) unit camera-space normals at the pixels ``hit`` of faces ``fid``, toward the viewer.

    The vertex normals are interpolated barycentrically at the pixel centres;
    a normal facing away is flipped (two-sided lighting).
    """
    tri = screen[faces[fid]]
    cx = (hit % cam.width) + 0.5
    cy = (hit // cam.width) + 0.5
    x0, y0 = tri[:, 0, 0], tri[:, 0, 1]
    x1, y1 = tri[:, 1, 0], tri[:, 1, 1]
    x2, y2 = tri[:, 2, 0], tri[:, 2, 1]
    a = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    w0 = ((x1 - cx) * (y2 - cy) - (x2 - cx) * (y1 - cy)) / a
    w1 = ((x2 - cx) * (y0 - cy) - (x0 - cx) * (y2 - cy)) / a
    w2 = 1.0 - w0 - w1
    vn = _vertex_normals(vertices, faces) @ cam.basis.T
    n = w0[:, None] * vn[faces[fid, 0]] + w1[:, None] * vn[faces[fid, 1]] + w2[:, None] * vn[faces[fid, 2]]
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
    n *= np.where(np.sum(n * np.array([0, 0, 1.0]), axis=1, keepdims=True) < 0, -1.0, 1.0)
    return n


def _shade(normals: np.ndarray) -> np.ndarray:
    """(n,) brightness of unit camera-space normals: ambient + Lambert + a rim toward the viewer."""
    light = _LIGHT / np.linalg.norm(_LIGHT)
    lambert = np.clip(normals @ light, 0.0, 1.0)
    rim = np.clip(normals[:, 2], 0.0, 1.0)
    return 0.28 + 0.62 * lambert + 0.10 * rim


def _base_colours(face_colors: np.ndarray | None, fid: np.ndarray) -> np.ndarray:
    """(n, 3) float64 RGB of the faces ``fid``: per face, one for all, or skin."""
    if face_colors is None:
        return np.broadcast_to(_SKIN, (fid.size, 3))
    fc = np.asarray(face_colors, dtype=np.float64)
    return np.broadcast_to(fc, (fid.size, 3)) if fc.ndim == 1 else fc[fid]


def _shaded_image(
    cam: _Camera,
    screen: np.ndarray,
    vertices: np.ndarray,
    faces: np.ndarray,
    fbuf: np.ndarray,
    face_colors: np.ndarray | None,
) -> np.ndarray:
    """(height, width, 3) uint8: the faces of the z-buffer ``fbuf`` shaded, on white."""
    image = np.full((cam.height * cam.width, 3), 255.0)
    hit = np.flatnonzero(fbuf >= 0)
    if hit.size:
        fid = fbuf[hit]
        n = _pixel_normals(cam, screen, vertices, faces, hit, fid)
        base = _base_colours(face_colors, fid)
        image[hit] = np.clip(base * _shade(n)[:, None], 0, 255)
    return image.reshape(cam.height, cam.width, 3).astype(np.uint8)


def _densify(points: np.ndarray, step: float) -> np.ndarray:
    """(m, 3) the polyline with points inserted so no segment is longer than ``step``."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    n_sub = np.maximum(1, np.ceil(seg / step).astype(np.int64))
    t = np.concatenate([np.arange(k) / k for k in n_sub])
    rep = np.repeat(np.arange(len(seg)), n_sub)
    dense = points[rep] + t[:, None] * (points[rep + 1] - points[rep])
    return np.vstack([dense, points[-1:]])


def _visible(sp: np.ndarray, zimg: np.ndarray, tolerance_cm: float) -> np.ndarray:
    """(n,) bool: screen points no farther than ``tolerance_cm`` behind the surface.

    The surface depth is the nearest in a 5x5 neighbourhood, so lines lying
    on the skin stay visible.
    """
    h, w = zimg.shape
    ix = np.clip(sp[:, 0].astype(np.int64), 0, w - 1)
    iy = np.clip(sp[:, 1].astype(np.int64), 0, h - 1)
    best = np.full(len(sp), -np.inf)
    for dy in (-2, 0, 2):
        for dx in (-2, 0, 2):
            best = np.maximum(best, zimg[np.clip(iy + dy, 0, h - 1), np.clip(ix + dx, 0, w - 1)])
    return sp[:, 2] >= best - tolerance_cm


def _visible_runs(sp: np.ndarray, visible: np.ndarray) -> list[list[tuple[float, float]]]:
    """The (x, y) runs of consecutive visible screen points, two points or more."""
    runs = []
    run: list[tuple[float, float]] = []
    for k in range(len(sp)):
        if visible[k]:
            run.append((float(sp[k, 0]), float(sp[k, 1])))
        if (not visible[k] or k == len(sp) - 1) and run:
            if len(run) > 1:
                runs.append(run)
            run = []
    return runs


def _overlaps(box: tuple[float, float, float, float], boxes) -> bool:
    x0, y0, x1, y1 = box
    return any(x0 < b[2] and x1 > b[0] and y0 < b[3] and y1 > b[1] for b in boxes)


def _label_position(
    anchor: np.ndarray,
    text_size: tuple[float, float],
    width: int,
    boxes: Sequence[tuple[float, float, float, float]],
) -> tuple[float, float]:
    """Top left of a label beside ``anchor``: right of it unless that leaves the
    picture, then nudged down until it does not overlap an earlier label."""
    tw, th = text_size
    x = float(anchor[0]) + 4 * _SS
    y = float(anchor[1]) - th / 2
    if x + tw > width - 2:
        x = float(anchor[0]) - tw - 4 * _SS
    for _ in range(12):
        if not _overlaps((x, y, x + tw, y + th), boxes):
            break
        y += th + 2 * _SS
    return x, y


def _draw_label(draw, font, text: str, anchor: np.ndarray, color, width: int, boxes: list) -> None:
    """Write ``text`` in a framed white box beside ``anchor``; append the box to ``boxes``."""
    bbox = draw.textbbox((0, 0), text, font=font)
    tw, th = bbox[2] - bbox[0], bbox[3] - bbox[1]
    x, y = _label_position(anchor, (tw, th), width, boxes)
    box = (x - 2 * _SS, y - 1 * _SS, x + tw + 2 * _SS, y + th + 2 * _SS)
    boxes.append(box)
    draw.rectangle(box, fill=(255, 255, 255), outline=color, width=_SS)
    draw.text((x - bbox[0], y - bbox[1]), text, fill=color, font=font)


def _polyline_colour(i: int, polyline_colors) -> tuple[int, ...]:
    return tuple(int(c) for c in (polyline_colors[i] if polyline_colors is not None else _PALETTE[i % len(_PALETTE)]))


def _draw_polylines(
    img,
    cam: _Camera,
    zimg: np.ndarray,
    polylines: Sequence[np.ndarray],
    labels: Sequence[str],
    polyline_colors,
    *,
    line_width_px: float,
    occlusion_tolerance_cm: float,
    label_leftmost: bool,
) -> None:
    """Draw the visible runs of each polyline and its label on ``img`` (in place)."""
    from PIL import ImageDraw

    draw = ImageDraw.Draw(img)
    font = _font(int(11 * _SS))
    lw = max(1, round(line_width_px * _SS))
    label_boxes: list[tuple[float, float, float, float]] = []
    for i, pl in enumerate(polylines):
        pts3 = np.asarray(pl, dtype=np.float64).reshape(-1, 3)
        if len(pts3) < 2:
            continue
        sp = _to_screen(cam, _densify(pts3, _DENSIFY_CM))
        visible = _visible(sp, zimg, occlusion_tolerance_cm)
        color = _polyline_colour(i, polyline_colors)
        for run in _visible_runs(sp, visible):
            draw.line(run, fill=color, width=lw, joint="curve")
        if i < len(labels) and labels[i] and visible.any():
            vis = sp[visible]
            pick = np.argmin if label_leftmost else np.argmax
            anchor = vis[pick(vis[:, 0])]
            _draw_label(draw, font, str(labels[i]), anchor, color, cam.width, label_boxes)


def render(
    vertices: np.ndarray,
    faces: np.ndarray,
    *,
    face_colors: np.ndarray | None = None,
    polylines: Sequence[np.ndarray] = (),
    labels: Sequence[str] = (),
    view: str = "front",
    size: tuple[int, int] = (800, 1000),
    up: int = 1,
    polyline_colors: Sequence[Sequence[int]] | None = None,
    line_width_px: float = 2.0,
    occlusion_tolerance_cm: float = 1.0,
    bounds: np.ndarray | None = None,
    title: str | None = None,
) -> np.ndarray:
    """Render a shaded mesh with polylines from an orthographic camera.

    Parameters
    ----------
    vertices : (V, 3) float64, cm
    faces : (F, 3) int64
    face_colors : (F, 3) uint8 RGB per face, or (3,) for all; skin tone by default
    polylines : sequence of (k, 3) float64 paths (closed curves repeat the first point)
    labels : one text per polyline (or fewer; empty strings are skipped)
    view : ``"front"``, ``"back"``, ``"side"`` (left side), ``"right"`` or ``"top"``
    size : (width, height) of the picture in pixels
    up : 1 when +Y is up, 2 when +Z is up
    polyline_colors : RGB per polyline; a 10-colour palette by default
    line_width_px : line width in output pixels
    occlusion_tolerance_cm : a polyline point farther than this behind the
        visible surface is hidden
    bounds : (2, 3) world box to frame (min, max); the mesh and polylines by default
    title : text written at the top left

    Returns
    -------
    (H, W, 3) uint8 image.
    """
    from PIL import Image, ImageDraw

    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    width, height = int(size[0]), int(size[1])
    W, H = width * _SS, height * _SS
    if bounds is None:
        bounds = _framing_box(v, polylines)
    cam = _frame(_camera(view, up), bounds, W, H)
    screen = _to_screen(cam, v)
    fbuf, zbuf = _rasterise(screen, f, W, H)
    img = Image.fromarray(_shaded_image(cam, screen, v, f, fbuf, face_colors))
    _draw_polylines(
        img,
        cam,
        zbuf.reshape(H, W),
        polylines,
        labels,
        polyline_colors,
        line_width_px=line_width_px,
        occlusion_tolerance_cm=occlusion_tolerance_cm,
        label_leftmost=view == "back",
    )
    if title:
        ImageDraw.Draw(img).text((8 * _SS, 6 * _SS), title, fill=(40, 40, 40), font=_font(int(14 * _SS)))
    img = img.resize((width, height), Image.LANCZOS)
    return np.asarray(img, dtype=np.uint8)


def render_views(
    vertices: np.ndarray,
    faces: np.ndarray,
    *,
    views: Sequence[str] = ("front", "back", "side"),
    size: tuple[int, int] = (600, 1000),
    **kwargs,
) -> np.ndarray:
    """Render several views with a common scale, side by side: (H, W·n, 3) uint8."""
    v = np.asarray(vertices, dtype=np.float64)
    polylines = kwargs.get("polylines", ())
    pts = [v] + [np.asarray(pl, dtype=np.float64).reshape(-1, 3) for pl in polylines]
    allp = np.concatenate(pts)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    # same horizontal half-width for x and z keeps one scale in every view
    c = (lo + hi) / 2
    half = (hi - lo) / 2
    up = kwargs.get("up", 1)
    horizontal = [0, 2] if up == 1 else [0, 1]
    half[horizontal] = half[horizontal].max()
    kwargs.setdefault("bounds", np.array([c - half, c + half]))
    title = kwargs.pop("title", None)
    panels = [
        render(
            v,
            faces,
            view=view,
            size=size,
            title=f"{title} - {view}" if title else view,
            **kwargs,
        )
        for view in views
    ]
    return np.concatenate(panels, axis=1)


def save_png(path: str | os.PathLike, image: np.ndarray) -> None:
    """Write an (H, W, 3) uint8 image as PNG, atomically."""
    from PIL import Image

    from ..atomic import atomic_path

    with atomic_path(path) as tmp:
        Image.fromarray(np.asarray(image, dtype=np.uint8)).save(tmp, format="PNG")
