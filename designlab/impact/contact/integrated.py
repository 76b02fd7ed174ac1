"""The shared face of the integrated (non-linear) contact models: metrics, histories, HIC.

A contact model whose foam force is a non-linear function of the compression eps and its
rate has no closed-form kernel; its responses come from the general response path
(:mod:`designlab.impact.general`: an adaptive integrator with event location). What such
a model declares is only its force law and the compression it cannot pass, read from its
parameter row by name (:meth:`IntegratedContact.force_law_of`,
:meth:`IntegratedContact.crush_depth_of`); everything else is here, once:

* first-lobe metrics of parameter rows, one design at a time (status ``"integrated"``,
  never certified; the warnings say how the numbers were obtained);
* the time histories of one impact (:func:`~designlab.impact.simulate`);
* HIC (docs/impact.md, "HIC") from the integrated head velocity, by the same window search
  as the linear kernels' (:func:`~designlab.impact.metrics.hic_of_velocity`);
* metric gradients by central finite differences of the integrated metrics
  (:meth:`IntegratedContact.finite_difference_gradients`): not the exact gradients of the
  linear model, stated as such.

This module is not a contact model itself: the variants
(:mod:`~designlab.impact.contact.hunt_crossley`, :mod:`~designlab.impact.contact.measured`)
subclass :class:`IntegratedContact`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.conditioning import check_conditioning
from designlab.impact.contact.base import HEAD_COLUMNS, ContactModel
from designlab.impact.general import (
    GENERAL_RTOL,
    ForceLaw,
    GeneralStatus,
    Histories,
    first_lobe,
    histories,
    integrator_note,
)
from designlab.impact.metric_names import ImpactPoint
from designlab.impact.metrics import ImpactMetrics, hic_of_velocity
from designlab.impact.model import PARAM_NAMES
from designlab.impact.parameters import STOP_TIME, check_closing_velocity
from designlab.validation import real_array

__all__ = ["FD_STEP", "IntegratedContact"]

#: Relative step of the central finite differences of integrated metrics: the metrics
#: carry the integrator's error (about 1e-11 relative at rtol 1e-12), so a step of 1e-5
#: leaves a truncation error of order 1e-10 and a rounding error of order 1e-6 relative.
FD_STEP = 1e-5

#: the metrics a gradient is given for, as :class:`~designlab.impact.derivatives.MetricGradients`
_GRADIENT_METRICS = ("peak_head_acceleration", "max_compression", "peak_force", "impact_duration")


class _Velocities:
    """``evaluate(t)``: each design's integrated head velocity at its row of times ``t``."""

    def __init__(self, runs: list[Histories]) -> None:
        self.runs = runs

    def evaluate(self, t: NDArray) -> NDArray[np.float64]:
        t = np.atleast_2d(t)
        return np.vstack([h(row)["head_velocity"] for h, row in zip(self.runs, t, strict=True)])


