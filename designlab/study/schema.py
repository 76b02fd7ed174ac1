"""The YAML study schema (pydantic v2).

A study file is a mapping with a format version, a ``kind`` that selects the
study type, a ``name`` (also the report directory name) and kind-specific
fields. Every model forbids unknown fields, so a typo is an error rather than
a silently ignored setting.

Study kinds form a discriminated union on ``kind``:

``impact_cases``
    A list of single impacts (manipulator, foam, head, closing speed), each
    simulated with :func:`designlab.impact.simulate` and compared with
    optional reference values (for example a thesis table).
``impact_sweep``
    A parameter sweep of the impact metrics with sensitivity tables.
``foam_envelope``
    A parameter sweep of the feasible foam region with sensitivity tables.
``foam_design``
    The foam covering design report: envelopes for several robots, foam
    verdicts, safe speeds, thickness and the optimal foam.

Later kinds (navigation, following) subclass :class:`StudyBase`, fix ``kind``
to their own literal and are added to :data:`Study`.

Units are SI throughout: kg, N/m, N s/m, m, m/s, s.

Examples
--------
>>> from designlab.study.schema import STUDY_ADAPTER
>>> study = STUDY_ADAPTER.validate_python({
...     "designlab": 1, "kind": "impact_cases", "name": "demo",
...     "cases": [{"robot": "MANIPULATOR_1", "foam": "FOAM_1",
...                "head": "TEST_HEAD", "v_r": 0.25, "v_h": -1.0}]})
>>> study.cases[0].closing_velocity
1.25
>>> study.cases[0].robot.build().mass
9.6
"""

from __future__ import annotations

import difflib
from typing import Annotated, Any, ClassVar, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    TypeAdapter,
    field_validator,
    model_validator,
)

from designlab.impact.criteria import (
    ISO_TS_15066_QUASI_STATIC_FORCE,
    Criterion,
    HeadAcceleration,
    HeadInjuryCriterion,
    ImpactForce,
    IsoTransientForce,
)
from designlab.impact.envelope import HeadRange
from designlab.impact.parameters import (
    FOAM_1,
    FOAM_2,
    FOAM_2_MEASURED,
    FOAM_3,
    HEAD_MAX,
    HEAD_MIN,
    MANIPULATOR_1,
    MANIPULATOR_2,
    TEST_HEAD,
    ContactDynamics,
    Foam,
    HeadNeck,
)
from designlab.study.sweeps import (
    OneAtATimeSpec,
    ParameterInfo,
    SobolSpec,
    SweepSpec,
    parameter_model,
)

__all__ = [
    "ENVELOPE_METRICS",
    "ENVELOPE_PARAMETERS",
    "FORMAT_VERSION",
    "IMPACT_METRICS",
    "IMPACT_PARAMETERS",
    "STUDY_ADAPTER",
    "STUDY_KINDS",
    "FoamEnvelopeStudy",
    "FoamSpec",
    "HeadSpec",
    "ImpactCase",
    "ImpactCasesStudy",
    "ImpactDesign",
    "ImpactReference",
    "ImpactSensitivitySpec",
    "ImpactSweepSpec",
    "ImpactSweepStudy",
    "ImpactTolerance",
    "RobotSpec",
    "Study",
    "StudyBase",
    "SweepStudyBase",
    "did_you_mean",
    "study_json_schema",
]

#: The study file format this version of designlab reads (the ``designlab:`` key).
FORMAT_VERSION = 1


def did_you_mean(word: str, choices: list[str] | tuple[str, ...] | set[str]) -> str:
    """Return ``"; did you mean 'x'?"`` for the closest choice, or ``""``.

    Examples
    --------
    >>> did_you_mean("stifness", ["mass", "stiffness", "damping"])
    "; did you mean 'stiffness'?"
    >>> did_you_mean("zzz", ["mass"])
    ''
    """
    close = difflib.get_close_matches(str(word), sorted(choices), n=1, cutoff=0.6)
    return f"; did you mean {close[0]!r}?" if close else ""


