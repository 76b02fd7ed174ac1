"""The disk cache of built CasADi functions (designlab.sx.functions) and of compiled kernels."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import casadi as ca
import pytest

from designlab.sx import jit
from designlab.sx.functions import cached_function, source_hash


def _builder(counter: list[int], factor: float):  # type: ignore[no-untyped-def]
    def build() -> ca.Function:
        counter.append(1)
        x = ca.SX.sym("x")
        return ca.Function("f", [x], [factor * ca.sin(x)])

    return build


def test_second_call_loads_instead_of_building(tmp_path: Path, _private_cache: Path) -> None:
    src = tmp_path / "model.py"
    src.write_text("A = 1\n")
    built: list[int] = []
    f1 = cached_function("sin times 3", _builder(built, 3.0), (str(src),))
    f2 = cached_function("sin times 3", _builder(built, 3.0), (str(src),))
    assert len(built) == 1
    assert float(f2(0.5)) == float(f1(0.5))
    assert len(list((_private_cache / "functions").glob("*.casadi"))) == 1


def test_description_and_sources_are_part_of_the_key(tmp_path: Path, _private_cache: Path) -> None:
    src = tmp_path / "model.py"
    src.write_text("A = 1\n")
    built: list[int] = []
    cached_function("sin times 3", _builder(built, 3.0), (str(src),))
    f = cached_function("sin times 4", _builder(built, 4.0), (str(src),))
    assert len(built) == 2 and float(f(0.5)) == pytest.approx(4.0 * 0.479425538604203)
    src.write_text("A = 2\n")
    source_hash.cache_clear()
    cached_function("sin times 3", _builder(built, 3.0), (str(src),))
    assert len(built) == 3


def test_damaged_entry_is_rebuilt(tmp_path: Path, _private_cache: Path) -> None:
    built: list[int] = []
    cached_function("damaged", _builder(built, 2.0), (str(tmp_path),))
    (entry,) = (_private_cache / "functions").glob("*.casadi")
    entry.write_text("not a serialized function")
    f = cached_function("damaged", _builder(built, 2.0), (str(tmp_path),))
    assert len(built) == 2 and float(f(0.0)) == 0.0


@pytest.mark.skipif(not jit.AVAILABLE, reason=f"no compiled kernels: {jit.reason()}")
def test_compiled_kernels_are_cached_under_the_designlab_cache(_private_cache: Path) -> None:
    """A fresh process compiles into <cache>/numba/<sources key>; numba's index files are there."""
    env = {**os.environ, "DESIGNLAB_CACHE_DIR": str(_private_cache)}
    env.pop("NUMBA_CACHE_DIR", None)
    code = (
        "from designlab.sx import jit; from designlab.impact.kernel_modal import shape;"
        "print(jit.jit_cache_dir()); print(shape(-1.0, -2.0, 1.0, 1.0))"
    )
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    where, value = out.stdout.splitlines()
    assert Path(where) == _private_cache / "numba" / jit.sources_key() and value == "-1"
    assert any(Path(where).rglob("*.nbi"))


def test_kernel_cache_is_keyed_by_every_kernel_module(tmp_path: Path) -> None:
    """numba tracks only a function's own file: a helper changed elsewhere changes the key."""
    package = Path(jit.__file__).resolve().parent.parent
    users = {
        p.relative_to(package).as_posix()
        for p in package.rglob("*.py")
        if "@kernel" in p.read_text(encoding="utf-8") and p.name != "jit.py"
    }
    assert users <= set(jit.KERNEL_MODULES)
    for rel in jit.KERNEL_MODULES:
        dest = tmp_path / rel
        dest.parent.mkdir(parents=True, exist_ok=True)
        dest.write_bytes((package / rel).read_bytes())
    key = jit.sources_key(tmp_path)
    assert key == jit.sources_key(package)
    helper = tmp_path / "impact" / "kernel_modal.py"
    helper.write_text(helper.read_text(encoding="utf-8") + "\n# changed\n", encoding="utf-8")
    assert jit.sources_key(tmp_path) != key


@pytest.mark.skipif(not jit.AVAILABLE, reason=f"no compiled kernels: {jit.reason()}")
@pytest.mark.slow
def test_kernel_cache_is_ours_when_numba_was_imported_first(_private_cache: Path) -> None:
    """A program that imports numba before designlab still gets the keyed cache (not
    numba's default next to the sources, keyed by each file's own time stamp only)."""
    env = {**os.environ, "DESIGNLAB_CACHE_DIR": str(_private_cache)}
    env.pop("NUMBA_CACHE_DIR", None)
    code = (
        "import numba; from designlab.sx import jit;"
        "from designlab.impact.kernel_modal import shape; shape(-1.0, -2.0, 1.0, 1.0);"
        "print(numba.config.CACHE_DIR)"
    )
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert Path(out.stdout.strip()) == _private_cache / "numba" / jit.sources_key()
    assert any(Path(out.stdout.strip()).rglob("*.nbi"))
