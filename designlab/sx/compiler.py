"""The one way designlab runs a C compiler: ``$CC`` as an argument list, never a shell.

The compiler is ``$CC`` (split like a shell word list, so it may carry options:
``CC="clang -O1"``), else ``cc``, else ``gcc``. It runs with :func:`subprocess.run`
on a list of arguments, in a private temporary directory that is removed whether the
compilation succeeds or fails; no path is ever interpreted by a shell, so a
``TMPDIR`` with spaces or shell metacharacters is harmless.

Examples
--------
>>> reason = compiler_missing_reason()     # None where a C compiler works
>>> reason is None or reason.startswith("no C compiler")
True
"""

from __future__ import annotations

import hashlib
import os
import platform
import shlex
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from functools import cache
from pathlib import Path

__all__ = [
    "FLAGS",
    "Compiler",
    "CompilerError",
    "build_shared_object",
    "compiler_missing_reason",
    "find_compiler",
]

#: Flags of every compilation. -ffp-contract=off: no fused multiply-add (the virtual
#: machine rounds every product); -fno-math-errno: errno is never read, which lets sqrt
#: be inlined (same results); -march=native: the widest vectors the CPU has (the code
#: is compiled where it runs, and the cache key names the CPU).
FLAGS = ("-O2", "-ffp-contract=off", "-fno-math-errno", "-fPIC", "-shared", "-march=native")


class CompilerError(RuntimeError):
    """No C compiler was found, or it could not build the code (the message says which)."""


@dataclass(frozen=True)
class Compiler:
    """A C compiler command and what identifies it in a cache key.

    Attributes
    ----------
    command
        The program and its options (from ``$CC`` or the default).
    identity
        The resolved program path, the options and the first line of ``--version``.
    """

    command: tuple[str, ...]
    identity: str


def _split_cc(cc: str) -> list[str]:
    try:
        return shlex.split(cc)
    except ValueError as exc:
        raise CompilerError(f"no C compiler found (CC = {cc!r} cannot be split: {exc})") from None


@cache
def _find(cc: str, path: str) -> Compiler:
    """The compiler for ``$CC = cc`` on ``$PATH = path`` (cached per value of both)."""
    default = shutil.which("cc", path=path) or shutil.which("gcc", path=path) or ""
    command = _split_cc(cc) or [default]
    program = shutil.which(command[0], path=path) if command[0] else None
    if program is None:
        raise CompilerError(
            f"no C compiler found (CC = {cc!r}, PATH searched for cc and gcc; "
            "set CC or install a C compiler)"
        )
    try:
        version = subprocess.run(
            [program, *command[1:], "--version"], capture_output=True, text=True, timeout=60
        ).stdout.partition("\n")[0]
    except (OSError, subprocess.SubprocessError) as exc:
        raise CompilerError(f"no C compiler found ({program!r} does not run: {exc})") from None
    return Compiler((program, *command[1:]), f"{program} {command[1:]} {version}")


def find_compiler() -> Compiler:
    """The C compiler of ``$CC`` (which may carry options), else ``cc``, else ``gcc``.

    Raises
    ------
    CompilerError
        When no such program exists or it does not run.
    """
    return _find(os.environ.get("CC", ""), os.environ.get("PATH", os.defpath))


def compiler_missing_reason() -> str | None:
    """``None`` if a C compiler is found, else why not (a reason to skip or fall back)."""
    try:
        find_compiler()
    except CompilerError as exc:
        return str(exc)
    return None


@cache
def machine_identity() -> str:
    """What the machine code compiled with ``-march=native`` depends on: the CPU."""
    try:
        with open("/proc/cpuinfo") as fh:
            lines = [ln for ln in fh if ln.startswith(("model name", "flags", "Features"))]
        cpu = "".join(sorted(set(lines)))
    except OSError:
        cpu = platform.processor()
    return f"{platform.system()} {platform.machine()} " + hashlib.sha256(cpu.encode()).hexdigest()


def build_shared_object(source: str, name: str, compiler: Compiler, out: Path) -> None:
    """Compile the C ``source`` to the shared object ``out`` (its directory must exist).

    The source is written to a private temporary directory, removed on success and
    on failure; the compiler runs on an argument list (no shell).

    Parameters
    ----------
    source
        C source.
    name
        The function's name (for messages and the file name).
    compiler
        From :func:`find_compiler`.
    out
        Where the shared object goes.

    Raises
    ------
    CompilerError
        When the compiler fails (its messages included).
    """
    directory = tempfile.mkdtemp(prefix="designlab_cc_")
    try:
        c_path = os.path.join(directory, "source.c")
        with open(c_path, "w") as fh:
            fh.write(source)
        argv = [*compiler.command, *FLAGS, c_path, "-o", str(out), "-lm"]
        try:
            res = subprocess.run(argv, capture_output=True, text=True)
        except OSError as exc:
            raise CompilerError(f"compiling {name!r} failed: {exc}") from None
        if res.returncode != 0:
            raise CompilerError(f"compiling {name!r} failed: {res.stderr.strip()[-2000:]}")
    finally:
        shutil.rmtree(directory, ignore_errors=True)
