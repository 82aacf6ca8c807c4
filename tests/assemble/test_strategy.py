"""The dressing strategy is chosen from the placement data, and the phases it plans run in a stated order."""

from __future__ import annotations

import ast
import dataclasses
import itertools
from pathlib import Path

import pytest

import patternbridge.assemble as assemble_pkg
from patternbridge.assemble.phases import PoseKeyframe, Settle, Sew, plan_phases
from patternbridge.assemble.strategy import Dressing, Strategy, choose_strategy, piece_parts
from patternbridge.library import load_garment
from patternbridge.pattern.model import BodyPart, Placement, Role, Side


@pytest.mark.parametrize(
    ("garment", "kind"),
    [
        ("shirt", Dressing.TOP),
        ("tshirt", Dressing.TOP),
        ("dress", Dressing.TOP),
        ("skirt", Dressing.TOP),
        ("trousers", Dressing.LEGS),
        ("shorts", Dressing.LEGS),
    ],
)
def test_library_garments_get_the_strategy_of_the_parts_they_sit_on(garment, kind):
    assert choose_strategy(load_garment(garment)).kind is kind


def test_a_garment_on_the_arms_and_the_legs_is_dressed_across_both():
    trousers, shirt = load_garment("trousers"), load_garment("shirt")
    sleeve = next(p for p in shirt.pieces if p.placement.body_part is BodyPart.RIGHT_ARM)
    suit = dataclasses.replace(trousers, pieces=(*trousers.pieces, sleeve))
    assert {BodyPart.LEFT_ARM, BodyPart.RIGHT_ARM, BodyPart.LEFT_LEG} <= piece_parts(suit)
    s = choose_strategy(suit)
    assert s.kind is Dressing.ACROSS
    assert s.raise_arms and s.pin_far_from_open_seams and not s.fill_between_thighs


def test_moving_a_piece_changes_the_strategy_not_its_name():
    """Data decides: the same pieces re-placed from the legs to the torso make a top."""
    shorts = load_garment("shorts")
    moved = dataclasses.replace(
        shorts,
        pieces=tuple(
            dataclasses.replace(p, placement=dataclasses.replace(p.placement, body_part=BodyPart.TORSO))
            for p in shorts.pieces
        ),
    )
    assert choose_strategy(shorts).kind is Dressing.LEGS
    assert choose_strategy(moved).kind is Dressing.TOP


def test_a_top_in_the_dressing_pose_sews_then_lowers_the_arms_over_keyframes():
    phases = plan_phases(Strategy.of(Dressing.TOP), posed=True, steps=160)
    sew, keys = phases[0], phases[1:]
    assert isinstance(sew, Sew) and sew.open_arm_seams and not sew.pin and sew.arm_inertia > 1.0
    assert all(isinstance(k, PoseKeyframe) for k in keys)
    assert keys[0].share_from == 1.0 and keys[-1].share_to == 0.0
    assert all(a.share_to == b.share_from for a, b in itertools.pairwise(keys))
    assert all(a.sew_to == b.sew_from for a, b in itertools.pairwise(keys))
    assert keys[-1].sew_to == 1.0  # the seams left open are closed by the end


def test_without_a_dressing_pose_every_strategy_sews_then_settles_within_the_budget():
    for kind in Dressing:
        phases = plan_phases(Strategy.of(kind), posed=False, steps=100)
        assert [type(p) for p in phases] == [Sew, Settle]
        assert sum(p.steps for p in phases) == 100
        assert phases[1].hold == Strategy.of(kind).hold_after_sewing


def test_phases_are_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        Sew(steps=3).steps = 4  # type: ignore[misc]


def _named_strings() -> set[str]:
    vocab = {str(v) for enum in (BodyPart, Side, Role) for v in enum}
    return vocab | {"leg", "arm", "_leg", "_arm", "sleeve", "cuff", "collar", "yoke", "waistband"}


def test_assemble_tests_no_piece_name_body_part_string_or_garment_type():
    """No comparison, membership or prefix test in assemble/ against a body-part, side, role or piece word."""
    words = _named_strings() | {p.name for g in ("shirt", "trousers", "dress") for p in load_garment(g).pieces}
    words |= {"shirt", "trousers", "shorts", "skirt", "tshirt"}
    found = []
    for path in sorted(Path(assemble_pkg.__file__).parent.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            consts = []
            if isinstance(node, ast.Compare):
                consts = [n for n in (node.left, *node.comparators) if isinstance(n, ast.Constant)]
            elif isinstance(node, ast.Call) and getattr(node.func, "attr", "") in ("endswith", "startswith"):
                consts = [a for a in node.args if isinstance(a, ast.Constant)]
            found += [f"{path.name}:{c.lineno} {c.value!r}" for c in consts if c.value in words]
    assert found == []


def test_the_vocabulary_check_catches_a_string_test():
    tree = ast.parse('part = "left_leg"\nok = "leg" in str(part)\n')
    hits = [n for n in ast.walk(tree) if isinstance(n, ast.Compare) and n.left.value in _named_strings()]
    assert len(hits) == 1
    assert Placement(body_part="left_leg", side="front", anchor="a", anchor_mark="m").body_part is BodyPart.LEFT_LEG