def _reject_bool(value: Any) -> Any:
    # YAML ``yes``/``true`` would otherwise be accepted as 1.0 by pydantic's lax mode.
    if isinstance(value, bool):
        raise ValueError("must be a number, not a boolean")
    return value


_Number = Annotated[float, BeforeValidator(_reject_bool)]
Positive = Annotated[_Number, Field(gt=0, allow_inf_nan=False)]
NonNegative = Annotated[_Number, Field(ge=0, allow_inf_nan=False)]
Finite = Annotated[_Number, Field(allow_inf_nan=False)]
#: Speeds are limited to a sanity range; human-robot impacts are a few m/s.
Speed = Annotated[_Number, Field(ge=-20.0, le=20.0, allow_inf_nan=False)]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


# --- physical components ----------------------------------------------------


class _ComponentSpec(_Model):
    """A preset name, or explicit values, or a preset with some values replaced."""

    PRESETS: ClassVar[dict[str, Any]] = {}
    REQUIRED: ClassVar[tuple[str, ...]] = ()
    WHAT: ClassVar[str] = "component"

    preset: str | None = Field(None, description="name of a preset to start from")

    @model_validator(mode="before")
    @classmethod
    def _preset_shorthand(cls, data: Any) -> Any:
        # ``robot: MANIPULATOR_1`` is short for ``robot: {preset: MANIPULATOR_1}``
        return {"preset": data} if isinstance(data, str) else data

    @field_validator("preset")
    @classmethod
    def _known_preset(cls, value: str | None) -> str | None:
        if value is not None and value not in cls.PRESETS:
            known = ", ".join(cls.PRESETS)
            raise ValueError(
                f"unknown {cls.WHAT} preset {value!r}{did_you_mean(value, list(cls.PRESETS))} "
                f"(known: {known})"
            )
        return value

    @model_validator(mode="after")
    def _complete(self) -> _ComponentSpec:
        if self.preset is None:
            missing = [f for f in self.REQUIRED if getattr(self, f) is None]
            if missing:
                raise ValueError(
                    f"give a preset ({', '.join(self.PRESETS)}) or all of "
                    f"{', '.join(self.REQUIRED)}; missing: {', '.join(missing)}"
                )
        return self

    def _overrides(self) -> dict[str, Any]:
        return {k: v for k, v in self.model_dump(exclude={"preset"}).items() if v is not None}

    def build(self) -> Any:
        """Return the designlab parameter object (validated by its constructor)."""
        overrides = self._overrides()
        if self.preset is None:
            return self._cls()(**overrides)
        base = self.PRESETS[self.preset]
        return base.replace(**overrides) if overrides else base

    @classmethod
    def _cls(cls) -> type:
        raise NotImplementedError


class RobotSpec(_ComponentSpec):
    """Effective manipulator at the impact point (:class:`~designlab.impact.ContactDynamics`).

    Presets: ``MANIPULATOR_1`` (direct-drive arm), ``MANIPULATOR_2`` (Puma 560).
    """

    PRESETS: ClassVar[dict[str, Any]] = {
        "MANIPULATOR_1": MANIPULATOR_1,
        "MANIPULATOR_2": MANIPULATOR_2,
    }
    REQUIRED: ClassVar[tuple[str, ...]] = ("mass", "stiffness", "damping")
    WHAT: ClassVar[str] = "robot"

    mass: Positive | None = Field(None, description="effective mass M_r, kg")
    stiffness: NonNegative | None = Field(None, description="stiffness K_r, N/m")
    damping: NonNegative | None = Field(None, description="damping C_r, N s/m")

    @classmethod
    def _cls(cls) -> type:
        return ContactDynamics

    def build(self) -> ContactDynamics:
        """Return the :class:`~designlab.impact.ContactDynamics`."""
        return super().build()  # type: ignore[no-any-return]


