"""The typed phases of a drape (sew, pose keyframe, settle), planned from the strategy and run in order.

A drape is a list of phases, each a frozen dataclass:

- :class:`Sew` closes the seams from their placed gaps to zero without
  gravity (optionally leaving the seams between two pieces of one arm open,
  pinning the cloth far from open seams, and making the arm pieces heavy).
- :class:`PoseKeyframe` moves the body from one share of the dressing pose
  to the next a little every cloth step (the colliders following), the cloth
  moved by the contact, its own dynamics under reduced gravity and a soft
  hold on the skin's motion near the arms, sewing the seams left open from
  ``sew_from`` to ``sew_to`` of the way.
- :class:`Settle` drapes under gravity, holding what the strategy holds.

:func:`plan_phases` turns a :class:`~patternbridge.assemble.strategy.Strategy`
into that list once; :func:`run_phases` runs it, calling
:func:`~patternbridge.assemble.drape.drape` with the arguments each phase
states and nothing else, so the call order lives here and not in the
solver's state.
"""

from __future__ import annotations

import itertools
import logging
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .strategy import Strategy

if TYPE_CHECKING:
    from .pipeline import Simulation

__all__ = [
    "POSE_ATTACH",
    "POSE_GRAVITY",
    "POSE_SEW_STAGES",
    "POSE_STAGES",
    "POSE_STEPS",
    "SEW_ARM_INERTIA",
    "SEW_SHARE",
    "Phase",
    "PoseKeyframe",
    "Settle",
    "Sew",
    "plan_phases",
    "run_phases",
]

log = logging.getLogger(__name__)

SEW_SHARE = 0.55  # share of the drape's steps spent sewing
POSE_STAGES = 5  # keyframes of the dressing pose -> rest pose return (the arms lowered step by step)
POSE_STEPS = 12  # cloth steps from one keyframe to the next (the body moves in every one)
POSE_GRAVITY = 0.3  # share of gravity while the arms come down
POSE_SEW_STAGES = 3  # keyframes over which the seams left open in the dressing pose (cuffs) close
POSE_ATTACH = 100.0  # soft hold of the cloth on the moving bones on the skin's motion, in units of its mass / h²
SEW_ARM_INERTIA = 30.0  # the arm pieces' mass multiple while a top is sewn (see pipeline.sewing_inertia)


@dataclass(frozen=True, slots=True, kw_only=True)
class Sew:
    """Close the seams from their placed gaps to zero over ``steps`` steps, without gravity.

    open_arm_seams : leave the seams between two pieces of one arm (a cuff on
        its sleeve) open; a later :class:`PoseKeyframe` sews them
    pin : hold the cloth far from the seams that start open (see
        :func:`~patternbridge.assemble.pipeline.anchor_weights`)
    arm_inertia : mass multiple of the arm pieces (1: none)
    untangle : undo the crossings of the cloth through itself while sewing (:mod:`.cloth.untangle`)
    """

    steps: int
    open_arm_seams: bool = False
    pin: bool = False
    arm_inertia: float = 1.0
    untangle: bool = False


@dataclass(frozen=True, slots=True, kw_only=True)
class PoseKeyframe:
    """Move the body from ``share_from`` to ``share_to`` of the dressing pose over ``steps`` cloth steps.

    The pose is interpolated per step and the colliders follow it; the cloth
    is moved by the contact with the moving body and its own dynamics (under
    ``gravity_scale`` × gravity). With ``attach`` > 0 the cloth on the moving
    bones starts each step with the skin's velocity (by the share of its skin
    weights on those bones) and is held with ``attach`` × that share (in
    units of its mass / h²) on where the skin's motion carries it in the step
    (the sewn vertices are not held: that would keep their seams' gaps).
    The seams left open by :class:`Sew` close from ``sew_from`` to ``sew_to``
    of the way between their gaps at the first keyframe and zero.
    ``untangle``: undo crossings in the keyframe's steps (planned off: see
    :func:`plan_phases`).
    """

    share_from: float
    share_to: float
    steps: int
    gravity_scale: float
    sew_from: float
    sew_to: float
    attach: float = 0.0
    untangle: bool = False


