"""Safety criteria for a head impact, sharing one interface.

A criterion maps the first-lobe response of an impact to one scalar, compares
it with a limit, and knows which head-neck parameter set is conservative for it
(Zeng 2011, Sec. 3.6 and 3.9): the *minimum* set (light head, soft neck) gives
the largest head acceleration; the *maximum* set gives the largest force and
compression. The foam's thickness constraint (3.9.3) is a criterion too; it is
the only one that bounds the foam stiffness from *below*.

=====================  ===============================  ======================
criterion              metric                           conservative head set
=====================  ===============================  ======================
HeadAcceleration       a_h,max (thesis: 10 g)           HEAD_MIN
ImpactForce            peak f_c                         HEAD_MAX
HeadInjuryCriterion    HIC15 / HIC36 (standard)         HEAD_MIN
IsoQuasiStaticForce    peak f_c vs ISO/TS 15066 A.2     HEAD_MAX
IsoTransientForce      peak f_c vs factor x A.2 value   HEAD_MAX
CompressionLimit       eps_max <= lambda (3.9.3)        HEAD_MAX
=====================  ===============================  ======================

See ``docs/impact.md`` ("Safety criteria") for the sources of every limit.

Examples
--------
>>> from designlab.impact.criteria import HeadAcceleration, IsoQuasiStaticForce
>>> HeadAcceleration(max_g=10).limit
98.0665
>>> IsoQuasiStaticForce("face").limit      # ISO/TS 15066, Table A.2
65.0
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.metrics import ImpactMetrics, hic_batch, metrics_of_matrix
from designlab.impact.parameters import (
    HEAD_MAX,
    HEAD_MIN,
    HIC_SAMPLES,
    HIC_WINDOW,
    MAX_COMPRESSION,
    STOP_TIME,
    HeadNeck,
    as_field,
)
from designlab.params import Param, declared, param
from designlab.units import STANDARD_GRAVITY

__all__ = [
    "BODY_REGION",
    "ISO_TS_15066_QUASI_STATIC_FORCE",
    "ISO_TS_15066_TRANSIENT_FACTOR",
    "CompressionLimit",
    "Criterion",
    "ForceCriterion",
    "HeadAcceleration",
    "HeadInjuryCriterion",
    "ImpactForce",
    "IsoQuasiStaticForce",
    "IsoTransientForce",
]

#: ISO/TS 15066:2016, Annex A, Table A.2, "maximum permissible force" for
#: quasi-static contact, per body region, N. Every value is taken from that
#: table. The standard asks that contact with the head regions (skull and
#: forehead, face) be avoided in collaborative operation; the values serve to
#: assess accidental contact. Check them against your copy of the standard.
ISO_TS_15066_QUASI_STATIC_FORCE = MappingProxyType(
    {
        "skull_forehead": 130.0,
        "face": 65.0,
        "neck": 150.0,
        "back_shoulders": 210.0,
        "chest": 140.0,
        "abdomen": 110.0,
        "pelvis": 180.0,
        "upper_arm_elbow": 150.0,
        "lower_arm_wrist": 160.0,
        "hand_finger": 140.0,
        "thigh_knee": 220.0,
        "lower_leg": 130.0,
    }
)

#: ISO/TS 15066:2016, Annex A, Table A.2, force multiplier for transient contact.
#: The table gives none for the head regions (transient contact with the skull,
#: forehead or face is not permissible): they are absent here, and a transient
#: criterion for them needs an explicit factor from the user.
ISO_TS_15066_TRANSIENT_FACTOR = MappingProxyType(
    {
        region: 2.0
        for region in ISO_TS_15066_QUASI_STATIC_FORCE
        if region not in ("skull_forehead", "face")
    }
)
_HEAD_REGIONS = ("skull_forehead", "face")


@dataclass(frozen=True)
class Criterion:
    """Base class: a limit on one first-lobe metric of the impact.

    Subclasses set ``metric`` (``"head_acceleration"``, ``"force"`` or ``"hic"``),
    ``limit`` (SI) and ``conservative_head``, the head-neck set that maximises the metric
    (Sec. 3.9): the minimum set (Sec. 3.6) for a_h and HIC, the maximum for the force and
    the compression (Sec. 3.6, 3.9.2).
    """

    metric: ClassVar[str] = ""
    #: how the metric scales with the impact velocity (metric ~ v_c ** exponent)
    velocity_exponent: ClassVar[float] = 1.0
    unit: ClassVar[str] = ""
    #: ``"upper"``: the criterion bounds the foam stiffness from above (safety);
    #: ``"lower"``: from below (the thickness constraint)
    boundary: ClassVar[str] = "upper"
    #: the head-neck set that maximises this metric (Sec. 3.9)
    conservative_head: ClassVar[HeadNeck]

    @property
    def limit(self) -> float:  # pragma: no cover - overridden
        """The limit in SI units."""
        raise NotImplementedError

    @property
    def name(self) -> str:
        """Short label with the limit, e.g. ``a_h <= 10 g``."""
        return f"{self.metric} <= {self.limit:g} {self.unit}"

    @property
    def needs_force(self) -> bool:
        """Whether the metric needs the peak force."""
        return self.metric == "force"

    def values(
        self,
        params: NDArray[np.float64],
        impact_velocity: NDArray[np.float64],
        *,
        constrained: bool = False,
        stop_time: float = STOP_TIME.default,
    ) -> NDArray[np.float64]:
        """The metric for a batch of designs (``(N, 8)`` params, ``(N,)`` v_c), SI.

        ``stop_time`` is the window of the constrained impact's metrics, s.
        """
        m = metrics_of_matrix(
            params,
            impact_velocity,
            constrained=constrained,
            stop_time=stop_time,
            with_force=self.needs_force,
            with_compression=self.metric == "compression",
        )
        return self.from_metrics(m)

    def from_metrics(self, m: ImpactMetrics) -> NDArray[np.float64]:
        """Extract the metric from an :class:`~designlab.impact.metrics.ImpactMetrics`."""
        if self.metric == "head_acceleration":
            return m.peak_head_acceleration
        if self.metric == "force":
            return m.peak_force
        if self.metric == "compression":
            return m.max_compression
        raise NotImplementedError(self.metric)  # pragma: no cover - subclasses override

    def describe(self) -> str:
        """One sentence for reports."""
        return self.name


@declared
@dataclass(frozen=True)
class HeadAcceleration(Criterion):
    """Peak head acceleration over the impact period below ``max_g`` (thesis: 10 g).

    Examples
    --------
    >>> HeadAcceleration(max_g=10).name
    'a_h,max <= 10 g'
    """

    max_g: float = param(
        "a_h,max", "g", doc="head acceleration limit", gt=0, le=1000, default=10.0,
        typical=(10.0, 10.0),
    )  # fmt: skip
    metric: ClassVar[str] = "head_acceleration"
    unit: ClassVar[str] = "g"
    conservative_head: ClassVar[HeadNeck] = HEAD_MIN

    @property
    def limit(self) -> float:
        """Limit in m/s^2."""
        return self.max_g * STANDARD_GRAVITY

    @property
    def name(self) -> str:
        """``a_h,max <= <max_g> g``."""
        return f"a_h,max <= {self.max_g:g} g"


class ForceCriterion(Criterion):
    """Base of the limits on the peak contact force f_c (conservative head set: maximum).

    Subclasses give ``max_force`` (N), a field or a property.
    """

    metric: ClassVar[str] = "force"
    unit: ClassVar[str] = "N"
    conservative_head: ClassVar[HeadNeck] = HEAD_MAX
    max_force: float

    @property
    def limit(self) -> float:
        """Limit in N."""
        return self.max_force

    @property
    def name(self) -> str:
        """``f_c,max <= <max_force> N``."""
        return f"f_c,max <= {self.max_force:g} N"


@declared
@dataclass(frozen=True)
class ImpactForce(ForceCriterion):
    """Peak contact force f_c over the impact period below ``max_force`` (N).

    Examples
    --------
    >>> ImpactForce(max_force=660.0).name      # maxilla fracture (Haddadin et al. 2008)
    'f_c,max <= 660 N'
    """

    max_force: float = param(
        "f_c,max", "N", doc="peak contact force limit", gt=0, le=1e5, default=660.0,
        typical=(65.0, 660.0),
    )  # fmt: skip


#: The ISO/TS 15066 body region of a force limit (Annex A, Table A.2).
BODY_REGION = Param(
    None, "", "ISO/TS 15066 Table A.2 body region", kind="choice",
    choices=tuple(ISO_TS_15066_QUASI_STATIC_FORCE), name="body_region",
)  # fmt: skip


def _head_note(region: str) -> str:
    return (
        "; ISO/TS 15066 asks that contact with this region be avoided"
        if region in _HEAD_REGIONS
        else ""
    )


@declared
@dataclass(frozen=True)
class IsoQuasiStaticForce(ForceCriterion):
    """ISO/TS 15066 quasi-static contact force limit of a body region (Table A.2).

    Examples
    --------
    >>> IsoQuasiStaticForce("skull_forehead").limit
    130.0
    """

    body_region: str = as_field(BODY_REGION, default="skull_forehead")

    @property
    def max_force(self) -> float:  # type: ignore[override]
        """The Table A.2 maximum permissible force of the region, N."""
        return ISO_TS_15066_QUASI_STATIC_FORCE[self.body_region]

    @property
    def name(self) -> str:
        """``f_c,max <= <limit> N (ISO/TS 15066 quasi-static, <region>)``."""
        return f"f_c,max <= {self.max_force:g} N (ISO/TS 15066 quasi-static, {self.body_region})"

    def describe(self) -> str:
        """One sentence for reports (the source and, for the head, the standard's advice)."""
        return self.name + " (ISO/TS 15066:2016, Table A.2)" + _head_note(self.body_region)


@declared
@dataclass(frozen=True)
class IsoTransientForce(ForceCriterion):
    """ISO/TS 15066 transient-contact force limit of a body region.

    ``limit = factor x`` the quasi-static maximum permissible force of Annex A,
    Table A.2 (:data:`ISO_TS_15066_QUASI_STATIC_FORCE`), with the table's
    transient multiplier (:data:`ISO_TS_15066_TRANSIENT_FACTOR`, 2 where the
    table gives one). The table gives no multiplier for the skull/forehead and
    the face: for them ``transient_factor`` must be given explicitly (or use
    :class:`IsoQuasiStaticForce`); the project does not invent one.

    Examples
    --------
    >>> IsoTransientForce("chest").limit
    280.0
    >>> IsoTransientForce("face")
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: IsoTransientForce.transient_factor = None ...
    gives no transient-contact multiplier for 'face' ...
    >>> IsoTransientForce("face", transient_factor=1.0).limit
    65.0
    """

    body_region: str = as_field(BODY_REGION, default="lower_arm_wrist")
    transient_factor: float | None = param(
        None, "", doc="factor on the quasi-static limit for transient contact", gt=0, le=10,
        optional=True, none="the Table A.2 multiplier (there is none for the head regions)",
        default=None,
    )  # fmt: skip

    def __post_init__(self) -> None:
        if self.transient_factor is None:
            if self.body_region not in ISO_TS_15066_TRANSIENT_FACTOR:
                raise InvalidParameterError(
                    "IsoTransientForce.transient_factor",
                    None,
                    "ISO/TS 15066 Table A.2 gives no transient-contact multiplier for "
                    f"{self.body_region!r} (transient contact with the head is not "
                    "permissible); give transient_factor explicitly or use IsoQuasiStaticForce",
                )
            factor = ISO_TS_15066_TRANSIENT_FACTOR[self.body_region]
            object.__setattr__(self, "transient_factor", factor)

    @property
    def max_force(self) -> float:  # type: ignore[override]
        """``transient_factor x`` the Table A.2 quasi-static value, N."""
        return float(self.transient_factor) * ISO_TS_15066_QUASI_STATIC_FORCE[self.body_region]  # type: ignore[arg-type]

    @property
    def name(self) -> str:
        """``f_c,max <= <limit> N (ISO/TS 15066 transient, <region>)``."""
        return f"f_c,max <= {self.max_force:g} N (ISO/TS 15066 transient, {self.body_region})"

    def describe(self) -> str:
        """One sentence for reports: the limit, where its factor comes from."""
        source = (
            f"user factor {self.transient_factor:g} x Table A.2 quasi-static value"
            if self.body_region not in ISO_TS_15066_TRANSIENT_FACTOR
            or self.transient_factor != ISO_TS_15066_TRANSIENT_FACTOR[self.body_region]
            else f"{self.transient_factor:g} x Table A.2 quasi-static value (Table A.2 multiplier)"
        )
        return f"{self.name}: {source}{_head_note(self.body_region)}"


@declared
@dataclass(frozen=True)
class CompressionLimit(Criterion):
    """The thickness constraint (3.9.3): eps_max below the foam's linear depth lambda.

    The linear foam model holds only while eps <= lambda (Zeng 2011, Sec. 3.9.2;
    docs/impact.md, "Foam bottoming"). Unlike the safety criteria it bounds the
    foam stiffness from *below* (a softer foam compresses more). The limit is
    the foam's linear depth, declared once (:class:`~designlab.impact.Foam`).

    Examples
    --------
    >>> CompressionLimit(0.02).name
    'eps_max <= 20 mm'
    """

    max_compression: float = as_field(MAX_COMPRESSION, default=0.02)
    metric: ClassVar[str] = "compression"
    unit: ClassVar[str] = "m"
    conservative_head: ClassVar[HeadNeck] = HEAD_MAX
    boundary: ClassVar[str] = "lower"

    @property
    def limit(self) -> float:
        """Limit (lambda) in m."""
        return self.max_compression

    @property
    def name(self) -> str:
        """``eps_max <= <lambda> mm``."""
        return f"eps_max <= {self.max_compression * 1e3:g} mm"


@declared
@dataclass(frozen=True)
class HeadInjuryCriterion(Criterion):
    """HIC over the first lobe below ``max_hic`` (standard definition; docs/impact.md, "HIC").

    ``window`` is 0.015 s (HIC15) or 0.036 s (HIC36). HIC < 650 corresponds to
    AIS < 3 (EuroNCAP 2004, quoted by the thesis). HIC scales as v_c ** 2.5.

    Examples
    --------
    >>> HeadInjuryCriterion(max_hic=650, window=0.015).name
    'HIC15 <= 650'
    """

    max_hic: float = param(
        "HIC", "", doc="largest allowed HIC", gt=0, le=1e5, default=650.0, typical=(650.0, 1000.0)
    )
    window: float = as_field(HIC_WINDOW, default=0.015)
    samples: int = as_field(HIC_SAMPLES, default=400)
    metric: ClassVar[str] = "hic"
    velocity_exponent: ClassVar[float] = 2.5
    unit: ClassVar[str] = ""
    conservative_head: ClassVar[HeadNeck] = HEAD_MIN

    @property
    def limit(self) -> float:
        """Limit (dimensionless HIC)."""
        return self.max_hic

    @property
    def name(self) -> str:
        """``HIC<window in ms> <= <max_hic>``."""
        return f"HIC{round(self.window * 1000):d} <= {self.max_hic:g}"

    def values(
        self,
        params: NDArray[np.float64],
        impact_velocity: NDArray[np.float64],
        *,
        constrained: bool = False,
        stop_time: float = STOP_TIME.default,
    ) -> NDArray[np.float64]:
        if constrained:
            return np.zeros(np.atleast_2d(params).shape[0])
        m = metrics_of_matrix(params, impact_velocity, with_force=False, with_compression=False)
        return hic_batch(m, self.window, self.samples)

    def from_metrics(self, m: ImpactMetrics) -> NDArray[np.float64]:
        return hic_batch(m, self.window, self.samples)
