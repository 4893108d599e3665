"""The one rule for the names of coordinates and parameters, in a model file, in an expression
and in the Python API: an ASCII identifier, or one with Greek letters.

Names reach the equations, the exported code and the printed results, where two names that
look alike must be two names that read alike.  Unicode has many letters that look like Latin
ones: the Cyrillic ``х`` beside the Latin ``x`` would give two coordinates printed the same;
Python's tokenizer (and so the expression parser) folds the mathematical bold ``𝐱`` and the
fullwidth ``ｘ`` into ``x`` (normal form NFKC), merging two names silently.  So a name is made
of ASCII letters, digits and underscores, and the letters of the Greek alphabet (``theta`` or
``θ``, as a physicist writes), not starting with a digit, and not a Python keyword
(``lambda``: no expression could name it, nor exported code use it).  Anything else is refused
with the ASCII name it looks like.

>>> name_problem("theta_1"), name_problem("ω0")
(None, None)
>>> name_problem("х")  # Cyrillic
("'х' has a letter that is neither ASCII nor Greek (CYRILLIC SMALL LETTER HA)", 'write x')
>>> name_problem("lambda")
("'lambda' is a Python keyword, which no expression can use as a name", 'write lambda_ or lam')
"""

from __future__ import annotations

import keyword
import unicodedata

#: Cyrillic letters that look like Latin ones, by what they look like (from Unicode's
#: confusables list).
LOOKALIKES = str.maketrans("аАвВеЕкКмМнНоОрРсСтТуУхХіІјЈѕЅԁԛԝ", "aABBeEkKmMhHoOpPcCtTyYxXiIjJsSdqw")


def is_greek(character: str) -> bool:
    """True for a letter of the Greek alphabet (the Greek and Coptic block's letters)."""
    return "\u0370" <= character <= "\u03ff" and unicodedata.name(character, "").startswith("GREEK")


def ascii_suggestion(name: str) -> str:
    """The ASCII name ``name`` looks like: its lookalike letters and NFKC's foldings
    (fullwidth, bold) replaced, whatever else left out (``x1`` when nothing is left)."""
    folded = unicodedata.normalize("NFKC", name.translate(LOOKALIKES)).translate(LOOKALIKES)
    kept = "".join(c for c in folded if (c.isascii() and (c.isalnum() or c == "_")) or is_greek(c))
    if not kept or kept[0].isdigit():
        kept = "x" + kept
    return kept if kept.isidentifier() and not keyword.iskeyword(kept) else "x1"


def name_problem(name: str) -> tuple[str, str] | None:
    """(what is wrong, the fix) when ``name`` cannot name a coordinate or a parameter (module
    docstring), else None."""
    shown = name.encode("unicode_escape").decode("ascii") if not name.isprintable() else name
    foreign = [c for c in name if not c.isascii() and not is_greek(c)]
    if foreign:
        names = ", ".join(dict.fromkeys(unicodedata.name(c, f"U+{ord(c):04X}") for c in foreign))
        noun = "a letter" if all(c.isalpha() for c in foreign) else "a character"
        return f"{shown!r} has {noun} that is neither ASCII nor Greek ({names})", (
            f"write {ascii_suggestion(name)}"
        )
    if unicodedata.normalize("NFKC", name) != name:  # ϑ, ϕ: read as θ, φ in expressions
        return f"{name!r} is read as {unicodedata.normalize('NFKC', name)!r} in expressions", (
            f"write {unicodedata.normalize('NFKC', name)}"
        )
    if not name.isidentifier():
        return (
            f"{shown!r} is not a name (letters, digits and underscores, not starting with a digit)",
            "rename it, e.g. x1 or theta_2",
        )
    if keyword.iskeyword(name):
        return f"{name!r} is a Python keyword, which no expression can use as a name", (
            f"write {name}_ or {_short_form(name)}"
        )
    return None


def _short_form(word: str) -> str:
    return {"lambda": "lam"}.get(word, word[:3] + "1")