@dataclass(frozen=True, slots=True, kw_only=True)
class Settle:
    """Drape ``steps`` steps under ``gravity_scale`` × gravity (ramped up when it follows a :class:`Sew`).

    hold : keep what the strategy holds after sewing (bands, limb pieces) where the sewing left it
    untangle : undo the crossings of the cloth through itself
    """

    steps: int
    gravity_scale: float = 1.0
    hold: bool = False
    untangle: bool = False


Phase = Sew | PoseKeyframe | Settle


def plan_phases(strategy: Strategy, *, posed: bool, steps: int = 160) -> tuple[Phase, ...]:
    """The phases that dress a garment with ``strategy``; ``posed``: the body starts in the dressing pose.

    Parameters
    ----------
    strategy : the dressing strategy
    posed : whether the body was put into the dressing pose (arms raised)
    steps : the drape's step budget without keyframes: :data:`SEW_SHARE` of it
        sews, the rest settles (a posed body settles in its keyframes)

    Sewing and settling in the rest pose untangle (the crossings the
    placement left and those the seams make are undone: the trousers and
    shorts). A drape in the dressing pose does not, in none of its phases:
    there the untangling, which lets the layers round a crossing pass, made
    more crossings than it undid, most while the arms came down (measured
    when the cloth was carried with the skin in jumps and folded between arm
    and torso; docs/assembly.md, *Untangling by phase*).

    Examples
    --------
    >>> from patternbridge.assemble.strategy import Dressing, Strategy
    >>> [type(p).__name__ for p in plan_phases(Strategy.of(Dressing.LEGS), posed=False)]
    ['Sew', 'Settle']
    >>> len(plan_phases(Strategy.of(Dressing.TOP), posed=True))
    6
    """
    sew_steps = int(SEW_SHARE * steps)
    if posed:
        # a top is only sewn in the dressing pose (no gravity): hanging on
        # raised arms, the weight of the body of the shirt dragged the
        # sleeves toward the shoulders; it drapes while the arms come down
        levels = np.linspace(1.0, 0.0, POSE_STAGES + 1)
        keys = tuple(
            PoseKeyframe(
                share_from=float(s0),
                share_to=float(s1),
                steps=POSE_STEPS,
                gravity_scale=POSE_GRAVITY,
                sew_from=min(1.0, k / POSE_SEW_STAGES),
                sew_to=min(1.0, (k + 1) / POSE_SEW_STAGES),
                attach=POSE_ATTACH,
            )
            for k, (s0, s1) in enumerate(itertools.pairwise(levels))
        )
        sew = Sew(
            steps=sew_steps,
            open_arm_seams=True,
            pin=strategy.pin_far_from_open_seams,
            arm_inertia=SEW_ARM_INERTIA,
        )
        tail: tuple[Phase, ...] = ()
        if strategy.hold_after_sewing:
            tail = (Settle(steps=POSE_STEPS, gravity_scale=1.0, hold=True),)
        return (sew, *keys, *tail)
    return (
        Sew(steps=sew_steps, pin=strategy.pin_far_from_open_seams, untangle=True),
        Settle(steps=steps - sew_steps, hold=strategy.hold_after_sewing, untangle=True),
    )


