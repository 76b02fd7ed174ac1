"""The path buffer of Follow the Leader (Allan 2015 Sec. 2.3.2-2.3.3, App. C ``point_tracker``).

FTL and FTL-CD record the estimated tether tip whenever it is at least
``min_step`` from the last recorded point, keep the newest ``buffer_size - 1``
points and steer at a target on the recorded path:

* FTL (``"lookahead"``, App. C ``find_closest_point`` and ``find_lookahead_point``):
  the recorded point nearest to the robot, then ``lookahead`` further along the
  recorded path;
* FTL-CD (``"constant_distance"``, ``find_const_dist_target``): the newest
  recorded point at least ``l_d`` (Euclidean) from the newest one.

With a noise-free planar sensor every member of a batch records the same tips
(the leader's positions), so the buffer is recorded once
(:func:`record_shared`) and only the target search is per member. Otherwise
each member keeps its own buffer (:class:`MemberBuffers`). Each target finder
is a small object called once per control period with the robot state; it
returns the target point ``(x, y)`` (floats for one run, arrays for a batch).

Examples
--------
>>> import numpy as np
>>> tips = np.column_stack([np.linspace(0.0, 1.0, 101), np.zeros(101)])
>>> rec, s, counts = record_shared(tips, 0.095, np.zeros((0, 2)))
>>> len(rec), counts[:12].tolist()
(11, [1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 2, 2])
"""

from __future__ import annotations

import math
from bisect import bisect_left, bisect_right
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "CONSTANT_DISTANCE",
    "LOOKAHEAD",
    "TETHER_ANGLE",
    "ConstantDistanceBatch",
    "ConstantDistanceTarget",
    "LookaheadBatch",
    "LookaheadTarget",
    "MemberBuffers",
    "NoTarget",
    "SharedBufferTarget",
    "TargetFinder",
    "record_shared",
]


