"""What every study kind shares: the base model, number types and helpers.

A study file is a mapping with a format version (``designlab: 1``), a ``kind``
that selects the study type, a ``name`` (also the report directory name), a
``description`` and kind-specific fields. Every model forbids unknown fields,
so a typo is an error rather than a silently ignored setting. Units are SI
throughout: kg, N/m, N s/m, m, m/s, s.

Examples
--------
>>> class Demo(StudyBase):
...     kind: Literal["demo"]
...     speed: Positive
>>> Demo(designlab=1, kind="demo", name="d", speed=1.5).speed
1.5
>>> did_you_mean("stifness", ["mass", "stiffness", "damping"])
"; did you mean 'stiffness'?"
"""

from __future__ import annotations

import difflib
from typing import Annotated, ClassVar, Literal

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field

from designlab.validation import reject_bool

__all__ = [
    "FORMAT_VERSION",
    "Finite",
    "Flag",
    "Model",
    "NonNegative",
    "Number",
    "Positive",
    "Speed",
    "StudyBase",
    "did_you_mean",
]

#: The study file format this version of designlab reads (the ``designlab:`` key).
FORMAT_VERSION = 1


def did_you_mean(word: str, choices: list[str] | tuple[str, ...] | set[str]) -> str:
    """Return ``"; did you mean 'x'?"`` for the closest choice, or ``""``.

    Parameters
    ----------
    word
        What the user wrote.
    choices
        What is allowed.

    Examples
    --------
    >>> did_you_mean("zzz", ["mass"])
    ''
    """
    close = difflib.get_close_matches(str(word), sorted(choices), n=1, cutoff=0.6)
    return f"; did you mean {close[0]!r}?" if close else ""


#: A real number (a boolean is refused).
Number = Annotated[float, BeforeValidator(reject_bool)]
#: An integer (a boolean is refused: YAML's ``true`` is not 1).
Integer = Annotated[int, BeforeValidator(reject_bool)]
#: A yes/no switch: YAML ``true`` or ``false`` only (not ``1``, ``"yes"`` or ``"on"``).
Flag = Annotated[bool, Field(strict=True)]
#: A finite number > 0.
Positive = Annotated[Number, Field(gt=0, allow_inf_nan=False)]
#: A finite number >= 0.
NonNegative = Annotated[Number, Field(ge=0, allow_inf_nan=False)]
#: A finite number.
Finite = Annotated[Number, Field(allow_inf_nan=False)]
#: A speed in m/s, limited to a sanity range (human-robot contacts are a few m/s).
Speed = Annotated[Number, Field(ge=-20.0, le=20.0, allow_inf_nan=False)]


class Model(BaseModel):
    """Base of every study model: unknown fields are errors, values are frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class StudyBase(Model):
    """Fields common to every study kind."""

    designlab: Annotated[Literal[1], BeforeValidator(reject_bool)] = Field(
        description="study file format version"
    )
    kind: str
    name: str = Field(
        pattern=r"^[A-Za-z0-9][A-Za-z0-9_.-]*$",
        max_length=100,
        description="identifier; the report goes to <output-dir>/<name>/",
    )
    description: str = ""

    #: Files (glob patterns) the report of this kind contains, for ``designlab list``.
    PRODUCES: ClassVar[tuple[str, ...]] = ()

    def size(self) -> str:
        """A few words on the size of the study, for ``designlab validate``."""
        return ""