class FoamSpec(_ComponentSpec):
    """Foam covering (:class:`~designlab.impact.Foam`).

    Presets: ``FOAM_1``, ``FOAM_2`` (Table 3.3), ``FOAM_2_MEASURED`` (App. A.1,
    used for Ch. 4), ``FOAM_3``.
    """

    PRESETS: ClassVar[dict[str, Any]] = {
        "FOAM_1": FOAM_1,
        "FOAM_2": FOAM_2,
        "FOAM_2_MEASURED": FOAM_2_MEASURED,
        "FOAM_3": FOAM_3,
    }
    REQUIRED: ClassVar[tuple[str, ...]] = ("stiffness", "damping")
    WHAT: ClassVar[str] = "foam"

    stiffness: Positive | None = Field(None, description="stiffness K_c, N/m")
    damping: NonNegative | None = Field(None, description="damping C_c, N s/m")
    linear_depth: Positive | None = Field(
        None, description="lambda, end of the linear range, m (default 0.02)"
    )
    thickness: Positive | None = Field(None, description="uncompressed thickness T_u, m")

    @classmethod
    def _cls(cls) -> type:
        return Foam

    def build(self) -> Foam:
        """Return the :class:`~designlab.impact.Foam`."""
        return super().build()  # type: ignore[no-any-return]


class HeadSpec(_ComponentSpec):
    """Head on a neck (:class:`~designlab.impact.HeadNeck`).

    Presets: ``HEAD_MIN``, ``HEAD_MAX`` (Sec. 3.6), ``TEST_HEAD`` (Ch. 4 apparatus).
    """

    PRESETS: ClassVar[dict[str, Any]] = {
        "HEAD_MIN": HEAD_MIN,
        "HEAD_MAX": HEAD_MAX,
        "TEST_HEAD": TEST_HEAD,
    }
    REQUIRED: ClassVar[tuple[str, ...]] = ("mass", "stiffness", "damping")
    WHAT: ClassVar[str] = "head"

    mass: Positive | None = Field(None, description="head mass M_h, kg")
    stiffness: NonNegative | None = Field(None, description="neck stiffness K_h, N/m")
    damping: NonNegative | None = Field(None, description="neck damping C_h, N s/m")

    @classmethod
    def _cls(cls) -> type:
        return HeadNeck

    def build(self) -> HeadNeck:
        """Return the :class:`~designlab.impact.HeadNeck`."""
        return super().build()  # type: ignore[no-any-return]


# --- impact cases -------------------------------------------------------------


class ImpactTolerance(_Model):
    """Acceptance band of the model against the reference (reported, not enforced)."""

    a_h_max_rel: Positive | None = Field(None, description="relative, e.g. 0.02 for 2 %")
    t_imp_abs_s: Positive | None = Field(None, description="absolute, s")
    eps_max_rel: Positive | None = Field(None, description="relative")


class ImpactReference(_Model):
    """Reference values a case is compared with (e.g. a thesis table).

    ``a_h_max_g``, ``t_imp_s`` and ``eps_max_m`` are the reference *simulation*
    (the source's model); ``exp_*`` are experimental means.
    """

    source: str | None = Field(None, description="where the numbers come from")
    a_h_max_g: Positive | None = None
    t_imp_s: Positive | None = None
    eps_max_m: Positive | None = None
    peak_force_N: Positive | None = None
    exp_a_h_max_g: Positive | None = None
    exp_t_imp_s: Positive | None = None
    exp_eps_max_m: Positive | None = None
    exp_trials: Annotated[int, Field(ge=1)] | None = None
    tolerance: ImpactTolerance | None = None


