"""Exact responses of a linear impact model from its state space (eigen-decomposition).

A stiff transmission puts the full joint's motor-node pole
(:mod:`designlab.impact.full_joint_model`) many decades above the impact
modes; the roots of the characteristic *polynomial* then lose all accuracy,
while the eigenvalues of ``A`` keep it. :func:`modal_families` builds the
exact responses (poles, residues and polynomial part,
:class:`~designlab.impact.modal.ModalResponse`) from the eigen-decomposition,
falling back to the transfer functions where ``A`` is nearly defective.

Examples
--------
>>> import numpy as np
>>> from designlab.impact.full_joint_model import full_joint_model
>>> p = np.array([[1.475, 50.0, 5e4, 24250.0, 71.9, 4.4, 46.0, 3e3, 750.0, 37500.0]])
>>> r = modal_families(full_joint_model(), p, ("force",))["ramp"]["force"]
>>> round(float(r.evaluate(np.array([[0.0]]))[0, 0]), 1)        # f_c(0+) = C_c v_c
71.9
"""

from __future__ import annotations

from collections.abc import Sequence
from math import factorial

import numpy as np
from numpy.typing import NDArray

from designlab.impact.modal import ModalResponse, fold_conjugates, fold_plan, poles_of
from designlab.impact.model import LinearImpactModel

__all__ = ["FAMILIES", "MAX_EIGVEC_CONDITION", "modal_families"]

#: Condition number of the eigenvector matrix above which a design's responses
#: are built from its transfer functions instead (nearly coincident modes).
MAX_EIGVEC_CONDITION = 1e8

#: Input families of an impact: name -> ({input: power of s}, order m of the pole at 0).
#: ``y = (sum_j s^e_j G_j(s)) / s^m``: the constant-velocity ramp (v_c = 1), the
#: ramp of the closing speed (v_c = t), and steps of a_d and a_ff.
FAMILIES: dict[str, tuple[dict[str, int], int]] = {
    "ramp": ({"s_c": 0, "v_c": 1}, 2),
    "accel": ({"s_c": 0, "v_c": 1}, 3),
    "a_d": ({"a_d": 0}, 1),
    "a_ff": ({"a_ff": 0}, 1),
}


def modal_families(
    model: LinearImpactModel,
    params: NDArray[np.float64],
    outputs: Sequence[str],
    families: Sequence[str] = ("ramp",),
) -> dict[str, dict[str, ModalResponse]]:
    """Exact responses of the full-joint model from its state space (eigen-decomposition).

    A stiff transmission puts the motor node's pole many decades above the
    impact modes; the roots of the characteristic *polynomial* then lose all
    accuracy, while the eigenvalues of ``A`` keep it. With ``A = V diag(l) V^-1``
    each transfer function is ``G_j(s) = D_j + sum_i (C v_i)(w_i B_j)/(s - l_i)``,
    so the response ``y = (sum_j s^e_j G_j) / s^m`` has the residues
    ``(C v_i) sum_j l_i^e_j (w_i B_j) / l_i^m`` and a polynomial part from the
    Taylor coefficients ``G_j^(k)(0)/k! = [k=0] D_j - C A^-(k+1) B_j``.

    Parameters
    ----------
    model
        A model of :func:`full_joint_model` (any linear model works).
    params
        ``(N, n_p)`` parameters.
    outputs
        Output names.
    families
        Keys of :data:`FAMILIES`.

    Returns
    -------
    dict
        ``{family: {output: ModalResponse}}`` (unit input).

    Notes
    -----
    Where ``A`` is nearly defective (two modes coincide, condition number of
    the eigenvector matrix above ``1e8``) the design's responses come from the
    transfer-function route instead, whose partial fractions separate nearly
    repeated poles (:mod:`designlab.impact.modal`).
    """
    out = _eigen_families(model, params, outputs, families)
    a = model.matrices_batch(params)[0]
    with np.errstate(all="ignore"):
        cond = np.linalg.cond(np.linalg.eig(a)[1])
    bad = np.flatnonzero(~np.isfinite(cond) | (cond > MAX_EIGVEC_CONDITION))
    if bad.size:
        fallback = _polynomial_families(model, params[bad], outputs, families)
        for fam in families:
            for name in outputs:
                out[fam][name] = _splice(out[fam][name], fallback[fam][name], bad)
    return out


