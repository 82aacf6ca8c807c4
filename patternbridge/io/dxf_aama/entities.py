"""Entity meaning: what each entity of a piece BLOCK is, by layer and type, in file units.

The middle layer of the reader (ezdxf's ``entities``): it turns the checked
entities of one block (:mod:`.tags`) into a :class:`RawBlock`: the layer-1
boundary segments, turn and curve points (2/3), ``# n`` rule texts on any
layer, notches (POINTs on 4/80-83, legacy short LINEs on 4), grade reference,
mirror and grain lines (5/6/7), internal lines (8), cutouts (11), drill holes
(13), sew lines (14), annotations and the piece system text. Validation curves
(84-87) and ATTDEF notch links are counted; other layers are listed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .layers import NOTCH_LAYERS, VALIDATION_LAYERS, Layer
from .tags import Block, Entity
from .text import parse_rule_text, split_key

__all__ = ["RawBlock", "raw_block"]


@dataclass(slots=True)
class RawBlock:
    """A block's content in file units, before units and nest handling."""

    name: str
    text: dict[str, str]
    text_order: list[tuple[str, str]]
    boundary: list[tuple[np.ndarray, bool]]  # segments (k, 2), closed flag
    turn: np.ndarray
    curve: np.ndarray
    rule_texts: list[tuple[float, float, str, int | None]]  # x, y, id, layer
    notches: list[tuple[int, np.ndarray, float, float, float | None, np.ndarray | None]]
    lines: dict[int, list[np.ndarray]]  # layer 5/6/7 -> (2, 2) lines
    internal: list[tuple[np.ndarray, bool]]
    cutouts: list[tuple[np.ndarray, bool]]
    sew: list[tuple[np.ndarray, bool]]
    drills: list[tuple[np.ndarray, float]]
    texts: list[tuple[int, str, np.ndarray, float, float]]  # layer, text, pos, height, angle_deg
    validation: int
    other_layers: set
    attdefs: int
    attdef_texts: list[tuple[np.ndarray, np.ndarray, str]]  # ATTDEF anchor (10/20), notch (11/21), text


def raw_block(block: Block) -> RawBlock:
    """The meaning of every entity of ``block`` (file units, file order kept)."""
    raw = RawBlock(
        name=block.name, text={}, text_order=[], boundary=[], turn=np.zeros((0, 2)), curve=np.zeros((0, 2)),
        rule_texts=[], notches=[], lines={5: [], 6: [], 7: []}, internal=[], cutouts=[], sew=[], drills=[],
        texts=[], validation=0, other_layers=set(), attdefs=0, attdef_texts=[],
    )
    turn: list[np.ndarray] = []
    curve: list[np.ndarray] = []
    for ent in block.entities:
        t = ent.type
        if t == "ATTDEF":
            raw.attdefs += 1
            raw.attdef_texts.append((np.array([ent.f(10), ent.f(20)]), np.array([ent.f(11), ent.f(21)]),
                                     ent.tags.get(1, "")))
        elif ent.layer in VALIDATION_LAYERS:
            _validation(raw, ent)
        elif t in ("TEXT", "MTEXT"):
            _text(raw, ent)
        elif t in ("POLYLINE", "LINE"):
            _polyline(raw, ent)
        elif t == "POINT":
            _point(raw, ent, turn, curve)
        elif t not in ("SEQEND", "VERTEX"):
            raw.other_layers.add(f"{ent.layer_name} ({t})")
    raw.turn = np.array(turn, dtype=np.float64).reshape(-1, 2)
    raw.curve = np.array(curve, dtype=np.float64).reshape(-1, 2)
    return raw


def _validation(raw: RawBlock, ent: Entity) -> None:
    if ent.type in ("POLYLINE", "LINE"):
        raw.validation += 1
    rid = parse_rule_text(ent.tags.get(1, "")) if ent.type == "TEXT" else None
    if rid is not None:
        raw.rule_texts.append((ent.f(10), ent.f(20), rid[0], ent.layer))


def _text(raw: RawBlock, ent: Entity) -> None:
    s = ent.tags.get(1, "")
    pos = np.array([ent.f(10), ent.f(20)])
    rid = parse_rule_text(s)
    if rid is not None:
        raw.rule_texts.append((pos[0], pos[1], rid[0], ent.layer))
        return
    if ent.layer == Layer.BOUNDARY:
        kv = split_key(s)
        if kv is not None:
            raw.text.setdefault(kv[0], kv[1])
            raw.text_order.append(kv)
            return
    raw.texts.append((ent.layer if ent.layer is not None else 0, s, pos, ent.f(40), ent.f(50)))


def _polyline(raw: RawBlock, ent: Entity) -> None:
    layer = ent.layer
    if ent.type == "LINE":
        pts = np.array([[ent.f(10), ent.f(20)], [ent.f(11), ent.f(21)]])
        closed = False
    else:
        pts = np.array(ent.vertices, dtype=np.float64).reshape(-1, 2)
        closed = ent.closed
    if layer == Layer.BOUNDARY:
        if len(pts):
            raw.boundary.append((pts, closed))
    elif layer in (5, 6, 7):
        if len(pts) >= 2:
            raw.lines[layer].append(pts[[0, -1]])
    elif layer == Layer.INTERNAL:
        raw.internal.append((pts, closed))
    elif layer == Layer.CUTOUT:
        raw.cutouts.append((pts, True))
    elif layer == Layer.SEW:
        raw.sew.append((pts, closed))
    elif layer in NOTCH_LAYERS and len(pts) >= 2:
        raw.notches.append((layer, pts[0], 0.0, 0.0, None, pts[-1]))
    else:
        raw.other_layers.add(ent.layer_name)


def _point(raw: RawBlock, ent: Entity, turn: list, curve: list) -> None:
    pos = np.array([ent.f(10), ent.f(20)])
    layer = ent.layer
    if layer == Layer.TURN_POINTS:
        turn.append(pos)
    elif layer == Layer.CURVE_POINTS:
        curve.append(pos)
    elif layer in NOTCH_LAYERS:
        raw.notches.append((layer, pos, abs(ent.f(30)), abs(ent.f(39)), ent.f(50, None), None))
    elif layer == Layer.DRILL:
        raw.drills.append((pos, abs(ent.f(30))))
    else:
        raw.other_layers.add(ent.layer_name)
