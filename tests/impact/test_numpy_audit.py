"""The numpy path (no numba, ``DESIGNLAB_NO_JIT=1``) checks its metrics a posteriori as the
compiled path does: :func:`designlab.impact.metrics.audit_metrics_numpy` is the kernel's
``audit_metrics`` vectorised, and a design that fails it is ``uncertified`` (NaN metrics)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from designlab.impact import kernel
from designlab.impact import metrics as M
from designlab.impact.full_joint_model import grid_rate

#: a full-joint design (FULL_PARAM_NAMES) and a reduced one (PARAM_NAMES), typical values
FULL = [9.6, 1.5e3, 2e5, 24.25e3, 71.9, 4.4, 46.0, 3e3, 250.0, 2e4]
REDUCED = [9.6, 250.0, 2e4, 24.25e3, 71.9, 4.4, 46.0, 3e3]


def _audit_inputs(p: np.ndarray, constrained: bool):
    """The numpy path's rows of ``p`` and the folded solutions both audits take."""
    names = ("force", "compression") if constrained else ("force", "head_acceleration")
    resp = M.ramp_responses(M.response_model(p, constrained), p, names)
    poles = resp[names[0]].poles
    h = 0.4 / (grid_rate(poles) if p.shape[1] == 10 else np.abs(poles).max(axis=1))
    rows, codes = M._numpy_rows(resp, h, constrained, 0.05, 4096, False)
    res = np.zeros((p.shape[0], 3, poles.shape[1]), dtype=complex)
    poly = np.zeros((p.shape[0], 3, 2))
    for o, k in enumerate(M._KERNEL_OUTPUTS):
        if k in resp:
            res[:, o], poly[:, o, 2 - resp[k].poly.shape[1] :] = resp[k].residues, resp[k].poly
    return poles, res, poly, rows, codes


def _both(poles, res, poly, rows, codes, lobe):
    a = M.audit_metrics_numpy(poles, res, poly, rows, codes, lobe=lobe)
    if kernel.AVAILABLE:  # the compiled check gives the same verdicts
        b = kernel.audit_metrics(poles, res, poly, rows, codes, lobe=lobe)
        np.testing.assert_array_equal(a, b)
    return a


@pytest.mark.parametrize("row", [FULL, REDUCED])
@pytest.mark.parametrize("constrained", [False, True])
def test_the_numpy_audit_certifies_right_maxima_and_flags_wrong_ones(row, constrained) -> None:
    scale = np.array([1.0, 0.5, 2.0, 1.5, 0.8, 1.2])[:, None]
    p = np.array([row]) * np.where(np.arange(len(row)) < 3, scale, 1.0)
    poles, res, poly, rows, codes = _audit_inputs(p, constrained)
    assert np.all(codes == 0)
    lobe = not constrained
    assert np.all(_both(poles, res, poly, rows, codes, lobe) == 0)
    low = rows.copy()
    low[:, 2] *= 1.0 - 1e-2  # a force maximum below what the samples show (constrained:
    # it is at the window's end, 1e-3 beyond the last sample)
    assert np.all(_both(poles, res, poly, low, codes, lobe) == kernel.SUSPECT_MAXIMUM)
    if lobe:  # a lobe "ending" well after a_h turned negative
        late = rows.copy()
        late[:, 3] *= 3.0
        late[:, 2] = np.inf  # only the lobe is checked
        assert np.all(_both(poles, res, poly, late, codes, lobe) == kernel.SUSPECT_LOBE)
    skipped = np.full_like(codes, 3)  # lobe_not_closed: nothing to check
    assert np.all(_both(poles, res, poly, low, skipped, lobe) == 3)


_CHILD = """
import warnings
import numpy as np
import designlab as dl
from designlab.impact import kernel, metrics
from designlab.impact.full_joint_model import FULL_PARAM_NAMES

assert not kernel.AVAILABLE
p = np.array([{full}])
for constrained in (False, True):
    m = dl.impact.impact_metrics(p, 1.0, columns=FULL_PARAM_NAMES, constrained=constrained)
    assert m.status == "ok" and np.isfinite(m.max_compression).all(), m
real = metrics._window_maxima

def lowered(*args, **kwargs):
    out, t_imp, t_low = real(*args, **kwargs)
    return {{k: (t, y * (1.0 - 1e-6)) for k, (t, y) in out.items()}}, t_imp, t_low

metrics._window_maxima = lowered
m = dl.impact.impact_metrics(p, 1.0, columns=FULL_PARAM_NAMES)
assert m.status == "uncertified" and np.isnan(m.max_compression).all(), m
assert any("uncertified" in w and "numpy path" in w for w in m.warnings), m.warnings
print("ok")
"""


def test_without_numba_the_full_joint_is_audited_and_a_wrong_maximum_uncertified(tmp_path):
    """In a child with ``DESIGNLAB_NO_JIT=1``: right metrics pass the audit (status ok); maxima
    lowered by 1e-6 (what a wrong numpy maximum would be) give ``uncertified`` and NaN."""
    env = {**os.environ, "DESIGNLAB_NO_JIT": "1", "DESIGNLAB_CACHE_DIR": str(tmp_path)}
    code = textwrap.dedent(_CHILD.format(full=FULL))
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.strip().endswith("ok")