class ImpactCase(_Model):
    """One impact: manipulator, foam and head meeting at a closing speed.

    Give either ``impact_velocity`` (the closing speed v_c, m/s) or both
    ``v_r`` and ``v_h`` (manipulator and head velocities; v_c = v_r - v_h,
    a negative v_h moves the head toward the robot, DECISIONS I5).
    """

    label: str | None = Field(None, min_length=1, max_length=80)
    group: str | None = Field(
        None, min_length=1, max_length=80, description="cases of a group share a figure"
    )
    robot: RobotSpec
    foam: FoamSpec
    head: HeadSpec
    impact_velocity: Annotated[_Number, Field(gt=0, le=20.0, allow_inf_nan=False)] | None = None
    v_r: Speed | None = None
    v_h: Speed | None = None
    reference: ImpactReference | None = None

    @model_validator(mode="after")
    def _one_velocity(self) -> ImpactCase:
        pair = (self.v_r is not None, self.v_h is not None)
        if self.impact_velocity is not None and any(pair):
            raise ValueError("give either impact_velocity or v_r and v_h, not both")
        if self.impact_velocity is None:
            if pair != (True, True):
                raise ValueError("give impact_velocity (m/s) or both v_r and v_h (m/s)")
            v_c = float(self.v_r) - float(self.v_h)  # type: ignore[arg-type]
            if not v_c > 0.0:
                raise ValueError(
                    f"v_r - v_h = {v_c:g} m/s must be > 0 for an impact "
                    "(a negative v_h moves the head toward the robot)"
                )
        return self

    @property
    def closing_velocity(self) -> float:
        """v_c in m/s."""
        if self.impact_velocity is not None:
            return float(self.impact_velocity)
        return round(float(self.v_r) - float(self.v_h), 12)  # type: ignore[arg-type]

    def title(self, index: int) -> str:
        """The label, or ``"case <index+1>"``."""
        return self.label or f"case {index + 1}"


# --- studies ------------------------------------------------------------------


class StudyBase(_Model):
    """Fields common to every study kind."""

    designlab: Literal[1] = Field(description="study file format version")
    kind: str
    name: str = Field(
        pattern=r"^[A-Za-z0-9][A-Za-z0-9_.-]*$",
        max_length=100,
        description="identifier; the report goes to <output-dir>/<name>/",
    )
    description: str = ""

    #: Files (glob patterns) the report of this kind contains, for ``designlab list``.
    PRODUCES: ClassVar[tuple[str, ...]] = ()


class ImpactCasesStudy(StudyBase):
    """Simulate a list of impacts and compare them with reference values."""

    kind: Literal["impact_cases"]
    cases: list[ImpactCase] = Field(min_length=1)

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "metrics.csv",
        "time_histories*.png",
        "study.yaml",
    )

    @model_validator(mode="after")
    def _unique_labels(self) -> ImpactCasesStudy:
        seen: set[str] = set()
        for i, case in enumerate(self.cases):
            title = case.title(i)
            if title in seen:
                raise ValueError(f"case label {title!r} is used twice; labels must be unique")
            seen.add(title)
        return self


# --- sweeps ---------------------------------------------------------------------

#: Parameters of the impact model a sweep can vary: dotted path -> (point key, info).
IMPACT_PARAMETERS: dict[str, tuple[str, ParameterInfo]] = {
    "robot.mass": ("M_r", ParameterInfo("effective manipulator mass M_r", "kg", gt=0)),
    "robot.stiffness": ("K_r", ParameterInfo("manipulator stiffness K_r", "N/m", ge=0)),
    "robot.damping": ("C_r", ParameterInfo("manipulator damping C_r", "N s/m", ge=0)),
    "foam.stiffness": ("K_c", ParameterInfo("foam stiffness K_c", "N/m", gt=0)),
    "foam.damping": ("C_c", ParameterInfo("foam damping C_c", "N s/m", ge=0)),
    "foam.linear_depth": ("lambda", ParameterInfo("foam linear depth lambda", "m", gt=0)),
    "head.mass": ("M_h", ParameterInfo("head mass M_h", "kg", gt=0)),
    "head.stiffness": ("K_h", ParameterInfo("neck stiffness K_h", "N/m", ge=0)),
    "head.damping": ("C_h", ParameterInfo("neck damping C_h", "N s/m", ge=0)),
    "impact_velocity": ("v_c", ParameterInfo("closing velocity v_c", "m/s", gt=0, le=20)),
}

#: Metrics of an ``impact_sweep`` point (column name -> description with unit).
IMPACT_METRICS: dict[str, str] = {
    "a_h_max_g": "peak head acceleration a_h,max, g",
    "eps_max_m": "maximum foam compression eps_max, m",
    "f_c_max_N": "peak contact force, N",
    "t_imp_s": "impact period, s",
}

ImpactSweepParameters = parameter_model(
    "ImpactSweepParameters", {path: info for path, (_, info) in IMPACT_PARAMETERS.items()}
)
ImpactMetricName = Literal["a_h_max_g", "eps_max_m", "f_c_max_N", "t_imp_s"]


