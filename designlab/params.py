"""How a parameter is declared once, and everything that derives from the declaration.

A domain model declares each parameter on its dataclass field with :func:`param`:
its symbol, SI unit, allowed range, default, one-line meaning and typical range.
The class is then wrapped by :func:`declared`, and from that one declaration come

* the constructor's validation and its error message
  (:class:`~designlab.errors.InvalidParameterError` naming the parameter, its
  value and what is allowed);
* the ``Parameters`` section of the class docstring;
* the pydantic field of the YAML study models and so their JSON Schema
  (:meth:`Param.annotation`; :func:`designlab.study.specs.spec_model` builds a
  whole model);
* the sweepable-parameter tables of the sweep kinds (:func:`sweepable`);
* the parameter tables in reports and docs (:func:`parameter_table`).

A parameter that is an argument of a function rather than a field of a model
(the closing velocity of an impact, say) is a module-level :class:`Param`
checked with :meth:`Param.check`; the functions taking it read their default
from it (``stop_time: float = STOP_TIME.default``). The arguments shared across
the domains (the seed of random numbers, the confidence level of an interval)
are declared once here, in :data:`ARG`. Changing a bound or a default is a
one-line edit of the declaration; ``tests/test_declarations.py`` fails where a
signature restates a declared default.

Caps are part of a declaration: every real parameter has an upper bound where
a larger value would only exhaust memory or time (the caps are stated in the
generated docs). :func:`check_size` guards an allocation before it happens.

Examples
--------
>>> from dataclasses import dataclass
>>> @declared
... @dataclass(frozen=True)
... class Spring:
...     '''A linear spring.'''
...     stiffness: float = param("k", "N/m", gt=0, le=1e9, doc="spring stiffness",
...                              typical=(1e3, 1e5))
...     preload: float = param("F_0", "N", ge=0, le=1e6, default=0.0, doc="preload")
>>> Spring(stiffness=2e3)
Spring(stiffness=2000.0, preload=0.0)
>>> Spring(stiffness=-1)
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: Spring.stiffness = -1 N/m is not allowed: must be ...e+09
>>> print(Spring.__doc__.split("Parameters")[1].strip().splitlines()[1])
stiffness : float
>>> parameter_table(Spring)[["name", "symbol", "unit", "allowed"]]
        name symbol unit            allowed
0  stiffness      k  N/m   > 0 and <= 1e+09
1    preload    F_0    N  >= 0 and <= 1e+06
"""

from __future__ import annotations

import dataclasses
import inspect
import math
import numbers
import re
import textwrap
from collections.abc import Callable, Iterator, Sequence
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import BeforeValidator, Field

from designlab.errors import InvalidParameterError

__all__ = [
    "ARG",
    "MAX_ELEMENTS",
    "Arguments",
    "Param",
    "check_size",
    "declared",
    "is_complex",
    "numbers_only",
    "param",
    "parameter_table",
    "params_of",
    "sweepable",
]

#: The most elements (float64 values) one array of a simulation or a table may hold
#: before it is allocated: 2**27, 1 GiB. A larger request is refused with the parameter
#: that asked for it (:func:`check_size`).
MAX_ELEMENTS = 1 << 27

Kind = Literal["real", "integer", "choice", "flag", "text", "object"]

_MISSING: Any = dataclasses.MISSING


def _fmt(x: float) -> str:
    return f"{x:g}"


def numbers_only(value: Any) -> Any:
    """pydantic ``BeforeValidator``: numbers only (YAML ``true`` and ``'0.4'`` refused).

    Parameters
    ----------
    value
        The value given.

    Examples
    --------
    >>> numbers_only(0.4)
    0.4
    >>> numbers_only("0.4")
    Traceback (most recent call last):
    ...
    ValueError: must be a number, not the text '0.4'
    """
    if isinstance(value, (bool, np.bool_)):
        raise ValueError("must be a number, not a boolean")
    if isinstance(value, (str, bytes)):
        raise ValueError(f"must be a number, not the text {value!r}")
    if is_complex(value):
        raise ValueError(f"must be a real number, not the complex {value!r}")
    return value


