"""The compiled entry of one design (:func:`designlab.impact.single.impact_metrics_one`).

One compiled call per design: the conditioning estimate of
:func:`designlab.impact.kernel.time_scale_ratios` and, within its bound, the row of
:func:`designlab.impact.kernel.reduced_metrics`, from eight floats (a compiled call with
scalar arguments costs far less to enter than one with arrays).

Examples
--------
>>> code, a_max, *rest = one_design(9.6, 250.0, 20e3, 24.25e3, 71.9, 4.4, 0.0, 4e3, 0.05, 4096, 1e4)
>>> code, round(a_max * 1.25 / 9.80665, 3)
(0, 6.568)
"""

from __future__ import annotations

import numpy as np

from designlab.impact.kernel import _ratio_block, _reduced_block
from designlab.sx.jit import kernel

__all__ = ["FINAL", "REFUSED", "one_design"]

#: status codes below this are a design's final status (no settling, no error)
FINAL = 4
#: the code of a design refused before the kernel ran (its time-scale ratio over the bound)
REFUSED = 99


@kernel
def one_design(m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h, stop_time, max_steps, bound):  # type: ignore[no-untyped-def]
    """The kernel's status code and the first seven columns of its row
    (:data:`designlab.impact.kernel.COLUMNS`, unit v_c, every output) of one reduced,
    unconstrained design; the code :data:`REFUSED` where its time-scale ratio is over
    ``bound`` (the conditioning check fails).

    Parameters
    ----------
    m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h
        The design (:data:`~designlab.impact.model.PARAM_NAMES`), checked by the caller.
    stop_time, max_steps
        As in :func:`designlab.impact.kernel.reduced_metrics`.
    bound
        The largest time-scale ratio served
        (:data:`~designlab.impact.parameters.TIME_SCALE_RATIO`).

    Returns
    -------
    tuple
        ``(code, a_max, eps_max, f_max, t_imp, t_a, t_eps, t_f)``.
    """
    p = np.empty((1, 8))
    p[0, 0], p[0, 1], p[0, 2], p[0, 3] = m_r, c_r, k_r, k_c
    p[0, 4], p[0, 5], p[0, 6], p[0, 7] = c_c, m_h, c_h, k_h
    ratio = np.empty(1)
    out = np.full((1, 8), np.nan)
    status = np.zeros(1, dtype=np.int8)
    _ratio_block(p, ratio)
    if not ratio[0] <= bound:
        status[0] = REFUSED
    else:
        outputs = np.ones(3, dtype=np.bool_)
        # the flags (printed, diag, check) read from an array: typed bool, not as the
        # literals False/True, so the block compiled for the batch path serves this call
        # too (literal flags compile a second copy of the whole block: tens of CPU seconds)
        flags = np.zeros(3, dtype=np.bool_)
        flags[2] = True
        _reduced_block(p, outputs, flags[0], stop_time, max_steps, flags[1], out, status, flags[2])
    r = out[0]
    return int(status[0]), r[0], r[1], r[2], r[3], r[4], r[5], r[6]