class ImpactDesign(_Model):
    """The nominal design of an impact sweep: manipulator, foam, head, closing speed."""

    robot: RobotSpec
    foam: FoamSpec
    head: HeadSpec
    impact_velocity: Annotated[_Number, Field(gt=0, le=20.0, allow_inf_nan=False)] = Field(
        description="closing velocity v_c, m/s"
    )


class ImpactSweepSpec(SweepSpec):
    """Design points of an ``impact_sweep`` (see :mod:`designlab.study.sweeps`)."""

    parameters: ImpactSweepParameters  # type: ignore[valid-type]


class ImpactSensitivitySpec(_Model):
    """Sensitivity tables of an ``impact_sweep``."""

    metrics: list[ImpactMetricName] = Field(
        default_factory=lambda: list(IMPACT_METRICS),
        min_length=1,
        description="metrics to analyse: " + ", ".join(IMPACT_METRICS),
    )
    local: bool = Field(
        True, description="elasticities d ln(metric) / d ln(parameter) at the base (CasADi AD)"
    )
    one_at_a_time: OneAtATimeSpec | None = Field(
        None, description="percentage perturbation table (Zeng 2011 App. C form)"
    )
    sobol: SobolSpec | None = Field(None, description="global Sobol indices (SALib)")
    tornado: bool = Field(
        True, description="metric at each sweep parameter's low and high (others at base)"
    )


class SweepStudyBase(StudyBase):
    """Fields and hooks common to the sweep kinds (``impact_sweep``, ...).

    A kind says how a dotted parameter path maps to a key of its plain point
    dictionary (``PARAMETERS``), which worker-side evaluator computes a point
    (``EVALUATOR``, see :mod:`designlab.analysis.sweep`) and which metrics it
    returns (``METRICS``).
    """

    PARAMETERS: ClassVar[dict[str, tuple[str, ParameterInfo]]] = {}
    METRICS: ClassVar[dict[str, str]] = {}
    EVALUATOR: ClassVar[str] = ""
    LOCAL_EVALUATOR: ClassVar[str | None] = None
    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "results.csv",
        "sensitivity_*.csv",
        "*.png",
        "study.yaml",
    )

    def base_point(self) -> dict[str, float]:  # pragma: no cover - overridden
        """The base design as a plain point dictionary."""
        raise NotImplementedError

    def evaluator_options(self) -> dict[str, Any]:
        """Settings of the evaluator that are the same for every point."""
        return {}

    def _check_paths(self) -> None:
        sens = getattr(self, "sensitivity", None)
        sweep = getattr(self, "sweep", None)
        swept = [p for p, _ in sweep.parameters.items()] if sweep is not None else []
        if sens is None:
            return
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
                ranged = {p for p, r in sweep.parameters.items()} if sweep is not None else set()
                missing = [p for p in paths if p not in ranged]
                if missing:
                    raise ValueError(
                        f"sensitivity.sobol: {', '.join(missing)} need a range in "
                        "sweep.parameters (low/high or values)"
                    )
                if len(paths) < 2:
                    raise ValueError("sensitivity.sobol needs at least two parameters")


class ImpactSweepStudy(SweepStudyBase):
    """Impact metrics over a sweep of designs, with sensitivity tables.

    Every point is one impact of the linear coupled model
    (:func:`designlab.impact.impact_metrics`): a_h,max, eps_max, peak force,
    impact period, status and ``bottoming`` (eps_max > lambda).
    """

    kind: Literal["impact_sweep"]
    base: ImpactDesign = Field(description="nominal design; the sweep varies some of it")
    sweep: ImpactSweepSpec | None = None
    sensitivity: ImpactSensitivitySpec | None = None

    PARAMETERS: ClassVar[dict[str, tuple[str, ParameterInfo]]] = IMPACT_PARAMETERS
    METRICS: ClassVar[dict[str, str]] = IMPACT_METRICS
    EVALUATOR: ClassVar[str] = "impact_metrics"
    LOCAL_EVALUATOR: ClassVar[str] = "impact_elasticities"

    @model_validator(mode="after")
    def _paths(self) -> ImpactSweepStudy:
        if self.sweep is None and self.sensitivity is None:
            raise ValueError("give a sweep, a sensitivity block, or both")
        self._check_paths()
        return self

    def base_point(self) -> dict[str, float]:
        """The base design as ``{M_r, C_r, K_r, K_c, C_c, lambda, M_h, C_h, K_h, v_c}``."""
        r, f, h = self.base.robot.build(), self.base.foam.build(), self.base.head.build()
        return {
            "M_r": float(r.mass),
            "C_r": float(r.damping),
            "K_r": float(r.stiffness),
            "K_c": float(f.stiffness),
            "C_c": float(f.damping),
            "lambda": float(f.linear_depth),
            "M_h": float(h.mass),
            "C_h": float(h.damping),
            "K_h": float(h.stiffness),
            "v_c": float(self.base.impact_velocity),
        }


