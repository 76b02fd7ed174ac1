"""Deprecated alias of :mod:`designlab.sx.replay` (kept for one release).

:func:`vectorize` and :func:`evaluate_batch` now live in :mod:`designlab.sx`, the one
symbolic back end; import them from there.

Examples
--------
>>> import casadi as ca, numpy as np
>>> x = ca.SX.sym("x", 2)
>>> evaluate_batch(ca.Function("f", [x], [x[0] * x[1]]), np.array([[2.0, 3.0]]))[0].tolist()
[[6.0]]
"""

from designlab.sx.replay import evaluate_batch, vectorize

__all__ = ["evaluate_batch", "vectorize"]