def is_complex(value: Any) -> bool:
    """Whether ``value`` is a complex number or an array of them (refused, never cast to real).

    numpy converts ``np.complex128(3 + 1j)`` to the float 3.0 with only a warning; every
    declaration refuses it instead (issue 41).

    Parameters
    ----------
    value
        The value given.

    Examples
    --------
    >>> is_complex(np.complex64(3)), is_complex([1.0, 2j]), is_complex(3.0)
    (True, True, False)
    """
    if isinstance(value, (complex, np.complexfloating)):
        return True
    if isinstance(value, np.ndarray):
        return value.dtype.kind == "c"
    if isinstance(value, (list, tuple)):
        return any(is_complex(v) for v in value)
    return False


_refuse_text_and_bool = numbers_only


def _integral(value: Any) -> Any:
    """pydantic ``BeforeValidator`` of integers: an integral float becomes an int."""
    value = numbers_only(value)
    if isinstance(value, float) and math.isfinite(value) and value.is_integer():
        return int(value)
    return value


@dataclasses.dataclass(frozen=True)
class Param:
    """The declaration of one parameter: symbol, unit, allowed range, meaning.

    Parameters
    ----------
    symbol
        The symbol in the source (``"M_h"``); also the key of a sweep point.
    unit
        SI unit as written in the docs (``"N s/m"``); ``""`` when dimensionless.
    doc
        One line: what the parameter is (``"head mass"``).
    kind
        ``"real"`` (a finite float), ``"integer"``, ``"choice"`` (one of
        ``choices``), ``"flag"`` (a bool), ``"text"`` or ``"object"`` (validated
        by its owner; declared for the docs only).
    gt, ge, lt, le
        Exclusive / inclusive lower and upper bounds (real and integer).
    min_length, max_length
        The shortest and longest text allowed (``"text"``), in characters.
    choices
        The allowed strings of a ``"choice"``.
    typical
        ``(low, high)``: the range met in practice or in the source.
    optional
        ``None`` is allowed; ``none`` says what it means.
    none
        What ``None`` means (``"copies the linear value"``).
    default
        The default (set by :func:`param` from the dataclass default).
    name, owner
        The field name and class name (set by :func:`declared`); ``name`` is
        also the key of a standalone declaration's error message.

    Examples
    --------
    >>> v = Param("v_c", "m/s", "closing velocity", gt=0, le=20, name="impact_velocity")
    >>> v.check(1.25)
    1.25
    >>> v.allowed()
    '> 0 and <= 20'
    >>> v.check(30)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: impact_velocity = 30 m/s is not allowed: must be a ...
    """

    symbol: str | None = None
    unit: str = ""
    doc: str = ""
    kind: Kind = "real"
    gt: float | None = None
    ge: float | None = None
    lt: float | None = None
    le: float | None = None
    choices: tuple[str, ...] = ()
    typical: tuple[float, float] | None = None
    optional: bool = False
    none: str = ""
    default: Any = None
    name: str = ""
    owner: str = ""
    min_length: int | None = None
    max_length: int | None = None

    # ------------------------------------------------------------------ text
    @property
    def qualname(self) -> str:
        """``Owner.name`` (or ``name`` for a standalone declaration)."""
        return f"{self.owner}.{self.name}" if self.owner else self.name

    @property
    def description(self) -> str:
        """The meaning with its symbol: ``"head mass M_h"``."""
        sym = f" {self.symbol}" if self.symbol else ""
        return f"{self.doc}{sym}"

    def allowed(self) -> str:
        """The allowed range as text, without the unit (``"> 0 and <= 100"``)."""
        if self.kind == "choice":
            return "one of " + ", ".join(self.choices)
        if self.kind == "flag":
            return "true or false"
        if self.kind == "text":
            return self._lengths()
        if self.kind == "object":
            return ""
        parts = [f"{op} {_fmt(b)}" for op, b in self._bounds() if b is not None]
        return " and ".join(parts) or "any finite value"

    def _lengths(self) -> str:
        lo, hi = self.min_length, self.max_length
        if lo is not None and hi is not None:
            return f"{lo} to {hi} characters"
        if lo is not None:
            return f"at least {lo} characters"
        return f"at most {hi} characters" if hi is not None else ""

    def _bounds(self) -> list[tuple[str, float | None]]:
        return [(">", self.gt), (">=", self.ge), ("<", self.lt), ("<=", self.le)]

    def _what(self) -> str:
        noun = "an integer" if self.kind == "integer" else "a finite number"
        rng = self.allowed()
        text = noun if rng == "any finite value" else f"{noun} {rng}"
        return text + (" or None" if self.optional else "")

    # ------------------------------------------------------------ validation
    def within(self, value: float) -> bool:
        """Whether a number is inside the bounds (and finite).

        Parameters
        ----------
        value
            A value in the parameter's unit.
        """
        return bool(
            math.isfinite(value)
            and (self.gt is None or value > self.gt)
            and (self.ge is None or value >= self.ge)
            and (self.lt is None or value < self.lt)
            and (self.le is None or value <= self.le)
        )

    def check(self, value: Any, name: str | None = None) -> Any:
        """Return ``value`` validated and coerced (float, int, str, bool), or raise.

        Parameters
        ----------
        value
            The value given.
        name
            The name in the error message (default: ``Owner.name``).
        """
        label = name or self.qualname or (self.symbol or "parameter")
        if value is None and self.optional:
            return None
        if self.kind == "real":
            return self._check_real(label, value)
        if self.kind == "integer":
            return self._check_integer(label, value)
        if self.kind == "choice":
            if not isinstance(value, str) or value not in self.choices:
                raise InvalidParameterError(label, value, f"must be one of {list(self.choices)}")
            return value
        if self.kind == "flag":
            if not isinstance(value, (bool, np.bool_)):
                raise InvalidParameterError(label, value, "must be True or False")
            return bool(value)
        if self.kind == "text":
            return self._check_text(label, value)
        return value

    def _check_text(self, label: str, value: Any) -> str:
        lengths = self._lengths()
        what = "must be a text (str)" + (f" of {lengths}" if lengths else "")
        if not isinstance(value, str):
            raise InvalidParameterError(label, value, what)
        if (self.min_length is not None and len(value) < self.min_length) or (
            self.max_length is not None and len(value) > self.max_length
        ):
            shown = value if len(value) <= 80 else f"{value[:77]}..."
            raise InvalidParameterError(label, shown, what)
        return value

    def _check_real(self, label: str, value: Any) -> float:
        numeric = isinstance(value, (numbers.Real, np.floating, np.integer)) or (
            isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "fiu"
        )
        if isinstance(value, (bool, np.bool_, str, bytes)) or not numeric:
            raise InvalidParameterError(label, value, f"must be {self._what()}", self.unit)
        out = float(value)
        if not self.within(out):
            raise InvalidParameterError(label, value, f"must be {self._what()}", self.unit)
        return out

    def _check_integer(self, label: str, value: Any) -> int:
        ok = isinstance(value, (numbers.Integral, np.integer)) and not isinstance(
            value, (bool, np.bool_)
        )
        if not ok and isinstance(value, (float, np.floating)) and float(value).is_integer():
            ok = True
        if not ok:
            raise InvalidParameterError(label, value, f"must be {self._what()}", self.unit)
        out = int(value)
        if not self.within(out):
            raise InvalidParameterError(label, value, f"must be {self._what()}", self.unit)
        return out

    # -------------------------------------------------------- pydantic/schema
    def annotation(self, *, optional: bool | None = None) -> Any:
        """The pydantic type of this parameter (its JSON Schema follows from it).

        Parameters
        ----------
        optional
            Allow ``None`` (default: the declaration's ``optional``).

        Examples
        --------
        >>> from pydantic import TypeAdapter
        >>> t = TypeAdapter(Param("k", "N/m", "stiffness", gt=0, le=1e9).annotation())
        >>> t.json_schema()["exclusiveMinimum"], t.validate_python(3)
        (0.0, 3.0)
        """
        described = f"{self.description}" + (f", {self.unit}" if self.unit else "")
        rng = self.allowed()
        if rng and rng != "any finite value":
            described += f"; allowed {rng}"
        if self.optional and self.none:
            described += f"; null: {self.none}"
        bounds = {
            k: (float(v) if self.kind == "real" else int(v))
            for k, v in (("gt", self.gt), ("ge", self.ge), ("lt", self.lt), ("le", self.le))
            if v is not None
        }
        base: Any
        if self.kind == "real":
            base = Annotated[
                float,
                Field(allow_inf_nan=False, **bounds),
                BeforeValidator(_refuse_text_and_bool),
            ]
        elif self.kind == "integer":
            base = Annotated[int, Field(**bounds), BeforeValidator(_integral)]
        elif self.kind == "choice":
            base = Literal[self.choices]  # type: ignore[valid-type]
        elif self.kind == "flag":
            base = Annotated[bool, Field(strict=True)]
        elif self.kind == "text":
            lengths = {"min_length": self.min_length, "max_length": self.max_length}
            base = Annotated[str, Field(strict=True, **lengths)]
        else:
            base = Any
        allow_none = self.optional if optional is None else optional
        if allow_none:
            base = base | None  # type: ignore[operator]
        if not (self.doc or self.symbol):  # anonymous: a number type of the study models
            return base
        return Annotated[base, Field(description=described)]

    def json_bounds(self) -> dict[str, float]:
        """The range as JSON Schema keywords (``exclusiveMinimum``, ``minimum``, ...)."""
        keys = ("exclusiveMinimum", "minimum", "exclusiveMaximum", "maximum")
        return {
            k: float(b) for k, (_, b) in zip(keys, self._bounds(), strict=True) if b is not None
        }

    def but(self, **changes: Any) -> Param:
        """The same declaration with ``changes`` (a use that differs in what it says).

        Examples
        --------
        >>> ARG.seed.but(optional=True, none="fresh randomness").optional
        True
        """
        return dataclasses.replace(self, **changes)

    def field(self, **changes: Any) -> Any:
        """A :func:`declared` dataclass field carrying this declaration (and its default).

        Parameters
        ----------
        **changes
            As :meth:`but` (``doc="seed of the placement"``).

        Examples
        --------
        >>> from designlab.navigation.noise import SensorNoise  # seed: ARG.seed.field(doc=...)
        >>> seed = params_of(SensorNoise)["seed"]
        >>> seed.qualname, seed.default, seed.doc, seed.le == ARG.seed.le
        ('SensorNoise.seed', 0, 'seed of the generator', True)
        """
        decl = self.but(**changes)
        skip = {"symbol", "name", "owner", "default"}
        kwargs = {f.name: getattr(decl, f.name) for f in dataclasses.fields(Param)}
        kwargs = {k: v for k, v in kwargs.items() if k not in skip}
        return param(decl.symbol, default=decl.default, **kwargs)

    def doc_entry(self, type_name: str) -> str:
        """The numpydoc entry of this parameter (name, type, meaning, unit, range)."""
        unit = f" in {self.unit}" if self.unit else ""
        sym = f" {self.symbol}" if self.symbol else ""
        text = f"{self.doc[:1].upper()}{self.doc[1:]}{sym}{unit}"
        rng = self.allowed()
        if rng and rng != "any finite value" and self.kind in ("real", "integer"):
            text += f" ({rng})"
        elif self.kind == "choice" or (self.kind == "text" and rng):
            text += f" ({rng})"
        text += "."
        if self.typical is not None:
            lo, hi = self.typical
            text += f" Typical: {_fmt(lo)}-{_fmt(hi)}{(' ' + self.unit) if self.unit else ''}."
        if self.optional and self.none:
            text += f" ``None``: {self.none}."
        body = textwrap.fill(text, 80)
        return f"{self.name} : {type_name}\n" + textwrap.indent(body, "    ")