@dataclass(frozen=True)
class IntegratedContact(ContactModel):
    """A contact model served by the general response path (see the module text).

    Subclasses give :meth:`force_law_of` and :meth:`crush_depth_of`; their capabilities are
    ``linear=False`` (no closed form), ``batched=False`` (one design per integration) and
    ``gradients=False`` (no exact gradients; finite differences instead).

    Attributes
    ----------
    name, label, doc, robots, foam, columns, robot_attributes, foam_attributes
        As in :class:`~designlab.impact.contact.base.ContactModel`.
    linear_model, equations
        As there (no linear model: ``None``).
    linear, batched, gradients, profiles, printed_q2, response_form
        Its capabilities, as in :class:`~designlab.impact.contact.base.ContactModel`.
    """

    def force_law_of(self, values: Mapping[str, float]) -> ForceLaw:
        """The force law of one design from its parameter row by name."""
        raise NotImplementedError  # pragma: no cover - every variant implements it

    def crush_depth_of(self, values: Mapping[str, float]) -> float | None:
        """The compression the law cannot pass (m), or ``None`` (never crushed)."""
        raise NotImplementedError  # pragma: no cover - every variant implements it

    # ---------------------------------------------------------------- one design
    def _design(self, row: NDArray) -> tuple[ForceLaw, tuple, tuple, float | None]:
        """Force law, manipulator, head and crush depth of one parameter row."""
        named = {c: float(x) for c, x in zip(self.columns, row, strict=True)}
        arm = tuple(named[c] for c in self.robot_columns)
        head = tuple(named[c] for c in HEAD_COLUMNS)
        return self.force_law_of(named), arm, head, self.crush_depth_of(named)

    def _rows(self, rows: NDArray, impact_velocity: Any) -> tuple[NDArray, NDArray]:
        p = np.atleast_2d(real_array("params", rows))
        if p.ndim != 2 or p.shape[1] != len(self.columns):
            raise InvalidParameterError(
                "params", p.shape, f"must have shape (N, {len(self.columns)}) for the "
                f"{self.label} contact (columns {list(self.columns)})",
            )  # fmt: skip
        v = np.atleast_1d(check_closing_velocity(impact_velocity)).ravel()
        n = max(p.shape[0], v.size)
        return np.broadcast_to(p, (n, p.shape[1])), np.broadcast_to(v, (n,))

    def check_time_scales(
        self, rows: NDArray, constrained: bool, labels: Sequence[str | None] | None = None
    ) -> None:
        """Refuse designs whose linearisation at contact spans more time scales than served.

        The explicit integrator's steps follow the fastest time scale and its horizon the
        slowest, so their ratio bounds its work: the rows' linear columns (K_c and C_c the
        law's values at contact, or at x_d for the Hunt-Crossley damper: the larger) go
        through the linear model's check (docs/impact.md, "Limits"; a damping of 1e9 N s/m
        would otherwise take the integrator hours), the parameter named.

        Parameters
        ----------
        rows
            ``(N, len(columns))`` parameter rows.
        constrained
            The constrained impact.
        labels
            The caller's names of the columns (as :meth:`input_labels`), or ``None``.
        """
        idx = [self.columns.index(c) for c in PARAM_NAMES]
        named = None if labels is None else [labels[i] for i in idx]
        check_conditioning(np.atleast_2d(rows)[:, idx], PARAM_NAMES, constrained=constrained,
                           labels=named)  # fmt: skip

    # ---------------------------------------------------------------- metrics
    def metrics(self, rows: NDArray, impact_velocity: Any, **options: Any) -> ImpactMetrics:
        """First-lobe metrics of rows by the general response path (integrated, not certified).

        Parameters
        ----------
        rows
            ``(N, len(columns))`` parameter rows of :attr:`columns` (or one row).
        impact_velocity
            v_c, m/s: a scalar or ``(N,)``.
        **options
            ``constrained``, ``stop_time``, ``rtol``
            (:data:`~designlab.impact.general.GENERAL_RTOL`); the linear kernels' other
            options (``with_force``, ...) are accepted and have nothing to save here; ``q2``
            must be ``"correct"``.
        """
        if options.get("q2", "correct") != "correct":
            raise InvalidParameterError(
                "q2", options["q2"], "the printed q2 belongs to the reduced linear model"
            )
        p, v = self._rows(rows, impact_velocity)
        constrained = bool(options.get("constrained", False))
        self.check_rows(p, constrained)
        self.check_time_scales(p, constrained)
        stop_time = STOP_TIME.check(options.get("stop_time", STOP_TIME.default))
        rtol = GENERAL_RTOL.check(options.get("rtol", GENERAL_RTOL.default))
        lobes = []
        for row, vc in zip(p, v, strict=True):
            law, arm, head, crush = self._design(row)
            lobes.append(
                first_lobe(law, arm, None if constrained else head, float(vc),
                           stop_time=stop_time, rtol=rtol, crush_depth=crush)
            )  # fmt: skip
        return self._batch(p, v, lobes, constrained, rtol)

    def _batch(
        self, p: NDArray, v: NDArray, lobes: list[ImpactPoint], constrained: bool, rtol: float
    ) -> ImpactMetrics:
        def arr(name: str) -> NDArray[np.float64]:
            return np.array([getattr(lobe, name) for lobe in lobes], dtype=float)

        status = np.array([lobe.status for lobe in lobes])
        open_ = int(np.sum(status == GeneralStatus.LOBE_NOT_CLOSED.value))
        crushed = int(np.sum(status == "bottoming"))
        warnings = [integrator_note(rtol)]
        if crushed:
            warnings.append(
                f"{crushed} design(s) crushed the foam (eps reached the end of its law): "
                "their peak force and a_h are infinite, beyond any limit"
            )
        if open_:
            warnings.append(
                f"{open_} design(s) did not close their first lobe; their metrics are NaN"
            )
        return ImpactMetrics(
            np.array(p), np.array(v), arr("peak_head_acceleration"), arr("max_compression"),
            arr("peak_force"), arr("impact_duration"), arr("time_of_peak_acceleration"),
            arr("time_of_max_compression"), arr("time_of_peak_force"), status,
            constrained=constrained,
            status=GeneralStatus.LOBE_NOT_CLOSED if open_ else GeneralStatus.INTEGRATED,
            warnings=tuple(warnings), contact=self.name,
        )  # fmt: skip

    def values(
        self,
        key: Any,
        rows: NDArray,
        impact_velocity: NDArray,
        *,
        constrained: bool = False,
        stop_time: float = STOP_TIME.default,
    ) -> NDArray[np.float64]:
        """The metric of criterion ``key`` by the general path (HIC from the histories)."""
        m = self.metrics(rows, impact_velocity, constrained=constrained, stop_time=stop_time)
        return key.from_metrics(m)

    def hic(
        self, metrics: ImpactMetrics, window: float, samples: int, rtol: float | None = None
    ) -> NDArray[np.float64]:
        """HIC of integrated metrics: the window search on the integrated head velocity.

        Parameters
        ----------
        metrics
            This model's metrics (:meth:`metrics`; their rows and lobe ends).
        window, samples
            As for :func:`~designlab.impact.metrics.hic_batch` (checked there).
        rtol
            Relative tolerance of the histories (default
            :data:`~designlab.impact.general.GENERAL_RTOL`'s).
        """
        rtol = GENERAL_RTOL.default if rtol is None else rtol
        out = np.zeros(len(metrics))
        t_imp = metrics.impact_duration
        ok = (metrics.impact_velocity > 0) & np.isfinite(t_imp) & (t_imp > 0)
        idx = np.flatnonzero(ok)
        if metrics.constrained or idx.size == 0:
            return out
        runs = []
        for i in idx:
            law, arm, head, crush = self._design(metrics.params[i])
            runs.append(histories(law, arm, head, float(metrics.impact_velocity[i]),
                                  float(t_imp[i]), rtol=rtol, crush_depth=crush))  # fmt: skip
        out[idx] = hic_of_velocity(_Velocities(runs), np.ones(idx.size), t_imp[idx],
                                   window, samples)  # fmt: skip
        return out

    # ---------------------------------------------------------------- gradients
    def finite_difference_gradients(
        self, rows: NDArray, impact_velocity: Any, *, constrained: bool = False
    ) -> tuple[ImpactMetrics, dict[str, NDArray[np.float64]]]:
        """Metric gradients by central finite differences of the integrated metrics.

        Each column ``x`` of the row (and v_c, last) is stepped by ``FD_STEP * |x|``
        (``FD_STEP`` where ``x = 0``) both ways; the gradients carry the integrator's error
        divided by the step (about 1e-6 relative) and are not the exact gradients of a
        linear model. A step that leaves a column's declared range, or a design whose
        metrics are not finite at both ends, gives NaN.

        Parameters
        ----------
        rows, impact_velocity, constrained
            As for :meth:`metrics`.

        Returns
        -------
        (ImpactMetrics, dict)
            The metrics at the rows, and per metric an ``(N, len(columns) + 1)`` array of
            gradients (the columns, then v_c).
        """
        p, v = self._rows(rows, impact_velocity)
        base = self.metrics(p, v, constrained=constrained)
        full = np.column_stack([p, v])
        grads = {m: np.full(full.shape, np.nan) for m in _GRADIENT_METRICS}
        for j in range(full.shape[1]):
            h = FD_STEP * np.where(full[:, j] != 0.0, np.abs(full[:, j]), 1.0)
            ends = []
            for sign in (1.0, -1.0):
                q = full.copy()
                q[:, j] += sign * h
                ends.append(self._metrics_or_nan(q, constrained))
            for m in _GRADIENT_METRICS:
                grads[m][:, j] = (ends[0][m] - ends[1][m]) / (2.0 * h)
        return base, grads

    def _metrics_or_nan(self, q: NDArray, constrained: bool) -> dict[str, NDArray]:
        try:
            m = self.metrics(q[:, :-1], q[:, -1], constrained=constrained)
        except InvalidParameterError:  # a step left a column's range: no difference there
            return {name: np.full(q.shape[0], np.nan) for name in _GRADIENT_METRICS}
        return {name: getattr(m, name) for name in _GRADIENT_METRICS}

    # ---------------------------------------------------------------- one impact
    def integrate(
        self, robot: Any, foam: Any, head: Any, impact_velocity: float, **options: Any
    ) -> tuple[ImpactPoint, Histories]:
        """First-lobe metrics and time histories (over ``t_end``) of one impact, integrated.

        Parameters
        ----------
        robot, foam, head
            The impact (``head=None``: constrained).
        impact_velocity
            v_c > 0, m/s.
        **options
            ``t_end`` (s; default twice the impact period), ``stop_time``, ``rtol``.
        """
        row = self.row(robot, foam, head)
        self.check_time_scales(row, head is None, self.input_labels(head))
        law, arm, neck, crush = self._design(row)
        neck = None if head is None else neck
        stop_time = STOP_TIME.check(options.get("stop_time", STOP_TIME.default))
        rtol = GENERAL_RTOL.check(options.get("rtol", GENERAL_RTOL.default))
        lobe = first_lobe(
            law, arm, neck, impact_velocity, stop_time=stop_time, rtol=rtol, crush_depth=crush
        )
        t_imp = lobe.impact_duration
        t_end = options.get("t_end") or (2.0 * t_imp if np.isfinite(t_imp) and t_imp > 0 else 0.1)
        return lobe, histories(law, arm, neck, impact_velocity, t_end, rtol=rtol, crush_depth=crush)
