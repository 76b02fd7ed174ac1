"""One registry per family of alternatives: name -> variant, and what derives from it.

A *family* is a set of interchangeable variants chosen by name: the navigation methods
(``method="vff"``), the tether laws, the impact contact models. Each variant is one
object (usually declared in its own module) with a public ``name``, a ``label`` for
reports, a one-line ``doc`` and whatever capabilities its family asks of it
(``batched``, ``stabilised``, ...). The family's :class:`Registry` holds them, and from
that one table derive

* the allowed names of the argument (:meth:`Registry.choices`, optionally only the
  variants with some capabilities, ``choices(batched=True)``);
* the look-up with a clear error naming the parameter, the value and the allowed names
  (:meth:`Registry.get`, an :class:`~designlab.errors.InvalidParameterError`);
* the declaration of the argument (:meth:`Registry.param`, a ``"choice"``
  :class:`~designlab.params.Param`), hence its pydantic ``Literal`` for the study specs
  (:meth:`Registry.literal`) and its JSON Schema enum (:meth:`Registry.json_schema`);
* the report labels (:meth:`Registry.label`, :meth:`Registry.labels`) and the docs table
  (:meth:`Registry.table`).

Engines, kinds and reports look a variant up and ask it; they never compare its name.

Examples
--------
>>> from dataclasses import dataclass
>>> @dataclass(frozen=True)
... class Law:
...     name: str
...     label: str
...     doc: str = ""
...     linear: bool = True
>>> laws = Registry("law", "spring laws", [Law("hooke", "Hooke", "F = k x"),
...                                        Law("cubic", "Cubic", "F = k x^3", linear=False)])
>>> laws.choices(), laws.choices(linear=True)
(('hooke', 'cubic'), ('hooke',))
>>> laws.get("cubic").label
'Cubic'
>>> laws.get("quartic")
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: law = 'quartic' is not allowed: must be one of ['hooke', ...
>>> laws.get("cubic", linear=True)
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: law = 'cubic' ... one of ['hooke'] (the spring laws with ...
>>> laws.json_schema()
{'enum': ['hooke', 'cubic'], 'type': 'string'}
>>> print(laws.table())
| name | label | description |
|---|---|---|
| `hooke` | Hooke | F = k x |
| `cubic` | Cubic | F = k x^3 |
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Mapping
from typing import Any, Generic, Literal, Protocol, TypeVar

from designlab.errors import InvalidParameterError
from designlab.params import Param

__all__ = ["Registry", "Variant"]


class Variant(Protocol):
    """What a registry asks of a variant: a public name and a report label."""

    @property
    def name(self) -> str: ...

    @property
    def label(self) -> str: ...


V = TypeVar("V", bound=Variant)


class Registry(Generic[V]):
    """The variants of one family, by public name, in declaration order.

    Parameters
    ----------
    parameter
        The argument that chooses a variant (``"method"``, ``"law"``): the name in error
        messages and in the derived :class:`~designlab.params.Param`.
    family
        What the variants are, plural (``"navigation methods"``): used in the docs and in
        the error raised for a variant without the requested capabilities.
    variants
        The variants; each has a unique ``name`` and a ``label`` (and optionally ``doc``).
    """

    def __init__(self, parameter: str, family: str, variants: Iterable[V] = ()) -> None:
        self.parameter = parameter
        self.family = family
        self._by_name: dict[str, V] = {}
        for v in variants:
            self.register(v)

    # ---------------------------------------------------------------- building
    def register(self, variant: V) -> V:
        """Add a variant (its name must be new); returns it, so it can decorate.

        Parameters
        ----------
        variant
            The variant, with a ``name`` and a ``label``.
        """
        name = getattr(variant, "name", None)
        if not isinstance(name, str) or not name:
            raise InvalidParameterError(
                f"{self.parameter} variant", variant, "must have a non-empty str name"
            )
        if name in self._by_name:
            raise InvalidParameterError(
                f"{self.parameter} variant name", name, f"is already registered in {self.family}"
            )
        self._by_name[name] = variant
        return variant

    # ---------------------------------------------------------------- look-up
    def __contains__(self, name: object) -> bool:
        return isinstance(name, str) and name in self._by_name

    def __iter__(self) -> Iterator[V]:
        return iter(self._by_name.values())

    def __len__(self) -> int:
        return len(self._by_name)

    def __repr__(self) -> str:
        return f"Registry({self.parameter!r}, {self.family!r}, {list(self._by_name)})"

    def variants(self, **capabilities: Any) -> tuple[V, ...]:
        """The variants whose attributes equal every given capability, in order.

        Parameters
        ----------
        **capabilities
            Attribute values the variants must have (``batched=True``).
        """
        return tuple(
            v
            for v in self._by_name.values()
            if all(getattr(v, k, None) == want for k, want in capabilities.items())
        )

    def choices(self, **capabilities: Any) -> tuple[str, ...]:
        """The allowed names (all, or those of the variants with the capabilities).

        Parameters
        ----------
        **capabilities
            As for :meth:`variants`.
        """
        return tuple(v.name for v in self.variants(**capabilities))

    def get(self, name: Any, *, parameter: str | None = None, **capabilities: Any) -> V:
        """The variant of a name, or an error naming the parameter, the value and the choices.

        Parameters
        ----------
        name
            The public name given.
        parameter
            The name in the error message (default: the registry's ``parameter``).
        **capabilities
            Only the variants with these attribute values are allowed here; a registered
            variant without them is refused with the names that are allowed.
        """
        allowed = self.choices(**capabilities)
        if isinstance(name, str) and name in allowed:
            return self._by_name[name]
        label = parameter or self.parameter
        why = ""
        if capabilities:
            caps = ", ".join(f"{k}={v!r}" for k, v in capabilities.items())
            why = f" (the {self.family} with {caps})"
        raise InvalidParameterError(label, name, f"must be one of {list(allowed)}{why}")

    # ---------------------------------------------------------------- derived
    def param(self, doc: str | None = None, *, default: Any = None, **capabilities: Any) -> Param:
        """The argument's declaration: a ``"choice"`` :class:`~designlab.params.Param`.

        Parameters
        ----------
        doc
            Its one-line meaning (default: the family, singular form not assumed).
        default
            The default name, if any.
        **capabilities
            Restrict the choices as for :meth:`choices`.
        """
        return Param(
            doc=doc or self.family,
            kind="choice",
            choices=self.choices(**capabilities),
            default=default,
            name=self.parameter,
        )

    def literal(self, **capabilities: Any) -> Any:
        """``Literal[...]`` of the names, for a pydantic field of a study spec.

        Parameters
        ----------
        **capabilities
            Restrict the choices as for :meth:`choices`.
        """
        return Literal[self.choices(**capabilities)]  # type: ignore[valid-type]

    def json_schema(self, **capabilities: Any) -> dict[str, Any]:
        """The JSON Schema of the argument: a string enum of the names.

        Parameters
        ----------
        **capabilities
            Restrict the choices as for :meth:`choices`.
        """
        return {"enum": list(self.choices(**capabilities)), "type": "string"}

    def label(self, name: str) -> str:
        """The report label of a name (checked as :meth:`get`).

        Parameters
        ----------
        name
            A registered name.
        """
        return self.get(name).label

    def labels(self, **capabilities: Any) -> dict[str, str]:
        """``{name: label}`` of the variants (with the capabilities), in order.

        Parameters
        ----------
        **capabilities
            Restrict the variants as for :meth:`variants`.
        """
        return {v.name: v.label for v in self.variants(**capabilities)}

    def table(
        self,
        columns: Mapping[str, Callable[[V], Any]] | None = None,
        **capabilities: Any,
    ) -> str:
        """A markdown table of the variants for the docs: name, label, description, ...

        Parameters
        ----------
        columns
            Extra columns: header -> function of the variant giving the cell.
        **capabilities
            Restrict the variants as for :meth:`variants`.
        """
        cols: dict[str, Callable[[V], Any]] = {
            "name": lambda v: f"`{v.name}`",
            "label": lambda v: v.label,
            "description": lambda v: getattr(v, "doc", ""),
        }
        cols.update(columns or {})
        lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
        for v in self.variants(**capabilities):
            cells = (_cell(f(v)) for f in cols.values())
            lines.append("| " + " | ".join(cells) + " |")
        return "\n".join(lines)


def _cell(value: Any) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    return str(value).replace("|", "\\|").replace("\n", " ")
