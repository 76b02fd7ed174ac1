"""Schema building blocks shared by every sweep study kind.

A sweep study has a ``base`` design, an optional ``sweep`` (the design points
of its results table) and an optional ``sensitivity`` block. The parameters a
kind can sweep are fields of a kind-specific model built by
:func:`parameter_model`, one field per dotted path (``foam.stiffness``), each
with its unit and allowed range, so that a misspelt path is reported with a
"did you mean" and an out-of-range value with the allowed range and unit.

Sampling methods (``sweep.method``):

``list``
    Every parameter gives ``values`` of the same length; point i takes the
    i-th value of each (a table of designs).
``grid``
    The Cartesian product of each parameter's ``values`` (or of ``num``
    points between ``low`` and ``high``, ``scale: linear | log``).
``lhs``
    ``samples`` seeded Latin-hypercube points in the box ``low``-``high``
    (:class:`scipy.stats.qmc.LatinHypercube`).
``sobol``
    ``samples`` (a power of two) seeded scrambled Sobol points
    (:class:`scipy.stats.qmc.Sobol`).

Examples
--------
>>> info = Param("K_c", "N/m", "foam stiffness", gt=0)
>>> Params = parameter_model("Demo", {"foam.stiffness": info})
>>> p = Params.model_validate({"foam.stiffness": {"low": 1e4, "high": 6e4, "num": 3}})
>>> [(path, rng.grid()) for path, rng in p.items()]
[('foam.stiffness', [10000.0, 35000.0, 60000.0])]
>>> from pydantic import ValidationError
>>> try:
...     Params.model_validate({"foam.stiffness": {"values": [-1]}})
... except ValidationError as exc:
...     print(exc.errors()[0]["msg"])
Value error, -1 N/m is out of range for foam stiffness K_c: allowed > 0 N/m
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Annotated, Any, ClassVar, Generic, Literal, TypeVar

from pydantic import BaseModel, Field, create_model, model_validator

from designlab.analysis.sampling import MAX_SALTELLI_SAMPLES
from designlab.params import Param
from designlab.study.base import Finite as _Finite
from designlab.study.base import Flag, Integer, StudyBase, did_you_mean
from designlab.study.base import Model as _Model

__all__ = [
    "MAX_POINTS",
    "OneAtATimeSpec",
    "ParameterRange",
    "SensitivitySpec",
    "SobolSpec",
    "SweepSpec",
    "SweepStudyBase",
    "parameter_model",
]


#: The most points a sweep (or a sensitivity block) may have: a guard against a
#: mistyped size, not a memory limit (a streamed sweep's memory does not grow with
#: its points; its store takes about 50 bytes per point, docs/sweeps.md).
MAX_POINTS = 10_000_000


def _allowed_with_unit(info: Param) -> str:
    return f"{info.allowed()} {info.unit}".rstrip()


class ParameterRange(_Model):
    """How one parameter varies: explicit ``values``, or ``low``/``high`` (and ``num``).

    Units are those of the parameter (SI; see its description).
    """

    INFO: ClassVar[Param | None] = None

    values: list[_Finite] | None = Field(
        None, min_length=1, description="explicit values (methods list and grid)"
    )
    low: _Finite | None = Field(None, description="lower bound of the range")
    high: _Finite | None = Field(None, description="upper bound of the range")
    num: Annotated[Integer, Field(ge=2, le=100_000)] | None = Field(
        None, description="grid: number of points from low to high"
    )
    scale: Literal["linear", "log"] = Field(
        "linear", description="spacing of grid points / sampling density"
    )

    @model_validator(mode="after")
    def _consistent(self) -> ParameterRange:
        has_range = self.low is not None or self.high is not None
        if self.values is not None and (has_range or self.num is not None):
            raise ValueError("give either values or low/high (and num), not both")
        if self.values is None:
            if self.low is None or self.high is None:
                raise ValueError("give values: [...] or both low and high")
            if not self.low < self.high:
                raise ValueError(f"low = {self.low:g} must be < high = {self.high:g}")
        if self.scale == "log" and min(self.bounds_or_values()) <= 0:
            raise ValueError("scale: log needs positive values")
        info = self.INFO
        if info is not None:
            for v in self.bounds_or_values():
                if not info.within(v):
                    raise ValueError(
                        f"{v:g} {info.unit} is out of range for {info.description}: "
                        f"allowed {_allowed_with_unit(info)}".replace("  ", " ")
                    )
        return self

    def bounds_or_values(self) -> list[float]:
        """The values given (``values``, or ``[low, high]``)."""
        if self.values is not None:
            return list(self.values)
        return [float(self.low), float(self.high)]  # type: ignore[arg-type]

    @property
    def has_range(self) -> bool:
        """Whether ``low`` and ``high`` are given."""
        return self.low is not None

    def grid(self) -> list[float]:
        """Grid values: ``values``, or ``num`` points from low to high."""
        import numpy as np

        if self.values is not None:
            return list(self.values)
        if self.num is None:
            raise ValueError("a grid needs values or num")
        if self.scale == "log":
            return [float(x) for x in np.geomspace(self.low, self.high, self.num)]
        return [float(x) for x in np.linspace(self.low, self.high, self.num)]

    def span(self) -> tuple[float, float]:
        """``(low, high)``, or the min and max of ``values``."""
        vals = self.bounds_or_values()
        return min(vals), max(vals)


def parameter_model(name: str, parameters: dict[str, Param]) -> type[BaseModel]:
    """Build the model of a kind's ``sweep.parameters`` mapping.

    One optional field per dotted path (the YAML key), each validated against
    its :class:`~designlab.params.Param`. The model has ``items()`` (the given
    parameters in file order) and ``INFO`` (path -> info).

    Parameters
    ----------
    name
        Name of the generated model (shown in the JSON Schema).
    parameters
        Dotted path -> :class:`~designlab.params.Param`.
    """
    # The caller's module (a kind's, which binds the model under ``name``): the models are
    # created there, and each range model bound there under its name, so that they pickle.
    module = sys._getframe(1).f_globals.get("__name__", __name__)
    fields: dict[str, Any] = {}
    for path, info in parameters.items():
        bounded = Annotated[_Finite, Field(json_schema_extra=info.json_bounds())]  # type: ignore[arg-type]
        rng = create_model(  # type: ignore[call-overload]
            f"{name}_{path.replace('.', '_')}",
            __base__=ParameterRange,
            __module__=module,
            __doc__=f"{info.description}, {info.unit}; allowed {_allowed_with_unit(info)}",
            values=(list[bounded] | None, Field(None, min_length=1, description="explicit values")),
            low=(bounded | None, Field(None, description="lower bound of the range")),
            high=(bounded | None, Field(None, description="upper bound of the range")),
        )
        rng.INFO = info
        if module in sys.modules:
            setattr(sys.modules[module], rng.__name__, rng)
        fields[path.replace(".", "__")] = (
            rng | None,
            Field(None, alias=path, description=f"{info.description}, {info.unit}"),
        )

    def items(self: BaseModel) -> list[tuple[str, ParameterRange]]:
        out = []
        for key, field in type(self).model_fields.items():
            value = getattr(self, key)
            if value is not None:
                out.append((field.alias or key, value))
        return out

    def _at_least_one(self: BaseModel) -> BaseModel:
        if not self.model_fields_set:
            raise ValueError(f"give at least one parameter (known: {', '.join(parameters)})")
        return self

    model = create_model(  # type: ignore[call-overload]
        name,
        __base__=_Model,
        __module__=module,
        __validators__={"_at_least_one": model_validator(mode="after")(_at_least_one)},
        **fields,
    )
    model.items = items
    model.INFO = dict(parameters)
    model.__doc__ = "Parameters to vary, by dotted path. " + "; ".join(
        f"``{p}``: {i.description}, {i.unit}" for p, i in parameters.items()
    )
    return model  # type: ignore[no-any-return]


def _power_of_two(n: int) -> bool:
    return n > 0 and (n & (n - 1)) == 0


class SweepSpec(_Model):
    """The design points of a sweep (subclassed per kind with its ``parameters``)."""

    method: Literal["list", "grid", "lhs", "sobol"] = Field(
        "grid", description="list | grid | lhs (Latin hypercube) | sobol (quasi-random)"
    )
    samples: Annotated[Integer, Field(ge=1, le=MAX_POINTS)] | None = Field(
        None, description="number of points (lhs, sobol: a power of two)"
    )
    seed: Annotated[Integer, Field(ge=0)] = Field(0, description="seed of lhs/sobol sampling")
    parameters: Any

    @model_validator(mode="after")
    def _method_fits(self) -> SweepSpec:
        items = self.parameters.items()
        if self.method in ("lhs", "sobol"):
            if self.samples is None:
                raise ValueError(f"method {self.method} needs samples: N")
            if self.method == "sobol" and not _power_of_two(self.samples):
                raise ValueError(
                    f"method sobol needs samples to be a power of two (got {self.samples}; "
                    f"try {1 << max(self.samples - 1, 1).bit_length()})"
                )
            for path, rng in items:
                if not rng.has_range:
                    raise ValueError(f"method {self.method}: {path} needs low and high")
        else:
            if self.samples is not None:
                raise ValueError(
                    f"samples is only used by methods lhs and sobol, not {self.method}"
                )
        if self.method == "list":
            lengths = {path: len(rng.values or ()) for path, rng in items}
            if any(rng.values is None for _, rng in items) or len(set(lengths.values())) != 1:
                raise ValueError(
                    "method list needs values of the same length for every parameter "
                    f"(got {lengths})"
                )
        if self.method == "grid":
            for path, rng in items:
                if rng.values is None and rng.num is None:
                    raise ValueError(f"method grid: {path} needs values or low, high and num")
        n = self.count()
        if n > MAX_POINTS:
            raise ValueError(
                f"the {self.method} has {n:,} points; at most {MAX_POINTS:,} are allowed "
                "(use lhs or sobol sampling, or fewer values per parameter)"
            )
        return self

    def count(self) -> int:
        """How many points the sweep has (computed without building them)."""
        items = self.parameters.items()
        if self.method in ("lhs", "sobol"):
            return int(self.samples or 0)
        if self.method == "list":
            return len(items[0][1].values or ()) if items else 0
        n = 1
        for _, rng in items:
            n *= len(rng.values) if rng.values is not None else int(rng.num or 0)
        return n


class OneAtATimeSpec(_Model):
    """One-at-a-time perturbations of the base design (the Appendix-C table form)."""

    deltas_pct: list[Annotated[_Finite, Field(ge=-100, le=1000)]] = Field(
        default_factory=lambda: [-50.0, -20.0, -10.0, -5.0, -2.0, 2.0, 5.0, 10.0, 20.0, 50.0],
        min_length=1,
        description="perturbations of each parameter, % of its base value",
    )
    parameters: list[str] | None = Field(
        None, description="dotted paths (default: the sweep parameters)"
    )


class SobolSpec(_Model):
    """Variance-based Sobol indices (SALib: Saltelli sampling, Sobol analysis)."""

    samples: Annotated[Integer, Field(ge=2, le=MAX_SALTELLI_SAMPLES)] = Field(
        256, description="base sample N (a power of two); N (D + 2) model runs"
    )
    seed: Annotated[Integer, Field(ge=0)] = Field(0, description="seed of sampling and bootstrap")
    parameters: list[str] | None = Field(
        None, description="dotted paths, ranges from the sweep (default: all with a range)"
    )

    @model_validator(mode="after")
    def _pow2(self) -> SobolSpec:
        if not _power_of_two(self.samples):
            raise ValueError(
                f"samples must be a power of two (got {self.samples}; "
                f"try {1 << max(self.samples - 1, 1).bit_length()})"
            )
        return self


ParametersT = TypeVar("ParametersT", bound=BaseModel)
MetricT = TypeVar("MetricT")


def _parametrized(origin: Any, args: tuple[Any, ...]) -> Any:
    """A blank instance of ``origin[args]`` (pydantic returns the same class each time)."""
    cls = origin[args if len(args) > 1 else args[0]]
    return cls.__new__(cls)


class _PicklableGeneric(BaseModel):
    """Pickled as its generic origin and arguments: a parametrized model such as
    ``SweepOf[ImpactSweepParameters]`` is made inside another class's parametrization,
    so pickle cannot find it by name (a sweep study's result would not pickle)."""

    def __reduce__(self) -> Any:
        meta = type(self).__pydantic_generic_metadata__
        if meta["origin"] is None:
            return super().__reduce__()
        return _parametrized, (meta["origin"], meta["args"]), self.__getstate__()


class SweepOf(SweepSpec, _PicklableGeneric, Generic[ParametersT]):
    """The ``sweep`` block of a kind whose parameters model is ``ParametersT``."""

    parameters: ParametersT


class SensitivitySpec(_Model, _PicklableGeneric, Generic[MetricT]):
    """The ``sensitivity`` block: which tables to compute, for which metrics."""

    metrics: list[MetricT] | None = Field(
        None, min_length=1, description="metrics to analyse (default: the kind's default metrics)"
    )
    local: Flag = Field(True, description="elasticities d ln(metric) / d ln(parameter) at the base")
    one_at_a_time: OneAtATimeSpec | None = Field(
        None, description="percentage perturbation table (Zeng 2011 App. C form)"
    )
    sobol: SobolSpec | None = Field(None, description="global Sobol indices (SALib)")
    tornado: Flag = Field(
        True, description="metric at each sweep parameter's low and high (others at base)"
    )


class SweepStudyBase(StudyBase, Generic[ParametersT, MetricT]):
    """A study kind that sweeps a design: ``base``, ``sweep`` and ``sensitivity``.

    ``sweep`` and ``sensitivity`` are declared here once; a kind subclasses
    ``SweepStudyBase[ItsParameters, ItsMetricLiteral]``, declares its ``base``
    and sets the class attributes:

    ``PARAMETERS``
        dotted path -> (point key, :class:`~designlab.params.Param`): what can be swept.
    ``METRICS``
        result column -> description with unit (one table per domain).
    ``DEFAULT_METRICS``
        the metrics analysed when the study does not list them.
    ``EVALUATOR``
        the domain's module-level evaluator ``(points, options) -> columns``
        (see :mod:`designlab.analysis.engine`), sent to workers by reference.
    ``LOCAL_EVALUATOR``
        optional: evaluator of exact elasticities at the base (else the
        elasticities are not computed).
    ``MAX_POINTS``
        the most points a study of the kind may evaluate (every set together,
        :meth:`point_counts`): a kind whose points are expensive (a simulation
        each) sets it so that a mistyped size is refused when the study is
        validated, naming the field, the count and the cap, instead of running
        for days. The default is the schema's absolute cap, :data:`MAX_POINTS`.
    """

    sweep: SweepOf[ParametersT] | None = None
    sensitivity: SensitivitySpec[MetricT] | None = None

    PARAMETERS: ClassVar[dict[str, tuple[str, Param]]] = {}
    METRICS: ClassVar[dict[str, str]] = {}
    DEFAULT_METRICS: ClassVar[tuple[str, ...]] = ()
    EVALUATOR: ClassVar[Callable[..., Any] | None] = None
    LOCAL_EVALUATOR: ClassVar[Callable[..., Any] | None] = None
    NEEDS_SWEEP_OR_SENSITIVITY: ClassVar[bool] = False
    MAX_POINTS: ClassVar[int] = MAX_POINTS
    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "results.csv",
        "sensitivity_*.csv",
        "*.png",
        "study.yaml",
    )

    def base_point(self) -> dict[str, float]:  # pragma: no cover - every kind overrides it
        """The base design as a plain point dictionary."""
        raise NotImplementedError

    def evaluator_options(self) -> dict[str, Any]:
        """Settings of the evaluator that are the same for every point."""
        return {}

    @property
    def metrics(self) -> list[str]:
        """The metrics analysed."""
        sens = self.sensitivity
        if sens is None:
            return list(self.METRICS)
        if sens.metrics:
            return [str(m) for m in sens.metrics]
        return list(self.DEFAULT_METRICS or self.METRICS)

    def point_counts(self) -> dict[str, int]:
        """Points evaluated per set (``base``, ``sweep``, ``one_at_a_time``, ``range``,
        ``sobol``, ``local``), computed from the study without building any point."""
        sens, sweep = self.sensitivity, self.sweep
        swept = [p for p, _ in sweep.parameters.items()] if sweep is not None else []
        counts = {"base": 1, "sweep": sweep.count() if sweep is not None else 0}
        if sens is not None:
            oat = sens.one_at_a_time
            if oat is not None:
                counts["one_at_a_time"] = len(oat.parameters or swept) * len(oat.deltas_pct)
            if sens.tornado:
                counts["range"] = 2 * len(swept)
            if sens.sobol is not None:
                names = sens.sobol.parameters or swept
                counts["sobol"] = sens.sobol.samples * (len(names) + 2)
            counts["local"] = int(bool(sens.local and self.LOCAL_EVALUATOR is not None))
        return counts

    def size(self) -> str:
        """The number of points, for ``designlab validate``."""
        return f"{sum(self.point_counts().values())} points"

    @model_validator(mode="after")
    def _within_cap(self) -> SweepStudyBase[ParametersT, MetricT]:
        counts = self.point_counts()
        total, cap = sum(counts.values()), type(self).MAX_POINTS
        if total <= cap:
            return self
        largest = max(counts, key=lambda s: counts[s])
        sweep = self.sweep
        field = {
            "sweep": "sweep.samples"
            if sweep is not None and sweep.method in ("lhs", "sobol")
            else "sweep.parameters",
            "sobol": "sensitivity.sobol.samples",
            "one_at_a_time": "sensitivity.one_at_a_time",
        }.get(largest, "sweep")
        raise ValueError(
            f"{field}: the study has {total:,} points ({counts[largest]:,} from {field}); a "
            f"study of kind {self.kind} evaluates at most {cap:,} (each point costs a full "
            "evaluation; see docs/sweeps.md): give fewer points"
        )

    @model_validator(mode="after")
    def _check_paths(self) -> SweepStudyBase[ParametersT, MetricT]:
        sens, sweep = self.sensitivity, self.sweep
        if self.NEEDS_SWEEP_OR_SENSITIVITY and sweep is None and sens is None:
            raise ValueError("give a sweep, a sensitivity block, or both")
        if sens is None:
            return self
        swept = [p for p, _ in sweep.parameters.items()] if sweep is not None else []
        known = list(self.PARAMETERS)
        for block, label in ((sens.one_at_a_time, "one_at_a_time"), (sens.sobol, "sobol")):
            if block is None:
                continue
            paths = block.parameters if block.parameters is not None else swept
            if not paths:
                raise ValueError(
                    f"sensitivity.{label}: give parameters: [...] or a sweep with parameters"
                )
            for path in paths:
                if path not in known:
                    raise ValueError(
                        f"sensitivity.{label}.parameters: unknown parameter {path!r}"
                        f"{did_you_mean(path, known)} (known: {', '.join(known)})"
                    )
            if label == "sobol":
                ranged = {p for p, _ in sweep.parameters.items()} if sweep is not None else set()
                missing = [p for p in paths if p not in ranged]
                if missing:
                    raise ValueError(
                        f"sensitivity.sobol: {', '.join(missing)} need a range in "
                        "sweep.parameters (low/high or values)"
                    )
                if len(paths) < 2:
                    raise ValueError("sensitivity.sobol needs at least two parameters")
                n = sens.sobol.samples * (len(paths) + 2)  # type: ignore[union-attr]
                if n > MAX_POINTS:
                    raise ValueError(
                        f"sensitivity.sobol needs {n:,} points; at most {MAX_POINTS:,} are allowed"
                    )
        return self
