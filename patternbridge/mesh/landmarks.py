"""Datum points (landmarks): names, and placement from a file, the skeleton or the geometry."""

from __future__ import annotations

__all__ = ["LANDMARK_NAMES"]

#: The landmark vocabulary (as in ``shared/characters/landmarks.json``); left = +X.
LANDMARK_NAMES: tuple[str, ...] = (
    "top_of_head",
    "front_neck_point",
    "back_neck_point",
    "neck_shoulder_point_left",
    "neck_shoulder_point_right",
    "shoulder_point_left",
    "shoulder_point_right",
    "armpit_point_left",
    "armpit_point_right",
    "axilla_front_left",
    "axilla_front_right",
    "axilla_back_left",
    "axilla_back_right",
    "bust_point_left",
    "bust_point_right",
    "waist_front",
    "waist_back",
    "waist_side_left",
    "waist_side_right",
    "buttock_point_left",
    "buttock_point_right",
    "hip_side_left",
    "hip_side_right",
    "crotch_point",
    "elbow_point_left",
    "elbow_point_right",
    "wrist_point_left",
    "wrist_point_right",
    "knee_point_left",
    "knee_point_right",
    "ankle_inside_left",
    "ankle_inside_right",
    "ankle_outside_left",
    "ankle_outside_right",
    "heel_point_left",
    "heel_point_right",
)