# --- foam envelope sweeps ---------------------------------------------------------

#: Parameters of a foam-envelope sweep: dotted path -> (point key, info).
ENVELOPE_PARAMETERS: dict[str, tuple[str, ParameterInfo]] = {
    "robot.mass": ("M_r", ParameterInfo("effective manipulator mass M_r", "kg", gt=0)),
    "robot.stiffness": ("K_r", ParameterInfo("manipulator stiffness K_r", "N/m", ge=0)),
    "robot.damping": ("C_r", ParameterInfo("manipulator damping C_r", "N s/m", ge=0)),
    "impact_velocity": ("v_c", ParameterInfo("worst closing velocity v_c", "m/s", gt=0, le=20)),
    "max_g": ("max_g", ParameterInfo("head acceleration limit a_h,max", "g", gt=0, le=1000)),
    "foam.linear_depth": (
        "lambda",
        ParameterInfo("foam linear depth lambda (compression limit)", "m", gt=0, le=1),
    ),
    "foam.stiffness": ("K_c", ParameterInfo("stiffness K_c of the checked foam", "N/m", gt=0)),
    "foam.damping": ("C_c", ParameterInfo("damping C_c of the checked foam", "N s/m", ge=0)),
}

#: Metrics of a ``foam_envelope`` point.
ENVELOPE_METRICS: dict[str, str] = {
    "k_c_max_N_per_m": "upper (safety) boundary K_c,max at the foam's damping, N/m",
    "k_c_min_N_per_m": "lower (thickness) boundary K_c,min at the foam's damping, N/m",
    "margin_decades": "margin of the foam to the nearest boundary, decades of K_c",
    "area_log": "feasible area over the damping grid, decades x N s/m",
}

EnvelopeSweepParameters = parameter_model(
    "EnvelopeSweepParameters", {path: info for path, (_, info) in ENVELOPE_PARAMETERS.items()}
)
EnvelopeMetricName = Literal["k_c_max_N_per_m", "k_c_min_N_per_m", "margin_decades", "area_log"]


class EnvelopeDesign(_Model):
    """The nominal design question of a foam envelope (Zeng 2011, Sec. 3.9).

    The upper boundary uses the minimum head-neck set and a_h,max <= ``max_g``;
    the lower boundary the maximum head-neck set and eps_max <= the foam's
    ``linear_depth`` (both as in the thesis).
    """

    robot: RobotSpec
    foam: FoamSpec = Field(description="the foam checked against the envelope (margin)")
    impact_velocity: Annotated[_Number, Field(gt=0, le=20.0, allow_inf_nan=False)] = Field(
        1.25, description="worst closing velocity v_c, m/s"
    )
    max_g: Annotated[_Number, Field(gt=0, le=1000, allow_inf_nan=False)] = Field(
        10.0, description="head acceleration limit, g"
    )


class DampingGrid(_Model):
    """The C_c grid of the envelope, N s/m."""

    low: Annotated[_Number, Field(ge=0, allow_inf_nan=False)] = 0.0
    high: Annotated[_Number, Field(gt=0, le=1e5, allow_inf_nan=False)] = 200.0
    num: Annotated[int, Field(ge=2, le=2001)] = 21

    @model_validator(mode="after")
    def _order(self) -> DampingGrid:
        if not self.low < self.high:
            raise ValueError(f"low = {self.low:g} N s/m must be < high = {self.high:g} N s/m")
        return self

    def values(self) -> list[float]:
        """The grid."""
        step = (self.high - self.low) / (self.num - 1)
        return [round(self.low + i * step, 12) for i in range(self.num)]