def run_phases(
    sim: Simulation,
    phases: tuple[Phase, ...],
    progress: Callable[[str, int, int], None] | None = None,
    observe: Callable[[Phase], None] | None = None,
) -> None:
    """Run ``phases`` on ``sim`` in order (the cloth moves in place; ``sim.solver`` and the colliders follow).

    A :class:`Sew` followed by a :class:`Settle` runs as one
    :func:`~patternbridge.assemble.drape.drape` call: its schedule ramps
    gravity up over the 20 steps after sewing and pins what is held where
    the sewing ended. ``observe(phase)`` is called when each phase has run
    (a merged Sew at its last sewing step), for measuring between phases.
    """
    n_keys = sum(isinstance(p, PoseKeyframe) for p in phases)
    done_keys = 0
    k = 0
    while k < len(phases):
        phase = phases[k]
        if isinstance(phase, Sew):
            after = phases[k + 1] if k + 1 < len(phases) else None
            settle = after if isinstance(after, Settle) else None
            _sew(sim, phase, settle, progress, observe)
            if observe is not None:
                observe(settle if settle is not None else phase)
            k += 2 if settle is not None else 1
            continue
        if isinstance(phase, PoseKeyframe):
            if done_keys == 0:
                sim.solver.restart_seams()  # the seams left open close while the arms come down
            _keyframe(sim, phase)
            if observe is not None:
                observe(phase)
            done_keys += 1
            if progress:
                progress("pose", done_keys, n_keys)
        else:
            _settle(sim, phase, progress)
            if observe is not None:
                observe(phase)
        k += 1


def _sew(
    sim: Simulation,
    phase: Sew,
    settle: Settle | None,
    progress: Callable[[str, int, int], None] | None,
    observe: Callable[[Phase], None] | None = None,
) -> None:
    """Sew (and settle, when ``settle`` follows) in one drape call; ``observe(phase)`` when the sewing ends."""
    from .drape import drape
    from .pipeline import anchor_weights, hem_hold_weights, hold_weights, limb_end_seams, sewing_inertia

    hem = hem_hold_weights(sim)
    pins = np.maximum(anchor_weights(sim) if phase.pin else np.zeros(len(sim.cloth.x)), hem)
    hold = hold_weights(sim, pins) if settle is not None and settle.hold else None
    if hold is not None or (settle is not None and hem.any()):
        hold = np.maximum(hem, 0.0 if hold is None else hold)
    sim.solver = drape(
        sim.cloth,
        sim.cloth_collider,
        steps=phase.steps + (settle.steps if settle is not None else 0),
        sew_steps=phase.steps,
        settings=sim.settings,
        gravity_scale=settle.gravity_scale if settle is not None else 1.0,
        progress=progress,
        stage="drape",
        solver=sim.solver,
        anchors=(pins, sim.x_placed),
        hold=hold,
        loose=limb_end_seams(sim.pattern, sim.pmesh)[sim.seam_ids] if phase.open_arm_seams else None,
        inertia=sewing_inertia(sim, phase.arm_inertia) if phase.arm_inertia != 1.0 else None,
        on_step=None if observe is None or settle is None else (lambda k: observe(phase) if k == phase.steps else None),
        untangle_steps=(
            0 if phase.untangle else phase.steps,
            phase.steps + (settle.steps if settle is not None and settle.untangle else 0),
        ),
    )


def _keyframe(sim: Simulation, phase: PoseKeyframe) -> None:
    """Move the body from one share of the dressing pose to the next, a little every step, the cloth running.

    Before each step the body is posed at that step's share and the
    colliders rebuilt round it (the hand mitts moved with their corners);
    the cloth meets the skin where the step leaves it, so it is moved by the
    contact and its own dynamics and never jumps. The cloth on the moving
    bones takes the skin's velocity and is held softly (``phase.attach``) on
    where the skin's motion in the step carries it (:func:`_skin_follow`).
    """
    from .collision import mitt_hulls
    from .drape import drape

    cloth = sim.cloth
    mitts = mitt_hulls(sim.body, sim.hands)
    shares = np.linspace(phase.share_from, phase.share_to, phase.steps + 1)
    follow = _skin_follow(sim) if phase.attach > 0 else None
    # the sewn vertices are left to their seams: a pin carrying each side with the skin holds the gap between them
    unsewn = np.ones(len(cloth.x))
    unsewn[cloth.seams.ravel()] = 0.0

    def body(k: int):
        _pose_colliders(sim, float(shares[k + 1]), mitts)
        if follow is not None:
            share, carry = follow
            target = carry(float(shares[k]), float(shares[k + 1]), cloth.x)
            # the skin's velocity, by the share of the vertex's weights on the moved bones, and a soft pin on
            # where it carries the vertex in this step
            v_skin = (target - cloth.x) / sim.settings.time_step_s
            cloth.v = cloth.v + share[:, None] * (v_skin - cloth.v)
            sim.solver.pin(phase.attach * share * unsewn, target)
        return sim.cloth_collider

    drape(
        cloth,
        sim.cloth_collider,
        steps=phase.steps,
        sew_steps=0,
        sew_ramp=(phase.sew_from, phase.sew_to),
        gravity_scale=phase.gravity_scale,
        settings=sim.settings,
        solver=sim.solver,
        stage="pose",
        untangle_steps=(0, phase.steps if phase.untangle else 0),
        body=body,
    )
    sim.solver.pin(None)


