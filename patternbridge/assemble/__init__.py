"""Assemble a garment on a character: place, sew, drape and write rigged-ready meshes.

The pipeline follows the source method (thesis, section 4.3): the body is
split into parts (:mod:`.bodyparts`), the triangulated pieces (:mod:`.mesh2d`)
are wrapped on body-part proxies by their placement hints and moved together
along the seam graph (:mod:`.place`); a dressing strategy chosen from the
pieces' body parts (:mod:`.strategy`) plans typed phases (:mod:`.phases`)
in which a cloth solver sews and drapes them
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
