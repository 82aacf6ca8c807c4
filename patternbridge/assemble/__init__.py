"""Assemble a garment on a character: place, sew, drape and write rigged-ready meshes.

The pipeline follows the source method (thesis, section 4.3): the body is
split into parts (:mod:`.bodyparts`), each part gets a bounding cylinder and
the triangulated pieces (:mod:`.mesh2d`) are wrapped onto it by their
placement hints (:mod:`.placement`); a cloth solver sews and drapes them
against the body (:mod:`.drape`, :mod:`.collision`). A rigged character is
dressed for tops with its arms raised and straight (:mod:`.pose`) and the cloth is carried back to
the rest pose by the skin weights of the nearest body points
(:mod:`.weights`), which it also keeps for rigging (:mod:`.export_gltf`,
:mod:`.export_usd`).
:mod:`.pipeline` chains the stages.

Public entry points: :func:`assemble` returns a :class:`Garment`;
:func:`dress` also writes ``garment.glb``, ``garment.obj``/``.mtl``,
``garment.usda`` and the ``fit_*.png`` pictures and returns the ``drape`` report.
"""

from __future__ import annotations

from .garment import Garment
from .pipeline import assemble, dress
from .weights import transfer_weights

__all__ = ["Garment", "assemble", "dress", "transfer_weights"]