def param(
    symbol: str | None = None,
    unit: str = "",
    *,
    doc: str,
    kind: Kind = "real",
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
    choices: Sequence[str] = (),
    typical: tuple[float, float] | None = None,
    optional: bool = False,
    none: str = "",
    default: Any = _MISSING,
    default_factory: Callable[[], Any] | Any = _MISSING,
    compare: bool = True,
    min_length: int | None = None,
    max_length: int | None = None,
) -> Any:
    """Declare a dataclass field as a parameter (use inside a :func:`declared` class).

    Parameters
    ----------
    symbol
        The symbol in the source (``"K_c"``).
    unit
        SI unit (``"N/m"``).
    doc
        One line: what it is.
    kind
        ``"real"``, ``"integer"``, ``"choice"``, ``"flag"``, ``"text"`` or ``"object"``.
    gt, ge, lt, le
        Bounds.
    choices
        Allowed strings of a ``"choice"``.
    typical
        Typical range ``(low, high)``.
    optional
        ``None`` allowed.
    none
        What ``None`` means.
    default
        The default value (omit for a required parameter).
    default_factory
        A factory of the default (mutable defaults).
    compare
        Whether the field takes part in ``==``.
    min_length, max_length
        Shortest and longest text (``"text"``), in characters.

    Returns
    -------
    dataclasses.Field
        A field carrying the declaration in its metadata (key ``"param"``).
    """
    decl = Param(
        symbol=symbol,
        unit=unit,
        doc=doc,
        kind=kind,
        gt=gt,
        ge=ge,
        lt=lt,
        le=le,
        choices=tuple(choices),
        typical=typical,
        optional=optional,
        none=none,
        default=None if default is _MISSING else default,
        min_length=min_length,
        max_length=max_length,
    )
    kwargs: dict[str, Any] = {"metadata": {"param": decl}, "compare": compare}
    if default is not _MISSING:
        kwargs["default"] = default
    if default_factory is not _MISSING:
        kwargs["default_factory"] = default_factory
    return dataclasses.field(**kwargs)