def record_shared(
    tips: NDArray[np.float64], min_step: float, prefill: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """Record a tip sequence with the App. C ``point_tracker`` rule (one shared buffer).

    Parameters
    ----------
    tips
        Tether-tip positions in m, one per control period, (N, 2).
    min_step
        Delta s_min in m.
    prefill
        Points recorded before t = 0 (the lead-in), (M, 2).

    Returns
    -------
    tuple
        The recorded points (M, 2), their path distance (M,), and for each
        period the number of records made up to and including it (N,).
    """
    rec = list(map(tuple, prefill))
    s_rec = [0.0]
    for i in range(1, len(rec)):
        s_rec.append(s_rec[-1] + math.dist(rec[i], rec[i - 1]))
    if not rec:
        s_rec = []
    counts = np.empty(len(tips), dtype=np.int64)
    lx, ly = rec[-1] if rec else (math.nan, math.nan)
    txs, tys = tips[:, 0].tolist(), tips[:, 1].tolist()
    for k in range(len(txs)):
        tx, ty = txs[k], tys[k]
        if not rec:
            rec.append((tx, ty))
            s_rec.append(0.0)
            lx, ly = tx, ty
        else:
            d = math.hypot(tx - lx, ty - ly)
            if d >= min_step:
                rec.append((tx, ty))
                s_rec.append(s_rec[-1] + d)
                lx, ly = tx, ty
        counts[k] = len(rec)
    return np.array(rec, dtype=float), np.array(s_rec, dtype=float), counts


class NoTarget:
    """Pseudo-Joystick steers along the tether: no target point (zeros).

    Parameters
    ----------
    zero
        The value returned (0.0, or zeros of the batch).
    """

    def __init__(self, zero: Any = 0.0) -> None:
        self.zero = zero

    def __call__(self, k: int, x: Any, y: Any, *state: Any) -> tuple[Any, Any]:
        """The (unused) target of period ``k``."""
        return self.zero, self.zero


class SharedBufferTarget:
    """A target on a shared buffer, for one run on Python floats (the base of the laws').

    Parameters
    ----------
    shared
        ``(points, path distance, counts)`` from :func:`record_shared`.
    window
        Points searched (``buffer_size - 1``).
    """

    def __init__(self, shared: tuple[NDArray, NDArray, NDArray], window: int) -> None:
        rec, s_rec, counts = shared
        self.s = s_rec.tolist()
        self.rx, self.ry = rec[:, 0].tolist(), rec[:, 1].tolist()
        self.counts = counts.tolist()
        self.window = window


class LookaheadTarget(SharedBufferTarget):
    """FTL's target on a shared buffer, for one run on Python floats.

    Parameters
    ----------
    shared, window
        As :class:`SharedBufferTarget`.
    lookahead
        delta in m.
    """

    def __init__(
        self, shared: tuple[NDArray, NDArray, NDArray], window: int, lookahead: float
    ) -> None:
        super().__init__(shared, window)
        rec = shared[0]
        self.aug = np.column_stack([rec, -0.5 * np.einsum("ij,ij->i", rec, rec)])
        self.delta = lookahead - 1e-12
        self.p3 = np.ones(3)

    def __call__(self, k: int, x: float, y: float, *state: Any) -> tuple[float, float]:
        """The target of period ``k`` for a robot at ``(x, y)``."""
        hi = self.counts[k]
        lo = hi - self.window if hi > self.window else 0
        if hi - lo < 2:
            j = hi - 1
        else:
            # the nearest recorded point maximises p . r - |r|^2 / 2
            self.p3[0] = x
            self.p3[1] = y
            i0 = int(np.argmax(self.aug[lo:hi] @ self.p3)) + lo
            j = bisect_left(self.s, self.s[i0] + self.delta, i0, hi)
            if j >= hi:
                j = hi - 1
        return self.rx[j], self.ry[j]


class ConstantDistanceTarget(SharedBufferTarget):
    """FTL-CD's target on a shared buffer, for one run on Python floats.

    Parameters
    ----------
    shared, window
        As :class:`SharedBufferTarget`.
    desired_length
        l_d in m.
    """

    def __init__(
        self, shared: tuple[NDArray, NDArray, NDArray], window: int, desired_length: float
    ) -> None:
        super().__init__(shared, window)
        self.ld = desired_length
        self.last_hi = -1
        self.target = (0.0, 0.0)

    def __call__(self, k: int, x: float, y: float, *state: Any) -> tuple[float, float]:
        """The target of period ``k`` (it changes only when a point is recorded)."""
        hi = self.counts[k]
        if hi != self.last_hi:
            # the newest point >= l_d (Euclidean) from the newest; a point closer than l_d
            # along the path is closer in space too
            lo = hi - self.window if hi > self.window else 0
            rx, ry, ld2 = self.rx, self.ry, self.ld * self.ld
            nx, ny = rx[hi - 1], ry[hi - 1]
            j = bisect_right(self.s, self.s[hi - 1] - self.ld, lo, hi) - 1
            while j >= lo and (rx[j] - nx) ** 2 + (ry[j] - ny) ** 2 < ld2:
                j -= 1
            if j < lo:
                j = hi - 1
            self.last_hi = hi
            self.target = (rx[j], ry[j])
        return self.target


class LookaheadBatch:
    """FTL's targets on a shared buffer for a batch (one look-ahead per member).

    Parameters
    ----------
    shared, window
        As :class:`SharedBufferTarget`.
    lookahead
        delta of each member in m, (B,).
    """

    def __init__(
        self, shared: tuple[NDArray, NDArray, NDArray], window: int, lookahead: NDArray
    ) -> None:
        self.rec, self.s, self.counts = shared
        self.aug_t = np.ascontiguousarray(
            np.column_stack([self.rec, -0.5 * np.einsum("ij,ij->i", self.rec, self.rec)]).T
        )
        self.window = window
        self.delta = lookahead - 1e-12
        self.p3 = np.ones((len(lookahead), 3))

    def __call__(self, k: int, x: NDArray, y: NDArray, *state: Any) -> tuple[NDArray, NDArray]:
        """The targets of period ``k`` for robots at ``(x, y)``."""
        hi = self.counts[k]
        lo = max(0, hi - self.window)
        if hi - lo < 2:
            j = np.full(len(self.delta), hi - 1)
        else:
            self.p3[:, 0] = x
            self.p3[:, 1] = y
            i0 = np.argmax(self.p3 @ self.aug_t[:, lo:hi], axis=1) + lo
            j = np.searchsorted(self.s[lo:hi], self.s[i0] + self.delta) + lo
            j = np.minimum(j, hi - 1)
        return self.rec[j, 0], self.rec[j, 1]


class ConstantDistanceBatch:
    """FTL-CD's targets on a shared buffer for a batch (one l_d per member).

    Parameters
    ----------
    shared, window
        As :class:`SharedBufferTarget`.
    desired_length
        l_d of each member in m, (B,).
    """

    def __init__(
        self, shared: tuple[NDArray, NDArray, NDArray], window: int, desired_length: NDArray
    ) -> None:
        self.rec, self.s, self.counts = shared
        self.window = window
        # members sharing l_d share the search (the same comparisons, done once)
        self.ld2, self.member = np.unique(desired_length**2, return_inverse=True)
        self.last_hi = -1
        self.target: tuple[NDArray, NDArray] = (np.zeros(len(desired_length)),) * 2

    def __call__(self, k: int, x: NDArray, y: NDArray, *state: Any) -> tuple[NDArray, NDArray]:
        """The targets of period ``k`` (they change only when a point is recorded)."""
        hi = self.counts[k]
        if hi != self.last_hi:
            lo = max(0, hi - self.window)
            w = self.rec[lo:hi]
            dd = ((w - w[-1]) ** 2).sum(axis=1)
            ok = dd[None, :] >= self.ld2[:, None]
            last = np.where(
                ok.any(axis=1), (hi - lo - 1) - np.argmax(ok[:, ::-1], axis=1), hi - lo - 1
            )[self.member]
            self.target = (self.rec[last + lo, 0], self.rec[last + lo, 1])
            self.last_hi = hi
        return self.target


class MemberBuffers:
    """Per-member buffers of the estimated tip (sensor noise or a tip height).

    Each member records its own estimate of the tip, from its own noisy
    reading, and searches its own buffer (FTL or FTL-CD rule).

    Parameters
    ----------
    finder
        The law's target finder (:data:`LOOKAHEAD` or :data:`CONSTANT_DISTANCE`).
    n_members, n_steps
        Batch size and number of control periods.
    window
        Points searched (``buffer_size - 1``).
    min_step
        Delta s_min in m.
    prefill
        Points recorded before t = 0, (M, 2).
    per_member
        The look-aheads (FTL) or desired lengths (FTL-CD), (B,).
    sense, tip
        Compiled sensor and tip-estimate functions (batch).
    robot_offsets
        ``(off_x, off_y, h)`` of the winch.
    """

    def __init__(
        self,
        finder: TargetFinder,
        n_members: int,
        n_steps: int,
        window: int,
        min_step: float,
        prefill: NDArray,
        per_member: NDArray,
        sense: Any,
        tip: Any,
        robot_offsets: tuple[float, float, float],
    ) -> None:
        cap = n_steps + len(prefill) + 1
        self.bx = np.full((n_members, cap), np.nan)
        self.by = np.full((n_members, cap), np.nan)
        self.bs = np.zeros((n_members, cap))
        self.cnt = np.zeros(n_members, dtype=np.int64)
        if len(prefill):
            self.bx[:, : len(prefill)] = prefill[:, 0]
            self.by[:, : len(prefill)] = prefill[:, 1]
            self.bs[:, : len(prefill)] = np.concatenate(
                [[0.0], np.cumsum(np.hypot(*np.diff(prefill, axis=0).T))]
            )
            self.cnt[:] = len(prefill)
        self.rows = np.arange(n_members)
        self.ar = np.arange(window)
        self.window, self.min_step, self.finder = window, min_step, finder
        self.delta = per_member - 1e-12
        self.ld2 = per_member**2
        self.sense, self.tip, self.offsets = sense, tip, robot_offsets

    def _record(self, x: NDArray, y: NDArray, g: NDArray, tx: float, ty: float, nl: Any, nth: Any):
        ox, oy, hh = self.offsets
        lm, th = self.sense(x, y, g, tx, ty, ox, oy, hh)
        tx_e, ty_e = self.tip(x, y, g, lm + nl, th + nth, ox, oy)
        rows, cnt = self.rows, self.cnt
        has = cnt > 0
        last_i = np.maximum(cnt - 1, 0)
        dd = np.hypot(tx_e - self.bx[rows, last_i], ty_e - self.by[rows, last_i])
        recm = ~has | (dd >= self.min_step)
        ri, idx = rows[recm], cnt[recm]
        self.bx[ri, idx] = tx_e[recm]
        self.by[ri, idx] = ty_e[recm]
        self.bs[ri, idx] = np.where(has[recm], self.bs[ri, np.maximum(idx - 1, 0)] + dd[recm], 0.0)
        self.cnt = cnt + recm

    def __call__(
        self, k: int, x: NDArray, y: NDArray, g: NDArray, tx: float, ty: float, nl: Any, nth: Any
    ) -> tuple[NDArray, NDArray]:
        """Record this period's estimates, then the targets of every member."""
        self._record(x, y, g, tx, ty, nl, nth)
        rows, window, ar = self.rows, self.window, self.ar
        widx = self.cnt[:, None] - window + ar[None, :]
        valid = widx >= 0
        widx = np.maximum(widx, 0)
        wxs = self.bx[rows[:, None], widx]
        wys = self.by[rows[:, None], widx]
        jj = self.finder.pick(self, x, y, wxs, wys, widx, valid)
        return wxs[rows, jj], wys[rows, jj]

    def pick_lookahead(
        self, x: NDArray, y: NDArray, wxs: NDArray, wys: NDArray, widx: NDArray, valid: NDArray
    ) -> NDArray:
        """FTL's rule: ``delta`` along the path beyond the nearest point (indices in the window)."""
        rows, window, ar = self.rows, self.window, self.ar
        d2 = np.where(valid, (wxs - x[:, None]) ** 2 + (wys - y[:, None]) ** 2, np.inf)
        i0 = np.where(np.minimum(self.cnt, window) < 2, window - 1, np.argmin(d2, axis=1))
        ws = self.bs[rows[:, None], widx]
        ok = (
            valid
            & (ws - ws[rows, i0][:, None] >= self.delta[:, None])
            & (ar[None, :] >= i0[:, None])
        )
        return np.where(ok.any(axis=1), np.argmax(ok, axis=1), window - 1)

    def pick_constant_distance(
        self, x: NDArray, y: NDArray, wxs: NDArray, wys: NDArray, widx: NDArray, valid: NDArray
    ) -> NDArray:
        """FTL-CD's rule: the newest point at least l_d from the newest (indices in the window)."""
        window = self.window
        nx, ny = wxs[:, -1], wys[:, -1]
        ok = valid & ((wxs - nx[:, None]) ** 2 + (wys - ny[:, None]) ** 2 >= self.ld2[:, None])
        return np.where(ok.any(axis=1), window - 1 - np.argmax(ok[:, ::-1], axis=1), window - 1)


class TargetFinder:
    """How a law obtains its steering angle: the tether angle itself (no recorded path).

    A law names its finder (``target_finder``); the loops ask the finder, never the
    law's name. :data:`TETHER_ANGLE` is this base; :data:`LOOKAHEAD` (FTL) and
    :data:`CONSTANT_DISTANCE` (FTL-CD) record the tip and steer at a point of it.

    Attributes
    ----------
    name
        What the target is (for the docs).
    records_path
        Whether the law records the tether tip in an App. C path buffer.
    """

    name = "tether"
    records_path = False

    def distance(self, law: Any) -> float:
        """The law's search distance in m (look-ahead or l_d; NaN without a path)."""
        return math.nan

    def single(self, shared: Any, window: int, distance: float) -> Any:
        """The per-period finder of one noise-free run on a shared buffer."""
        return NoTarget()

    def batch(self, shared: Any, window: int, distances: NDArray) -> Any:
        """The per-period finder of a batch on a shared buffer."""
        return NoTarget(np.zeros(len(distances)))

    def pick(self, buffers: MemberBuffers, *search: Any) -> NDArray:  # pragma: no cover
        """The target indices in each member's window (:class:`MemberBuffers`)."""
        raise NotImplementedError("the tether angle has no recorded path")

    def point(self, recorder: Any, x: float, y: float, distance: float) -> tuple[float, float]:
        """The target on a :class:`~designlab.following.tether.stepwise.TipRecorder`."""
        raise NotImplementedError("the tether angle has no recorded path")  # pragma: no cover


class _Lookahead(TargetFinder):
    """FTL: ``lookahead`` along the recorded path beyond the point nearest the robot."""

    name = "lookahead"
    records_path = True

    def distance(self, law: Any) -> float:
        return float(law.lookahead)

    def single(self, shared: Any, window: int, distance: float) -> Any:
        return LookaheadTarget(shared, window, distance)

    def batch(self, shared: Any, window: int, distances: NDArray) -> Any:
        return LookaheadBatch(shared, window, distances)

    def pick(self, buffers: MemberBuffers, *search: Any) -> NDArray:
        return buffers.pick_lookahead(*search)

    def point(self, recorder: Any, x: float, y: float, distance: float) -> tuple[float, float]:
        return recorder.lookahead_point(x, y, distance)  # type: ignore[no-any-return]


class _ConstantDistance(TargetFinder):
    """FTL-CD: the newest recorded point at least l_d (Euclidean) from the newest."""

    name = "constant_distance"
    records_path = True

    def distance(self, law: Any) -> float:
        return float(law.desired_length)

    def single(self, shared: Any, window: int, distance: float) -> Any:
        return ConstantDistanceTarget(shared, window, distance)

    def batch(self, shared: Any, window: int, distances: NDArray) -> Any:
        return ConstantDistanceBatch(shared, window, distances)

    def pick(self, buffers: MemberBuffers, *search: Any) -> NDArray:
        return buffers.pick_constant_distance(*search)

    def point(self, recorder: Any, x: float, y: float, distance: float) -> tuple[float, float]:
        return recorder.const_distance_point(distance)  # type: ignore[no-any-return]


#: Steer along the tether (Pseudo-Joystick, the joystick modes): no recorded path.
TETHER_ANGLE = TargetFinder()
#: FTL's target (App. C ``find_closest_point`` + ``find_lookahead_point``).
LOOKAHEAD = _Lookahead()
#: FTL-CD's target (App. C ``find_const_dist_target``).
CONSTANT_DISTANCE = _ConstantDistance()
