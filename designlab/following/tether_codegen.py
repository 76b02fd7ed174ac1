"""Compile CasADi SX functions of the tether follower to plain Python/numpy code.

The follower's physics (kinematics, tether sensor, control laws) is written once
with CasADi symbols; the closed loop runs thousands of small steps, each a call of
the function :func:`compile_sx` generated from the SX instruction list. The
generator is :func:`designlab.sx.compile_sx` of the one symbolic back end (one
operation table, CasADi's semantics on NaN, infinities and signed zeros); this module
re-exports it for the follower.

Examples
--------
>>> import casadi as ca
>>> x = ca.SX.sym("x"); y = ca.SX.sym("y")
>>> f = ca.Function("f", [x, y], [ca.atan2(y, x), ca.fmax(x, 0) * y])
>>> g = compile_sx(f)
>>> [round(v, 4) for v in g(-1.0, 2.0)]
[2.0344, 0.0]
>>> import numpy as np
>>> gb = compile_sx(f, batch=True)
>>> np.round(gb(np.array([1.0, -1.0]), 2.0)[1], 3)
array([2., 0.])
"""

from __future__ import annotations

from designlab.sx.pycode import compile_sx

__all__ = ["compile_sx"]