_SECTION = re.compile(
    r"^(Attributes|Methods|Returns|Yields|Raises|Warns|See Also|Notes|References|Examples)\n-+$",
    re.MULTILINE,
)

_TYPE_NAMES = {"real": "float", "integer": "int", "choice": "str", "flag": "bool", "text": "str"}


def _type_name(decl: Param, field: dataclasses.Field) -> str:
    name = _TYPE_NAMES.get(decl.kind)
    if name is None:
        ann = field.type if isinstance(field.type, str) else getattr(field.type, "__name__", "")
        name = str(ann).replace(" | None", "")
    return f"{name} or None" if decl.optional else name


def _with_parameters_section(doc: str, entries: list[str]) -> str:
    doc = textwrap.dedent(doc or "").strip("\n")
    lines = doc.splitlines()
    if lines and not lines[0].startswith(" "):
        # the first line of a class docstring is not indented; dedent the rest
        rest = textwrap.dedent("\n".join(lines[1:]))
        doc = lines[0] + ("\n" + rest if rest else "")
    block = "Parameters\n----------\n" + "\n".join(entries) + "\n"
    match = _SECTION.search(doc)
    if match is None:
        return doc.rstrip() + "\n\n" + block
    return doc[: match.start()] + block + "\n" + doc[match.start() :]