class EnvelopeSweepSpec(SweepSpec):
    """Design points of a ``foam_envelope`` study."""

    parameters: EnvelopeSweepParameters  # type: ignore[valid-type]


class EnvelopeSensitivitySpec(ImpactSensitivitySpec):
    """Sensitivity tables of a ``foam_envelope`` study.

    ``local`` elasticities are those of the boundaries K_c,max and K_c,min at
    the foam's damping, exact by AD and the implicit function theorem.
    """

    metrics: list[EnvelopeMetricName] = Field(  # type: ignore[assignment]
        default_factory=lambda: ["k_c_max_N_per_m", "k_c_min_N_per_m", "margin_decades"],
        min_length=1,
        description="metrics to analyse: " + ", ".join(ENVELOPE_METRICS),
    )


class FoamEnvelopeStudy(SweepStudyBase):
    """Feasible foam region (Zeng 2011, Sec. 3.9) and how it moves with the design.

    Every point solves a :func:`designlab.impact.foam_envelope` over the
    damping grid and checks the base foam against it.
    """

    kind: Literal["foam_envelope"]
    base: EnvelopeDesign
    damping: DampingGrid = Field(default_factory=DampingGrid)
    sweep: EnvelopeSweepSpec | None = None
    sensitivity: EnvelopeSensitivitySpec | None = None

    PARAMETERS: ClassVar[dict[str, tuple[str, ParameterInfo]]] = ENVELOPE_PARAMETERS
    METRICS: ClassVar[dict[str, str]] = ENVELOPE_METRICS
    EVALUATOR: ClassVar[str] = "foam_envelope"
    LOCAL_EVALUATOR: ClassVar[str] = "envelope_elasticities"

    @model_validator(mode="after")
    def _paths(self) -> FoamEnvelopeStudy:
        self._check_paths()
        return self

    def base_point(self) -> dict[str, float]:
        """``{M_r, C_r, K_r, v_c, max_g, lambda, K_c, C_c}``."""
        r, f = self.base.robot.build(), self.base.foam.build()
        return {
            "M_r": float(r.mass),
            "C_r": float(r.damping),
            "K_r": float(r.stiffness),
            "v_c": float(self.base.impact_velocity),
            "max_g": float(self.base.max_g),
            "lambda": float(f.linear_depth),
            "K_c": float(f.stiffness),
            "C_c": float(f.damping),
        }

    def evaluator_options(self) -> dict[str, Any]:
        """The damping grid."""
        return {"damping": self.damping.values()}


# --- foam design report (Zeng 2011, Sec. 3.9) ---------------------------------

_Pos = Annotated[float, Field(gt=0, allow_inf_nan=False)]


class HeadAccelerationSpec(_Model):
    """a_h,max <= ``max_g`` (thesis: 10 g); conservative head set: minimum."""

    type: Literal["head_acceleration"]
    max_g: _Pos = 10.0

    def build(self) -> Criterion:
        return HeadAcceleration(max_g=self.max_g)


class ImpactForceSpec(_Model):
    """Peak contact force <= ``max_force`` N; conservative head set: maximum."""

    type: Literal["force"]
    max_force: _Pos = 660.0

    def build(self) -> Criterion:
        return ImpactForce(max_force=self.max_force)


class HicSpec(_Model):
    """HIC over the first lobe <= ``max_hic`` with window 0.015 s or 0.036 s."""

    type: Literal["hic"]
    max_hic: _Pos = 650.0
    window: Literal[0.015, 0.036] = 0.015

    def build(self) -> Criterion:
        return HeadInjuryCriterion(max_hic=self.max_hic, window=self.window)