def _pose_colliders(sim: Simulation, share: float, mitts: tuple[tuple[np.ndarray, np.ndarray], ...]) -> None:
    """Pose the body at ``share`` of the dressing pose; ``sim.collider`` and ``sim.cloth_collider`` follow it.

    ``mitts`` are the hand mitts as hulls over body vertices taken in the
    dressing pose (:func:`~patternbridge.assemble.collision.mitt_hulls`):
    their corners move with the body; the helper volumes that do not move
    with the arms (``sim.proxies``) stay.
    """
    from ..mesh.skinning import pose_vertices
    from .collision import BodyCollider
    from .pose import rotations

    character = sim.character
    posed = (
        np.array(character.vertices, dtype=np.float64)
        if share == 0.0
        else pose_vertices(character, rotations(sim.rotvecs, share))
    )
    sim.collider = BodyCollider(posed, character.faces)
    helpers = sim.proxies + tuple((posed[ids], f) for ids, f in mitts)
    sim.cloth_collider = sim.collider.with_proxies(helpers) if helpers else sim.collider


def _skin_follow(sim: Simulation):
    """How much each cloth vertex follows the skin (N,), and where the skin carries it between two shares of the pose.

    Each cloth vertex takes the skin weights of its nearest body point
    (smoothed over the cloth, :func:`~patternbridge.assemble.pipeline.smooth_over_cloth`);
    it follows by the share of those weights on the bones the pose moves
    (the arms: the cloth on the torso is left to the contact).
    ``carry(s0, s1, x)`` is ``x`` moved by the blended skin transform from
    share ``s0`` to ``s1``: the target of one step (the skin's velocity),
    not a jump of the cloth.
    """
    from .pipeline import smooth_over_cloth
    from .pose import apply_transforms, blend_transforms, moved_bones, rotations, unapply_transforms
    from .weights import transfer_weights

    character, cloth = sim.character, sim.cloth
    joints, weights = transfer_weights(sim.collider, character, cloth.x)
    moved = moved_bones(character, sim.rotvecs)
    share = smooth_over_cloth(cloth, np.where(joints >= 0, weights * moved[np.maximum(joints, 0)], 0.0).sum(axis=1))

    made: dict[float, np.ndarray] = {}  # the last step's end is the next one's start

    def frames(s: float) -> np.ndarray:
        if s not in made:
            if len(made) > 1:
                made.clear()
            rots = rotations(sim.rotvecs, s)
            made[s] = smooth_over_cloth(cloth, blend_transforms(character, rots, joints, weights))
        return made[s]

    def carry(s0: float, s1: float, x: np.ndarray) -> np.ndarray:
        return apply_transforms(frames(s1), unapply_transforms(frames(s0), x))

    return share, carry


def _settle(sim: Simulation, phase: Settle, progress: Callable[[str, int, int], None] | None) -> None:
    """Drape under gravity, holding what the strategy holds where the cloth is now."""
    from .drape import drape
    from .pipeline import hold_weights

    sim.solver = drape(
        sim.cloth,
        sim.cloth_collider,
        steps=phase.steps,
        sew_steps=0,
        settings=sim.settings,
        gravity_scale=phase.gravity_scale,
        progress=progress,
        stage="settle",
        solver=sim.solver,
        hold=hold_weights(sim, np.zeros(len(sim.cloth.x))) if phase.hold else None,
        untangle_steps=(0, phase.steps if phase.untangle else 0),
    )