def declared(cls: type) -> type:
    """Wrap a dataclass whose fields are declared with :func:`param`.

    The constructor validates each declared field (coercing it: a real to
    ``float``, an integer to ``int``) before the class's own ``__post_init__``
    runs (which then checks only relations between fields), and the class
    docstring gains the ``Parameters`` section. The declarations are
    :func:`params_of` the class.

    Parameters
    ----------
    cls
        A dataclass (frozen or not). Its docstring must not have a
        ``Parameters`` section of its own.

    Returns
    -------
    type
        The same class.
    """
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"@declared needs a dataclass, got {cls!r}")
    decls: dict[str, Param] = {}
    entries: list[str] = []
    for f in dataclasses.fields(cls):
        decl = f.metadata.get("param")
        if decl is None:
            continue
        default = f.default if f.default is not _MISSING else None
        decl = dataclasses.replace(decl, name=f.name, owner=cls.__name__, default=default)
        decls[f.name] = decl
        entries.append(decl.doc_entry(_type_name(decl, f)))
    own_doc = cls.__dict__.get("__doc__") or ""
    if re.search(r"^\s*Parameters\n\s*-+\s*$", own_doc, re.MULTILINE):
        raise TypeError(
            f"{cls.__name__}: the Parameters section is generated from the declarations; "
            "remove it from the docstring"
        )
    inherited = {}
    for base in cls.__mro__[1:]:
        inherited.update(getattr(base, "__params__", {}))
    all_decls = {**inherited, **decls}
    all_decls = {f.name: all_decls[f.name] for f in dataclasses.fields(cls) if f.name in all_decls}
    cls.__params__ = all_decls  # type: ignore[attr-defined]
    cls.__doc__ = _with_parameters_section(own_doc, entries) if entries else own_doc
    original = cls.__dict__.get("__post_init__")
    calls_post_init = hasattr(cls, "__post_init__")  # the dataclass __init__ calls it

    def _validate(self: Any) -> None:
        for name, decl in type(self).__params__.items():
            value = getattr(self, name)
            checked = decl.check(value, f"{type(self).__name__}.{name}")
            if checked is not value:
                object.__setattr__(self, name, checked)

    if calls_post_init:

        def __post_init__(self: Any) -> None:
            _validate(self)
            if original is not None:
                original(self)
            else:
                super(cls, self).__post_init__()  # type: ignore[misc]

        __post_init__.__qualname__ = f"{cls.__qualname__}.__post_init__"
        cls.__post_init__ = __post_init__  # type: ignore[attr-defined]
    else:
        init = cls.__init__

        def __init__(self: Any, *args: Any, **kwargs: Any) -> None:
            init(self, *args, **kwargs)
            _validate(self)

        __init__.__qualname__ = f"{cls.__qualname__}.__init__"
        __init__.__signature__ = inspect.signature(init)  # type: ignore[attr-defined]
        __init__.__doc__ = init.__doc__
        cls.__init__ = __init__  # type: ignore[method-assign]
    return cls