class IsoSpec(_Model):
    """ISO/TS 15066 transient-contact force limit for a body region."""

    type: Literal["iso_ts_15066"]
    body_region: Literal[tuple(ISO_TS_15066_QUASI_STATIC_FORCE)] = "skull_forehead"  # type: ignore[valid-type]

    def build(self) -> Criterion:
        return IsoTransientForce(self.body_region)


CriterionSpec = Annotated[
    HeadAccelerationSpec | ImpactForceSpec | HicSpec | IsoSpec, Field(discriminator="type")
]


class HeadRangeSpec(_Model):
    """Head-neck ranges ``[low, high]``: the envelope takes the worst case over them."""

    mass: tuple[_Pos, _Pos] = (4.4, 5.3)
    stiffness: tuple[float, float] = (3.0e3, 5.0e3)
    damping: tuple[float, float] = (46.0, 130.2)

    def build(self) -> HeadRange:
        return HeadRange(self.mass, self.stiffness, self.damping)


class FoamDesignStudy(StudyBase):
    """Feasible foam region, foam verdicts, safe speed and optimal foam for each robot."""

    kind: Literal["foam_design"]
    robots: list[RobotSpec] = Field(min_length=1, description="effective manipulators")
    foams: list[FoamSpec] = Field(default_factory=list, description="foams to check")
    criteria: list[CriterionSpec] = Field(  # type: ignore[valid-type]
        default_factory=lambda: [HeadAccelerationSpec(type="head_acceleration", max_g=10.0)],
        min_length=1,
        description="safety criteria of the upper boundary",
    )
    impact_velocity: Annotated[float, Field(gt=0, le=20, allow_inf_nan=False)] = Field(
        1.25, description="worst closing velocity v_c, m/s"
    )
    human_speed: Annotated[float, Field(ge=0, le=20, allow_inf_nan=False)] = Field(
        1.0, description="head speed toward the robot, m/s (for the safe manipulator speed)"
    )
    max_compression: _Pos = Field(0.02, description="lambda, linear depth of the foam, m")
    damping: DampingGrid = Field(default_factory=lambda: DampingGrid(low=0, high=200, num=41))
    head_range: HeadRangeSpec | None = Field(
        None, description="worst case over these ranges instead of the thesis's sets"
    )
    optimal: bool = Field(True, description="also find the foam with the best margin")
    worst_case_samples: Annotated[int, Field(ge=0, le=10000)] = Field(
        64, description="samples per boundary point of the worst-case check (0: skip)"
    )

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "envelope.md",
        "envelope.csv",
        "envelope.png",
        "study.yaml",
    )

    @model_validator(mode="after")
    def _distinct(self) -> FoamDesignStudy:
        names = [r.build().name or f"robot {i + 1}" for i, r in enumerate(self.robots)]
        if len(set(names)) != len(names):
            raise ValueError(
                "robots must be distinct (give each explicit robot a different preset)"
            )
        return self


#: Every study kind, keyed by its ``kind`` value. To add a kind: subclass
#: :class:`StudyBase` (or :class:`SweepStudyBase`) with ``kind: Literal["new"]``,
#: add it here and to :data:`Study`, and register a runner and a report writer.
STUDY_KINDS: dict[str, type[StudyBase]] = {
    "impact_cases": ImpactCasesStudy,
    "impact_sweep": ImpactSweepStudy,
    "foam_envelope": FoamEnvelopeStudy,
    "foam_design": FoamDesignStudy,
}

#: A study of any kind (discriminated on ``kind``).
Study = Annotated[
    ImpactCasesStudy | ImpactSweepStudy | FoamEnvelopeStudy | FoamDesignStudy,
    Field(discriminator="kind"),
]

#: Validates a plain dict into the right study model.
STUDY_ADAPTER: TypeAdapter[Any] = TypeAdapter(Study)


def study_json_schema() -> dict[str, Any]:
    """The JSON Schema of a study file (every kind), for editors and CI.

    Examples
    --------
    >>> schema = study_json_schema()
    >>> sorted(schema["discriminator"]["mapping"])
    ['foam_design', 'foam_envelope', 'impact_cases', 'impact_sweep']
    """
    schema = STUDY_ADAPTER.json_schema(by_alias=True)
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["title"] = f"designlab study (format {FORMAT_VERSION})"
    return schema
