"""Many cases from one base: the case id, and the sub-tables a batch of cases shares, parsed once.

A campaign's case tables are its base with the swept keys set, built copy-on-write
(:mod:`study.campaign.expand`): a sub-table that no swept key touches is the same object in
every case table.  :class:`SharedTables`, given to :meth:`solver.Case.from_dict`, keeps the
parse of such a sub-table (a body, the grid, the solver options, the output fields) and the
text its normalised table adds to the case id, keyed by the object.  A case built with it is
the case built without it (its checks, notes, table and id); the sub-tables a batch shares
must not change while the batch is built.

:func:`case_hash` is the case id: the hash of the normalised table's JSON text with sorted
keys, which it writes one top-level table at a time so that a batch's shared tables are
written once.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable
from typing import Any

from .options import EXECUTION_KEYS

#: What a [solver] or [output] table that is not given is read as (never changed).
NO_TABLE: dict = {}


#: JSON text with sorted keys and no spaces (what the case id hashes): ``json.dumps`` with
#: these options, its encoder built once.
_text = json.JSONEncoder(sort_keys=True, separators=(",", ":")).encode
#: A key's JSON text, as :data:`_text` writes it (ASCII, escaped).
_key = json.encoder.encode_basestring_ascii


def id_form(key: str, value: Any) -> Any:
    """The part of the normalised table ``key`` that the case id hashes.

    Without :data:`~solver.case.options.EXECUTION_KEYS` (they change no result beyond
    round-off), and a height map as its content, wherever its file lies.
    """
    if key == "solver":
        return {k: v for k, v in value.items() if k not in EXECUTION_KEYS}
    if key in ("body1", "body2") and "surface" in value:
        surface = {k: v for k, v in value["surface"].items() if k not in ("file", "case")}
        return {**value, "surface": surface}
    return value


def case_hash(spec: dict, text: Callable[[str, Any], str] | None = None) -> str:
    """The case id of a normalised table: 16 hex digits of the SHA-256 of its JSON text.

    The text is ``json.dumps`` of the table's :func:`id_form` with sorted keys and no spaces,
    written here one top-level table at a time; ``text(key, value)`` writes one (a
    :class:`SharedTables` gives the texts of the tables it parsed).
    """
    if text is None:
        whole = _text({key: id_form(key, value) for key, value in spec.items()})
    else:
        parts = (f"{_key(key)}:{text(key, value)}" for key, value in sorted(spec.items()))
        whole = "{" + ",".join(parts) + "}"
    return hashlib.sha256(whole.encode()).hexdigest()[:16]


class SharedTables:
    """The parsed sub-tables of a batch of case tables built from one base.

    :meth:`parse` keeps what a parser made of a table, keyed by the table object (held, so
    that its id is not reused); a batch built copy-on-write hands the same object for every
    sub-table no swept key changes.  At most :attr:`KEPT` tables of each kind are kept.  Valid
    only while those tables are not changed: give one to the cases of one expansion, not to
    tables a caller edits between calls.
    """

    #: Tables kept per kind (a swept whole table from [define] takes a few values).
    KEPT = 16

    def __init__(self) -> None:
        self._parsed: dict[str, dict[int, tuple[Any, Any]]] = {}
        self._texts: dict[tuple[str, int], tuple[Any, str]] = {}

    def parse(self, kind: str, table: Any, parser: Callable[[Any], Any]) -> Any:
        """``parser(table)``, once per ``kind`` and table object (errors are not kept).

        A parser that returns ``(parsed, normalised table)``: the normalised table of a table
        seen again is shared by the batch, and :meth:`text` writes it once.
        """
        kept = self._parsed.setdefault(kind, {})
        hit = kept.get(id(table))
        if hit is not None and hit[0] is table:
            value = hit[1]
            if isinstance(value, tuple) and isinstance(value[-1], dict):
                self._texts.setdefault((kind, id(value[-1])), (value[-1], ""))
            return value
        value = parser(table)
        if len(kept) >= self.KEPT:
            kept.clear()
        if len(self._texts) >= 8 * self.KEPT:
            self._texts.clear()
        kept[id(table)] = (table, value)
        return value

    def text(self, key: str, value: Any) -> str:
        """The id text of the normalised table ``key`` (:func:`case_hash`), kept if shared."""
        hit = self._texts.get((key, id(value)))
        if hit is None or hit[0] is not value:
            return _text(id_form(key, value))
        if not hit[1]:
            hit = self._texts[key, id(value)] = (value, _text(id_form(key, value)))
        return hit[1]