def params_of(cls: type | Any) -> dict[str, Param]:
    """The declarations of a :func:`declared` class (or of an instance's class).

    Parameters
    ----------
    cls
        The class or an instance.

    Returns
    -------
    dict
        Field name -> :class:`Param`, in field order.
    """
    if not isinstance(cls, type):
        cls = type(cls)
    out = getattr(cls, "__params__", None)
    if out is None:
        raise TypeError(f"{cls.__name__} declares no parameters (@declared)")
    return dict(out)


def sweepable(
    cls: type, prefix: str, *, names: Sequence[str] | None = None, key_prefix: str = ""
) -> dict[str, tuple[str, Param]]:
    """The real parameters of a model as sweep entries: ``"prefix.name" -> (key, Param)``.

    The key of a sweep point is the declaration's symbol (``"K_c"``).

    Parameters
    ----------
    cls
        A :func:`declared` class.
    prefix
        Dotted-path prefix in the study file (``"foam"``).
    names
        The fields to include (default: every real, non-optional field).
    key_prefix
        Prefix of the point keys (to keep two models' symbols apart).

    Returns
    -------
    dict
        Dotted path -> (point key, declaration).

    Examples
    --------
    >>> from designlab.impact import Foam
    >>> list(sweepable(Foam, "foam", names=["stiffness"]).items())[0][1][0]
    'K_c'
    """
    decls = params_of(cls)
    chosen = (
        names
        if names is not None
        else [n for n, d in decls.items() if d.kind == "real" and not d.optional]
    )
    out = {}
    for n in chosen:
        d = decls[n]
        out[f"{prefix}.{n}" if prefix else n] = (key_prefix + (d.symbol or n), d)
    return out


