"""Our DXF lays pieces out side by side, as pattern CAD does: rendered with ezdxf's drawing add-on, no two overlap.

The geometry is taken from the rendering itself: every INSERT's virtual
entities (ezdxf applies the INSERT position as a CAD would), one polygon per
piece and size; polygons of different pieces must not overlap, the sizes of
one piece of a nest stack on each other (AccuMark's layout).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from patternbridge.io.dxf_aama import read_dxf, write_dxf

pytestmark = pytest.mark.shared

ezdxf = pytest.importorskip("ezdxf")
shapely = pytest.importorskip("shapely")

FILES = ["GMX1016S18_ASTM.DXF", "annotation.DXF", "clo-pattern.dxf", "simple.DXF"]


def rendered_pieces(path: Path) -> list[tuple[str, object]]:
    """(block name, shapely polygon) of every layer-1 boundary as placed by its INSERT."""
    from shapely.geometry import Polygon

    doc = ezdxf.readfile(path)
    out = []
    for insert in doc.modelspace().query("INSERT"):
        for entity in insert.virtual_entities():
            if entity.dxftype() == "POLYLINE" and entity.dxf.layer == "1":
                pts = [(v.dxf.location.x, v.dxf.location.y) for v in entity.vertices]
                out.append((insert.dxf.name, Polygon(pts)))
    return out


def render_png(path: Path, png: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from ezdxf.addons.drawing import Frontend, RenderContext
    from ezdxf.addons.drawing.matplotlib import MatplotlibBackend

    doc = ezdxf.readfile(path)
    fig = plt.figure(figsize=(8, 5))
    ax = fig.add_axes([0, 0, 1, 1])
    Frontend(RenderContext(doc), MatplotlibBackend(ax)).draw_layout(doc.modelspace(), finalize=True)
    fig.savefig(png, dpi=80)
    plt.close(fig)


@pytest.mark.parametrize("form", ["sample", "all"])
@pytest.mark.parametrize("name", FILES)
def test_rendered_pieces_do_not_overlap(aama_dir, tmp_path, name, form):
    pattern, _ = read_dxf(aama_dir / name)
    out = tmp_path / "layout.dxf"
    write_dxf(pattern, out, flavor="astm", sizes=form)
    pieces = rendered_pieces(out)
    blocks_per_piece = 1 if form == "sample" else len(pattern.sizes)
    assert len(pieces) == len(pattern.pieces) * blocks_per_piece
    owner = {}
    for block, poly in pieces:
        owner.setdefault(block.rsplit("_", 1)[0], []).append(poly)
    assert len(owner) == len(pattern.pieces)
    from shapely.ops import unary_union

    shapes = [unary_union(polys) for polys in owner.values()]
    for i in range(len(shapes)):
        for j in range(i + 1, len(shapes)):
            assert shapes[i].intersection(shapes[j]).area == 0.0, (name, i, j)
    if form == "all":  # the sizes of one piece are stacked where the source drew them, not spread
        for polys in owner.values():
            assert all(p.intersects(polys[0]) for p in polys)


def test_layout_renders_to_png(aama_dir, tmp_path):
    pytest.importorskip("matplotlib")
    pattern, _ = read_dxf(aama_dir / "GMX1016S18_ASTM.DXF")
    out = tmp_path / "layout.dxf"
    write_dxf(pattern, out, flavor="astm", sizes="all")
    png = tmp_path / "layout.png"
    render_png(out, png)
    assert png.stat().st_size > 10_000
