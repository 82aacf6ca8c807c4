"""Size names pattern CAD accepts: short codes for the others, their full names kept in a note.

CAD systems take sizes as short tokens (``42``, ``XS``, ``2XL``, ``36/38``) and
a size list of one kind; a character added as a size (``E_average_male``)
is neither. The writer gives such a size a code in the list's own kind (a
number from 901 in a numeric list, ``C1``, ``C2``… otherwise) and writes
``Size <code>: <full name>`` as a layer-15 text in ENTITIES; the reader turns
the codes back into the names.
"""

from __future__ import annotations

import dataclasses
import re

from ...pattern.model import GradeRuleTable, Pattern

__all__ = ["SIZE_NOTE", "is_cad_size", "rename_sizes", "size_codes"]

SIZE_NOTE = re.compile(r"^\s*Size\s+(\S+)\s*:\s*(.+?)\s*$", re.IGNORECASE)
"""A layer-15 ENTITIES text naming a coded size: ``Size 901: E_average_male``."""
_CAD_SIZE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9.+/-]{0,7}$")
_NUMERIC = re.compile(r"^\d+(?:[./]\d+)?$")


def is_cad_size(name: str) -> bool:
    """A size name CAD takes as it is: 1-8 characters of letters, digits and ``. + / -``.

    Examples
    --------
    >>> is_cad_size("42"), is_cad_size("2XL"), is_cad_size("E_average_male")
    (True, True, False)
    """
    return bool(_CAD_SIZE.match(name))


def size_codes(sizes: tuple[str, ...]) -> dict[str, str]:
    """Name -> code for every size that needs one (a CAD-unfriendly name, or a name in a numeric list).

    Examples
    --------
    >>> size_codes(("42", "44", "E_average_male"))
    {'E_average_male': '901'}
    >>> size_codes(("62", "66", "70", "hero"))
    {'hero': '901'}
    >>> size_codes(("S", "M", "B slim female"))
    {'B slim female': 'C1'}
    """
    plain = [s for s in sizes if is_cad_size(s)]
    numeric = 2 * sum(bool(_NUMERIC.match(s)) for s in plain) > len(plain)  # a list of mostly numbers
    odd = [s for s in sizes if not is_cad_size(s) or (numeric and not _NUMERIC.match(s))]
    taken = set(sizes)
    codes: dict[str, str] = {}
    k = 1
    for name in odd:
        while (code := (str(900 + k) if numeric else f"C{k}")) in taken:
            k += 1
        codes[name] = code
        taken.add(code)
        k += 1
    return codes


def rename_sizes(pattern: Pattern, mapping: dict[str, str]) -> Pattern:
    """``pattern`` with its sizes renamed by ``mapping`` (size list, sample size, rule table, pieces)."""
    if not mapping:
        return pattern

    def new(size: str) -> str:
        return mapping.get(size, size)

    rules = pattern.rules
    table = GradeRuleTable(name=rules.name, sizes=tuple(new(s) for s in rules.sizes),
                           sample_size=new(rules.sample_size), deltas=dict(rules.deltas))
    pieces = tuple(dataclasses.replace(p, size=new(p.size)) for p in pattern.pieces)
    return dataclasses.replace(pattern, sizes=tuple(new(s) for s in pattern.sizes),
                               sample_size=new(pattern.sample_size), rules=table, pieces=pieces)
