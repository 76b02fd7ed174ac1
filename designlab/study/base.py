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
import inspect
from collections.abc import Hashable, Iterator, Sequence
from typing import Annotated, Any, ClassVar, Literal

import numpy as np
from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, field_validator, model_validator

from designlab.errors import DesignlabError, StudyError
from designlab.params import Param, numbers_only
from designlab.validation import reject_bool

__all__ = [
    "FORMAT_VERSION",
    "RESERVED_NAMES",
    "Finite",
    "Flag",
    "Grid",
    "Integer",
    "Model",
    "NonNegative",
    "Number",
    "Positive",
    "Speed",
    "StudyBase",
    "build_every_spec",
    "did_you_mean",
    "format_path",
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


#: A real number: a boolean or a text is refused; ``inf`` is allowed (bound it where it matters).
Number = Annotated[float, BeforeValidator(numbers_only)]
#: An integer (a boolean or a text is refused: YAML's ``true`` is not 1; ``3.0`` reads as 3).
Integer = Param(kind="integer").annotation()
#: A yes/no switch: YAML ``true`` or ``false`` only (not ``1``, ``"yes"`` or ``"on"``).
Flag = Param(kind="flag").annotation()
#: A finite number > 0 (the same rule as a declaration ``param(..., gt=0)``).
Positive = Param(gt=0).annotation()
#: A finite number >= 0.
NonNegative = Param(ge=0).annotation()
#: A finite number.
Finite = Param().annotation()
#: A speed in m/s, limited to a sanity range (human-robot contacts are a few m/s).
Speed = Param(unit="m/s", ge=-20.0, le=20.0).annotation()

#: Study names refused although they fit the pattern: files of the output directory itself
#: (``index.md``, the reports index) and names Windows reserves for devices.
RESERVED_NAMES = frozenset(
    {"index.md", "con", "prn", "aux", "nul"}
    | {f"com{i}" for i in range(1, 10)}
    | {f"lpt{i}" for i in range(1, 10)}
)


def format_path(path: Sequence[Hashable]) -> str:
    """Format a data path as ``cases[0].robot.mass``.

    Parameters
    ----------
    path
        Keys and indices from the root of the study.

    Examples
    --------
    >>> format_path(("cases", 0, "robot", "mass"))
    'cases[0].robot.mass'
    """
    out = ""
    for part in path:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += f".{part}" if out else str(part)
    return out


def _buildable(obj: Any, path: tuple[Hashable, ...]) -> Iterator[tuple[tuple[Hashable, ...], Any]]:
    """Every sub-model with a ``build()`` of no arguments, with its data path, depth first."""
    if isinstance(obj, BaseModel):
        build = getattr(obj, "build", None)
        if callable(build) and path:
            try:
                needs_args = any(
                    p.default is inspect.Parameter.empty
                    and p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)
                    for p in inspect.signature(build).parameters.values()
                )
            except (TypeError, ValueError):  # pragma: no cover - builtins without a signature
                needs_args = True
            if not needs_args:
                yield path, obj
        for name, field in type(obj).model_fields.items():
            yield from _buildable(getattr(obj, name), (*path, field.alias or name))
    elif isinstance(obj, (list, tuple)):
        for i, item in enumerate(obj):
            yield from _buildable(item, (*path, i))
    elif isinstance(obj, dict):
        for key, item in obj.items():
            yield from _buildable(item, (*path, key))


def build_every_spec(study: BaseModel) -> None:
    """Build every domain object a study describes, so its constructor's checks run now.

    The cross-field rules of a domain class (``r2 > r3``, ``min < max``) live in
    its ``__post_init__``; building each spec (every sub-model with a
    ``build()`` of no arguments) runs them at validation time, with the field's
    place in the file, instead of when the run reaches it.

    Parameters
    ----------
    study
        A validated study (or any model).

    Raises
    ------
    StudyError
        With ``path`` set to the spec that cannot be built and the domain's message.
    """
    for path, spec in _buildable(study, ()):
        try:
            spec.build()
        except (DesignlabError, ValueError, OverflowError, ZeroDivisionError) as exc:
            raise StudyError(str(exc), path=path) from None
        except MemoryError:
            raise StudyError(
                "describes an object too large for this machine's memory", path=path
            ) from None


class Model(BaseModel):
    """Base of every study model: unknown fields are errors, values are frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class Grid(Model):
    """Base of a study file's grid of values: ``num`` of them from ``low`` to ``high``.

    A subclass declares the three fields (their bounds, units and defaults) and says with
    ``LOG`` whether the values are evenly spaced in log rather than linearly.

    Examples
    --------
    >>> class Demo(Grid):
    ...     low: float = 1.0
    ...     high: float = 100.0
    ...     num: int = 3
    ...     LOG: ClassVar[bool] = True
    >>> Demo().values()
    [1.0, 10.0, 100.0]
    >>> Demo(low=5, high=1)
    Traceback (most recent call last):
    ...
    pydantic_core._pydantic_core.ValidationError: 1 validation error for Demo
    ...
    """

    low: float
    high: float
    num: int

    #: Evenly spaced in log (``numpy.geomspace``) rather than linearly.
    LOG: ClassVar[bool] = False

    @model_validator(mode="after")
    def _order(self) -> Grid:
        if not self.low < self.high:
            raise ValueError(f"low = {self.low:g} must be < high = {self.high:g}")
        return self

    def values(self) -> list[float]:
        """The grid (rounded to 12 significant digits so reports diff cleanly)."""
        grid = (np.geomspace if self.LOG else np.linspace)(self.low, self.high, self.num)
        return [float(f"{x:.12g}") for x in grid]


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
    #: How long the committed study of this kind runs, in seconds, for ``designlab list``:
    #: wall time of ``designlab run studies/<study>.yaml`` (serial, fresh result store) on
    #: an idle 2-core machine. Measured, never guessed; 0: not measured.
    TYPICAL_DURATION: ClassVar[float] = 0.0

    @field_validator("name")
    @classmethod
    def _not_reserved(cls, value: str) -> str:
        if value.lower() in RESERVED_NAMES:
            raise ValueError(
                f"the name {value!r} is reserved: the report would go to <output-dir>/{value}/, "
                "which clashes with the reports index (index.md) or a device name; "
                "choose another name"
            )
        return value

    def size(self) -> str:
        """A few words on the size of the study, for ``designlab validate``."""
        return ""

    def typical_duration(self) -> float | None:
        """How long a study of this kind typically runs, s (``None``: not measured).

        Returns
        -------
        float or None
            :attr:`TYPICAL_DURATION`, the measured run time of the kind's
            committed study, for ``designlab list``.
        """
        return self.TYPICAL_DURATION or None

    def check(self) -> None:
        """Everything ``run`` checks before it computes, beyond the schema.

        The loader calls it after the schema has passed, so ``designlab
        validate`` refuses every study that ``designlab run`` would refuse
        before computing. The default builds every domain object the study
        describes (:func:`build_every_spec`), which runs the domain classes'
        cross-field rules; a kind with more to check (a size cap, a relation
        between fields of different specs) extends it and raises
        :class:`~designlab.errors.StudyError` with ``path`` set to the field.

        Raises
        ------
        StudyError
            What is wrong, at ``path`` (the loader adds the file and the line).
        """
        build_every_spec(self)