def parameter_table(cls: type | Sequence[Param]) -> Any:
    """The parameters as a table for reports and docs (one row per parameter).

    Parameters
    ----------
    cls
        A :func:`declared` class, or a list of declarations.

    Returns
    -------
    pandas.DataFrame
        Columns ``name, symbol, unit, allowed, default, typical, meaning``.
    """
    import pandas as pd

    decls = list(params_of(cls).values()) if isinstance(cls, type) else list(cls)
    rows = []
    for d in decls:
        default = "" if d.default is None else d.default
        typ = "" if d.typical is None else f"{_fmt(d.typical[0])}-{_fmt(d.typical[1])}"
        rows.append(
            {
                "name": d.name,
                "symbol": d.symbol or "",
                "unit": d.unit,
                "allowed": d.allowed(),
                "default": default,
                "typical": typ,
                "meaning": d.doc,
            }
        )
    return pd.DataFrame(rows)


class Arguments:
    """Arguments that functions of several domains share, each declared once (:data:`ARG`).

    A function taking one reads its default from the declaration and checks the value
    with it; a use that says more (a seed that may be ``None``) derives its own with
    :meth:`Param.but`, and a dataclass field takes it with :meth:`Param.field`.

    Parameters
    ----------
    *decls
        The declarations, each with its ``name``.

    Examples
    --------
    >>> def draw(n: int, *, seed: int = ARG.seed.default) -> int:
    ...     return ARG.seed.check(seed)
    >>> draw(3), ARG.confidence.default, "seed" in ARG
    (0, 0.95, True)
    >>> ARG.workers
    Traceback (most recent call last):
    ...
    AttributeError: no shared argument 'workers' is declared in designlab.params.ARG
    """

    def __init__(self, *decls: Param) -> None:
        self._decls = {d.name: d for d in decls}

    def __getattr__(self, name: str) -> Param:
        try:
            return self.__dict__["_decls"][name]  # type: ignore[no-any-return]
        except KeyError:
            raise AttributeError(
                f"no shared argument {name!r} is declared in designlab.params.ARG"
            ) from None

    def __iter__(self) -> Iterator[Param]:
        return iter(self._decls.values())

    def __contains__(self, name: object) -> bool:
        return name in self._decls


#: The arguments shared across the domains (``ARG.seed``, ``ARG.confidence``).
ARG = Arguments(
    Param(None, "", "seed of the random numbers (the same seed gives the same result)",
          kind="integer", ge=0, le=2**32 - 1, default=0, name="seed"),
    Param(None, "", "confidence level of an interval", gt=0, lt=1, default=0.95,
          name="confidence"),
)  # fmt: skip


def check_size(name: str, value: Any, elements: float, *, what: str = "") -> None:
    """Refuse an allocation of more than :data:`MAX_ELEMENTS` float64 values before it happens.

    Parameters
    ----------
    name
        The parameter that sets the size (named in the error).
    value
        Its value.
    elements
        The number of float64 values it would allocate.
    what
        What would be allocated (``"the simulation's time grid"``).

    Examples
    --------
    >>> check_size("duration", 1e7, 1e7 / 0.01 * 6, what="6 states at 100 Hz")
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: duration = 10000000.0 is not allowed: ...
    """
    if not math.isfinite(elements) or elements > MAX_ELEMENTS:
        gib = elements * 8 / 2**30 if math.isfinite(elements) else math.inf
        detail = f" for {what}" if what else ""
        raise InvalidParameterError(
            name,
            value,
            f"would need {gib:.3g} GiB{detail}; at most {MAX_ELEMENTS * 8 / 2**30:g} GiB "
            f"({MAX_ELEMENTS} values, designlab.params.MAX_ELEMENTS) are allowed",
        )