def _splice(base: ModalResponse, part: ModalResponse, rows: NDArray[np.intp]) -> ModalResponse:
    """``base`` with the designs ``rows`` replaced by ``part`` (columns padded with zeros)."""
    width = max(base.poles.shape[1], part.poles.shape[1])

    def pad(x: NDArray) -> NDArray:
        return np.pad(x, ((0, 0), (0, width - x.shape[1])))

    poles, residues = pad(base.poles), pad(base.residues)
    poles[rows], residues[rows] = pad(part.poles), pad(part.residues)
    poly = base.poly.copy()
    poly[rows] = part.poly
    return ModalResponse(poles, residues, poly)


def _polynomial_families(
    model: LinearImpactModel,
    params: NDArray[np.float64],
    outputs: Sequence[str],
    families: Sequence[str],
) -> dict[str, dict[str, ModalResponse]]:
    """The same responses from the model's transfer-function coefficients."""
    den, num = model.tf_coefficients(params)
    poles = poles_of(den)
    out: dict[str, dict[str, ModalResponse]] = {}
    for fam in families:
        powers, m = FAMILIES[fam]
        nums = {}
        for name in outputs:
            total = np.zeros((params.shape[0], den.shape[1] + 1))
            for k, e in powers.items():
                coef = num[name][:, model.input_names.index(k), :]
                shifted = np.concatenate([coef, np.zeros((coef.shape[0], e))], axis=1)
                total[:, total.shape[1] - shifted.shape[1] :] += shifted
            nums[name] = total
        out[fam] = ModalResponse.family(nums, den, m, poles)
    return out


def _eigen_families(
    model: LinearImpactModel,
    params: NDArray[np.float64],
    outputs: Sequence[str],
    families: Sequence[str],
) -> dict[str, dict[str, ModalResponse]]:
    """:func:`modal_families` by the eigen-decomposition of ``A``."""
    a, b, c, d = model.matrices_batch(params)
    lam, vec = np.linalg.eig(a)
    w = np.linalg.inv(vec)
    cv = np.einsum("nyx,nxi->nyi", c, vec)  # (N, n_y, n)
    wb = np.einsum("nix,nxu->niu", w, b)  # (N, n, n_u)
    a_inv = np.linalg.inv(a)
    plan = fold_plan(lam)
    out: dict[str, dict[str, ModalResponse]] = {}
    for fam in families:
        powers, m = FAMILIES[fam]
        idx = {model.input_names.index(k): e for k, e in powers.items()}
        # residues of (sum_j s^e_j G_j) / s^m at the eigenvalues
        gain = sum(lam**e * wb[:, :, j] for j, e in idx.items()) / lam**m  # (N, n)
        # Taylor coefficients of H(s) = sum_j s^e_j G_j(s), orders 0..m-1
        taylor = np.zeros((params.shape[0], len(model.output_names), m))
        a_pow = np.broadcast_to(np.eye(a.shape[1]), a.shape).copy()
        g_k = []
        for k in range(m):
            a_pow = a_pow @ a_inv  # A^-(k+1)
            g = -np.einsum("nyx,nxz,nzu->nyu", c, a_pow, b)
            if k == 0:
                g = g + d
            g_k.append(g)
        for lag in range(m):
            for j, e in idx.items():
                if lag - e >= 0:
                    taylor[:, :, lag] += g_k[lag - e][:, :, j]
        fam_out = {}
        for name in outputs:
            y = model.output_names.index(name)
            res = cv[:, y, :] * gain
            p_f, r_f = fold_conjugates(lam, res, plan)
            poly = np.stack(
                [taylor[:, y, lag] / factorial(m - 1 - lag) for lag in range(m)], axis=1
            )
            fam_out[name] = ModalResponse(p_f, r_f, poly)
        out[fam] = fam_out
    return out
