"""Role hints from the words a file writes on a piece (its category text and name).

Only hints: the geometry decides, a hint breaks ties and names what geometry
cannot tell apart (a placket from a strip of interlining). Codes are the
AccuMark piece-code habits (``FR``, ``BK``, ``SS``, ``CU`` …) and words in
English, French, German, Spanish and Italian.
"""

from __future__ import annotations

import re

from ..pattern.model import Piece
from .model import Role

__all__ = ["name_hint"]

_WORDS: tuple[tuple[Role, tuple[str, ...]], ...] = (
    (Role.INTERLINING, ("INTERLIN", "INTERFAC", "FUSIBLE", "ENTOILAGE", "EINLAGE", "ENTRETELA", "TELETTA")),
    (Role.ARMHOLE_BINDING, ("ARMHOLE BIND", "BINDING ARM", "BIND ARM", "BIAIS EMMANCH")),
    (Role.NECK_BINDING, ("NECK BIND", "BINDING NECK", "BIND NECK", "BIAIS ENCOL")),
    (Role.COLLAR_STAND, ("STAND", "PIED DE COL", "KRAGENSTEG", "PIE DE CUELLO")),
    (Role.PLACKET, ("PLACKET", "LEISTE", "TAPETA")),
    (Role.WAISTBAND, ("WAISTBAND", "WAIST BAND", "CEINTURE", "BUND", "PRETINA", "CINTURINO")),
    (Role.CUFF, ("CUFF", "POIGNET", "MANSCHETTE", "PUÑO", "POLSINO")),
    (Role.NECKBAND, ("NECKBAND", "NECK RIB", "NECKRIB", "CREWNECK", "RIB")),
    (Role.COLLAR, ("COLLAR", "COL ", "KRAGEN", "CUELLO", "COLLO")),
    (Role.YOKE, ("YOKE", "EMPIECEMENT", "PASSE", "SATTEL", "CANESU")),
    (Role.POCKET, ("POCKET", "POCHE", "TASCHE", "BOLSILLO", "TASCA")),
    (Role.HOOD, ("HOOD", "CAPUCHE", "KAPUZE", "CAPUCHA")),
    (Role.FACING, ("FACING", "PAREMENTURE", "BELEG", "VISTA")),
    (Role.GUSSET, ("GUSSET", "GOUSSET", "ZWICKEL")),
    (Role.SLEEVE, ("SLEEVE", "MANCHE", "ÄRMEL", "ARMEL", "MANGA", "MANICA")),
    (Role.LEG, ("LEG", "JAMBE", "BEIN", "PIERNA", "GAMBA")),
    (Role.BACK, ("BACK", "DOS", "RÜCKEN", "RUCKEN", "ESPALDA", "DIETRO")),
    (Role.FRONT, ("FRONT", "DEVANT", "VORDER", "DELANTER", "DAVANTI")),
)

#: trailing AccuMark piece codes (after the style number)
_CODES: dict[str, Role] = {
    "FR": Role.FRONT,
    "FA": Role.FRONT,
    "F": Role.FRONT,
    "BK": Role.BACK,
    "BA": Role.BACK,
    "B": Role.BACK,
    "SL": Role.SLEEVE,
    "SS": Role.SLEEVE,
    "ST": Role.SLEEVE,
    "SLS": Role.LEG,
    "SLL": Role.LEG,
    "SLO": Role.LEG,
    "CU": Role.CUFF,
    "CO": Role.COLLAR,
    "NR": Role.NECKBAND,
    "RN": Role.NECKBAND,
    "NB": Role.NECK_BINDING,
    "AB": Role.ARMHOLE_BINDING,
    "BIN": Role.NECK_BINDING,
    "BIA": Role.ARMHOLE_BINDING,
    "WB": Role.WAISTBAND,
    "YP": Role.PLACKET,
    "YL": Role.PLACKET,
    "IX": Role.INTERLINING,
    "IY": Role.INTERLINING,
}


def _word_role(text: str) -> Role | None:
    """The role of the last role word in ``text`` (``SLEEVE CUFF`` is a cuff)."""
    best, at = None, -1
    for role, words in _WORDS:
        for w in words:
            k = text.rfind(w)
            if k >= 0 and (len(w) > 4 or k == 0 or not text[k - 1].isalpha()) and k > at:
                best, at = role, k
    return best


def name_hint(piece: Piece) -> Role | None:
    """The role the piece's own words suggest, or None."""
    for text in (piece.category.upper(), piece.name.upper()):
        role = _word_role(text.split(" WITH ")[0])
        if role is not None:
            return role
    name = piece.name.upper()
    digits = re.search(r"\d", name)
    tokens = re.findall(r"[A-Z]+", name[digits.start() :] if digits else name)
    for token in tokens:
        for cand in (token, token[-3:], token[-2:], token[-1:]):
            if cand in _CODES:
                return _CODES[cand]
    return None
