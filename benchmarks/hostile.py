"""Hostile-input harness: every declared input answered right or refused (issue 41).

Generates hostile inputs systematically from the declarations (``designlab/params.py`` and
each domain's parameters module: every declared parameter with its bounds) and from the
study files, runs each case in a forked worker with a per-case timeout, and classifies the
outcome:

clear
    a ``DesignlabError`` or ``ValueError`` whose message names the parameter and the
    offending value (the house rule, docs/developers.md).
accepted
    answered, and the answer passes the case's oracle (finite, physically possible, equal to
    a closed form or a 40-digit mpmath evaluation where one is at hand).
traceback
    any other exception (``TypeError``, ``KeyError``, ``ZeroDivisionError``,
    ``RecursionError``, ``MemoryError``, ...), a worker that died, or a bare ``ValueError``
    from the inside that names neither the parameter nor the value.
hang
    the case did not finish within the timeout (20 s; 45 s for a CLI command).
silent
    accepted, but the answer violates the oracle (NaN, inf or a negative value where that
    is impossible, an arrival faster than the robot can drive, a value far from a closed
    form or from the 40-digit reference of the impact, reduced or full joint), or a value
    its own declaration refuses was answered (outside its domain no answer is vouched for).
    A NaN the target's base answer has too, or that its docs define, is not counted.
unclear
    a ``DesignlabError`` (or a ``ValueError`` naming the parameter) whose message does not
    name the parameter or the offending value.

Run one domain per invocation (one to ten minutes of one core each; ``nice`` it)::

    nice python benchmarks/hostile.py --domain impact --json impact.json
    nice python benchmarks/hostile.py --domain navigation --filter "simulate_planner|crowd"
    python benchmarks/hostile.py --merge impact.json yaml.json --findings notes.md

Domains: impact, codesign, navigation, following, yaml (every leaf of a small study of each
kind; the quick kinds also run and write their report), cli (hostile files and options, in
a subprocess). The output is the table of outcomes per domain and, per kind of fault, the
cases and one reproduction; ``--findings FILE`` appends them as Markdown under a dated
heading, ``--merge`` tallies earlier ``--json`` runs without running anything.
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import json
import math
import multiprocessing as mp
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
import traceback
import warnings
from collections import Counter
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

OUTCOMES = ("clear", "accepted", "traceback", "hang", "silent", "unclear")
ROOT = Path(__file__).resolve().parents[1]
NOVALUE: Any = object()


# ------------------------------------------------------------------------ cases


#: Names of the fields that are non-finite in the base answer of the running case's target
#: (a NaN there is by design, not caused by the hostile value); set by :func:`judge`.
_BASELINE: dict[int, frozenset[str]] = {}
_IGNORE: list[frozenset[str]] = [frozenset()]


@dataclasses.dataclass
class Case:
    """One hostile input: how to run it, what a clear refusal names, how to judge an answer.

    ``expect`` is ``"refuse"`` (the declaration refuses the value), ``"accept"`` (it admits
    it: answered right or refused clearly) or ``"either"`` (no declaration to tell).
    ``oracle`` returns ``None`` for a plausible answer, else what is wrong with it.
    ``judge`` replaces the whole classification (CLI cases judge an exit code).
    """

    domain: str
    name: str
    call: Callable[[], Any]
    names: tuple[str, ...] = ()
    value: Any = NOVALUE
    expect: str = "either"
    oracle: Callable[[Any], str | None] | None = None
    repro: str = ""
    judge: Callable[[Any], tuple[str, str]] | None = None
    baseline: Callable[[], Any] | None = None
    timeout: float | None = None


def _value_texts(value: Any) -> list[str]:
    """The ways a message may show ``value`` (repr, str, %g, YAML spellings)."""
    if value is NOVALUE:
        return []
    out = {repr(value), str(value)}
    if isinstance(value, float):
        out |= {f"{value:g}", f"{value:.6g}", f"{value:.17g}"}
        if math.isnan(value):
            out |= {"nan", "NaN", ".nan"}
        elif math.isinf(value):
            out |= {"inf", "infinity", "Infinity", ".inf"}
        elif value.is_integer():
            out.add(str(int(value))[:15])
    if isinstance(value, bool):
        out |= {"true", "false", "boolean", "bool"}
    if value is None:
        out |= {"null", "None", "none", "missing", "give ", "required"}
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) < 10**30:
        out.add(f"{float(value):g}")
    if isinstance(value, complex):
        out |= {"complex", "j)"}
    if isinstance(value, (list, tuple, dict)):
        out |= {"list", "sequence", "pair", "array", "mapping", "dict", "tuple", "1-D"}
    if isinstance(value, dict):
        out |= {str(k) for k in value}
    if isinstance(value, (list, tuple)) and len(value) <= 10:
        out |= {t for v in value for t in _value_texts(v) if len(t) > 1 or t.isalnum()}
    if isinstance(value, str) and value:
        out.add(repr(value[0]))
    if isinstance(value, (list, tuple)) and len(value) > 10:
        out |= {str(len(value)), "values", "elements", "size", "length"}
    if isinstance(value, str):
        out |= {value, "text", "str", "string"}
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10**30:
        out |= {"digits", "integer", "too large", "too long", str(value)[:20]}
    return [t for t in out if t]


def judge_error(case: Case, exc: BaseException) -> tuple[str, str]:
    """Classify an exception: clear, unclear or traceback (with a one-line detail)."""
    from designlab.errors import DesignlabError

    text = f"{type(exc).__name__}: {exc}"
    line = text.splitlines()[0][:240] if text else type(exc).__name__
    if not isinstance(exc, (DesignlabError, ValueError)) or _is_library_value_error(exc):
        return "traceback", line
    message = str(exc).lower()
    named = not case.names or any(n.lower() in message for n in case.names)
    shown = case.value is NOVALUE or any(t.lower() in message for t in _value_texts(case.value))
    if named and shown:
        return "clear", line
    missing = [w for w, ok in (("parameter", named), ("value", shown)) if not ok]
    if not isinstance(exc, DesignlabError) and not named:
        # a bare ValueError about something else escaped from the inside ('need at least
        # one array to concatenate', 'not enough values to unpack'): a crash, not a refusal
        return "traceback", f"an internal {line}"
    return "unclear", f"names no {' or '.join(missing)}: {line}"


def _is_library_value_error(exc: BaseException) -> bool:
    """A ValueError raised inside numpy/scipy/casadi rather than by designlab itself."""
    from designlab.errors import DesignlabError

    if isinstance(exc, DesignlabError):
        return False
    tb = traceback.extract_tb(exc.__traceback__)
    return bool(tb) and "designlab" not in tb[-1].filename


def judge(case: Case) -> tuple[str, str]:
    """Run one case (in the worker) and classify its outcome."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = case.call()
    except RecursionError as exc:
        return "traceback", f"RecursionError: {str(exc)[:200]}"
    except MemoryError as exc:
        return "traceback", f"MemoryError: {str(exc)[:200]}"
    except Exception as exc:
        if case.judge is not None:
            return case.judge(exc)
        return judge_error(case, exc)
    if case.judge is not None:
        return case.judge(result)
    _IGNORE[0] = _baseline_nonfinite(case.baseline)
    return judge_answer(case, result)


def _baseline_nonfinite(baseline: Callable[[], Any] | None) -> frozenset[str]:
    """The non-finite fields of a target's base answer (computed once per worker)."""
    if baseline is None:
        return frozenset()
    key = id(getattr(baseline, "__self__", baseline))  # one per target, not per case
    if key not in _BASELINE:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                base = baseline()
            bad = {n for n, a in numbers_of(base) if not np.isfinite(a).all()}
        except Exception:  # a base that fails: nothing to ignore
            bad = set()
        _BASELINE[key] = frozenset(bad)
    return _BASELINE[key]


def judge_answer(case: Case, result: Any) -> tuple[str, str]:
    """An answered case: silent if the declaration refuses the value or the oracle objects."""
    if case.expect == "refuse":
        # outside the declared domain no answer is vouched for, right or not
        return "silent", "accepted a value its declaration refuses" + _oracle_note(case, result)
    if case.oracle is None:
        return "accepted", ""
    try:
        problem = case.oracle(result)
    except Exception as exc:
        return "silent", f"answer unreadable by the oracle: {type(exc).__name__}: {exc}"[:240]
    return ("silent", problem) if problem else ("accepted", "")


def _oracle_note(case: Case, result: Any) -> str:
    if case.oracle is None:
        return ""
    try:
        problem = case.oracle(result)
    except Exception:
        return ""
    return f"; and {problem}" if problem else ""


# ----------------------------------------------------------------------- worker


def _worker(cases: Sequence[Case], conn: Any, memory_gib: float, warmup: Any) -> None:
    """Run the cases whose index arrives on ``conn``; send back (outcome, detail)."""
    limit = int(memory_gib * 2**30)
    try:
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    except (ValueError, OSError):
        pass
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 3000))
    import logging

    logging.disable(logging.CRITICAL)
    if warmup is not None:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                warmup()
        except Exception:
            pass
    conn.send("ready")
    while True:
        index = conn.recv()
        if index is None:
            return
        outcome = judge(cases[index])
        conn.send(outcome)


class Pool:
    """One forked worker at a time: killed and replaced when a case hangs or kills it."""

    def __init__(self, cases: Sequence[Case], memory_gib: float, warmup: Any = None) -> None:
        self.cases, self.memory_gib, self.warmup = cases, memory_gib, warmup
        self.ctx = mp.get_context("fork")
        self.proc: Any = None
        self.conn: Any = None

    def _start(self) -> None:
        parent, child = self.ctx.Pipe()
        self.proc = self.ctx.Process(
            target=_worker, args=(self.cases, child, self.memory_gib, self.warmup), daemon=True
        )
        self.proc.start()
        self.conn = parent
        if not parent.poll(900) or parent.recv() != "ready":
            raise RuntimeError("the hostile-input worker did not start")

    def stop(self) -> None:
        if self.proc is None:
            return
        if self.proc.is_alive():
            self.proc.kill()
        self.proc.join(5)
        self.proc = None

    def run(self, index: int, timeout: float) -> tuple[str, str, float]:
        if self.proc is None or not self.proc.is_alive():
            self._start()
        start = time.monotonic()
        self.conn.send(index)
        try:
            ready = self.conn.poll(timeout)
            if not ready:
                self.stop()
                return "hang", f"no answer within {timeout:g} s", time.monotonic() - start
            outcome, detail = self.conn.recv()
        except (EOFError, OSError):
            code = self.proc.exitcode if self.proc is not None else None
            self.stop()
            return "traceback", f"worker died (exit code {code})", time.monotonic() - start
        return outcome, detail, time.monotonic() - start


def run_cases(
    cases: Sequence[Case],
    timeout: float = 20.0,
    memory_gib: float = 6.0,
    verbose: bool = False,
    warmup: Callable[[], Any] | None = None,
) -> list[dict[str, Any]]:
    """Run every case in a forked worker with a timeout; one row per case.

    Parameters
    ----------
    cases
        The cases.
    timeout
        Seconds a case may take before it counts as a hang (its worker is killed).
    memory_gib
        The worker's address-space limit (a runaway allocation is a MemoryError).
    verbose
        Print each non-clean case as it is found.
    warmup
        Run once before the first worker is forked (compiles; not timed).

    Returns
    -------
    list of dict
        ``domain, name, outcome, detail, seconds, repro`` per case.
    """
    if warmup is not None:  # once, here: every forked worker inherits what it compiled
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                warmup()
        except Exception as exc:  # the cases will show it
            print(f"  warm-up failed: {type(exc).__name__}: {exc}", flush=True)
    pool = Pool(cases, memory_gib)
    rows = []
    try:
        for i, case in enumerate(cases):
            outcome, detail, seconds = pool.run(i, case.timeout or timeout)
            rows.append(
                {
                    "domain": case.domain,
                    "name": case.name,
                    "outcome": outcome,
                    "detail": detail,
                    "seconds": round(seconds, 3),
                    "repro": case.repro,
                }
            )
            if verbose and outcome not in ("clear", "accepted"):
                print(f"  [{outcome}] {case.name}: {detail}", flush=True)
            if verbose and (i + 1) % 100 == 0:
                print(f"  ... {i + 1}/{len(cases)} cases", flush=True)
    finally:
        if pool.conn is not None and pool.proc is not None and pool.proc.is_alive():
            pool.conn.send(None)
            pool.proc.join(5)
        pool.stop()
    return rows


# --------------------------------------------------------------- hostile values


def _outside(bound: float, below: bool) -> float:
    step = max(abs(bound) * 1e-6, 1e-9)
    return bound - step if below else bound + step


def _bound_values(decl: Any) -> list[tuple[str, Any]]:
    out: list[tuple[str, Any]] = []
    integer = decl.kind == "integer"
    for op, b in decl._bounds():
        if b is None or not math.isfinite(b):
            continue
        below = op in (">", ">=")
        if integer:
            out.append((f"at {op}{b:g}", int(b)))
            out.append((f"outside {op}{b:g}", int(b) - 1 if below else int(b) + 1))
        else:
            out.append((f"at {op}{b:g}", float(b)))
            out.append((f"outside {op}{b:g}", _outside(float(b), below)))
    return out


#: Magnitudes tried where the declaration admits them (where double precision runs out).
LADDER = (1e-200, 1e-12, 1e-6, 1e6, 1e9, 1e13, 3e13, 1e17, 1e18, 1e20)

#: The hostile values of a real parameter, whatever its bounds.
REAL_ATTACKS: tuple[tuple[str, Any], ...] = (
    ("nan", math.nan),
    ("+inf", math.inf),
    ("-inf", -math.inf),
    ("0", 0.0),
    ("-1", -1.0),
    ("1e300", 1e300),
    ("1e-300", 1e-300),
    ("complex", 1.0 + 1.0j),
    ("text", "1.0"),
    ("bool", True),
    ("None", None),
    ("list", [1.0, 1.0]),
)

INTEGER_ATTACKS: tuple[tuple[str, Any], ...] = (
    ("0", 0),
    ("-1", -1),
    ("1.5", 1.5),
    ("nan", math.nan),
    ("2**31", 2**31),
    ("10**12", 10**12),
    ("2**64", 2**64),
    ("text", "3"),
    ("bool", True),
    ("None", None),
    ("list", [3, 3]),
)

CHOICE_ATTACKS: tuple[tuple[str, Any], ...] = (
    ("typo", "nope"),
    ("empty", ""),
    ("number", 1),
    ("None", None),
    ("list", ["a"]),
)

FLAG_ATTACKS: tuple[tuple[str, Any], ...] = (("text", "yes"), ("int", 1), ("None", None))


#: The generic attacks on a field of a model (its constructor checks them all in one place).
FIELD_ATTACKS = ("nan", "+inf", "-1", "1e300", "complex", "text", "None")


def hostile_values(
    decl: Any, default: Any = None, field: bool = False, ladder: bool = True
) -> list[tuple[str, Any]]:
    """The hostile values of one declared parameter: generic attacks, its bounds, a ladder.

    Parameters
    ----------
    decl
        A :class:`designlab.params.Param` (``None``: a real without a declaration).
    default
        The parameter's value in the base case (a ladder value equal to it is skipped).
    field
        A field of a model: fewer generic attacks (:data:`FIELD_ATTACKS`).
    ladder
        Add the admitted magnitudes of :data:`LADDER`.
    """
    kind = "real" if decl is None else decl.kind
    if kind == "real":
        out = [a for a in REAL_ATTACKS if not field or a[0] in FIELD_ATTACKS]
        if decl is not None:
            out += _bound_values(decl)
            if ladder:
                out += [(f"{x:g}", x) for x in LADDER if decl.within(x) and x != default]
        return out
    if kind == "integer":
        return list(INTEGER_ATTACKS) + _bound_values(decl)
    if kind == "choice":
        return list(CHOICE_ATTACKS)
    if kind == "flag":
        return list(FLAG_ATTACKS)
    if kind == "text":
        return [("number", 3.0), ("huge text", "x" * 1_000_000)]
    return []


def expectation(decl: Any, value: Any, check: Callable[[Any], Any] | None = None) -> str:
    """Whether the declaration admits ``value`` (``"accept"``) or refuses it (``"refuse"``).

    ``"either"`` where there is no declaration to tell. An answer to a refused value is a
    silent wrong answer: outside its declared domain no answer is vouched for.
    """
    if check is None and decl is None:
        return "either"
    try:
        (check or decl.check)(value)
    except Exception:  # any refusal
        return "refuse"
    return "accept"


def fmt(value: Any) -> str:
    """A value as Python source (for the reproductions)."""
    if isinstance(value, float):
        if math.isnan(value):
            return "float('nan')"
        if math.isinf(value):
            return "float('inf')" if value > 0 else "-float('inf')"
    if isinstance(value, str) and len(value) > 40:
        return f"'x' * {len(value)}"
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10**20:
        power = value.bit_length() - 1
        return f"2**{power}" if value == 2**power else repr(value)
    if isinstance(value, tuple):
        return "(" + ", ".join(fmt(v) for v in value) + ("," if len(value) == 1 else "") + ")"
    if isinstance(value, list):
        if len(value) > 10 and all(_same(v, value[0]) for v in value):
            return f"[{fmt(value[0])}] * {len(value)}"
        return "[" + ", ".join(fmt(v) for v in value) + "]"
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return _fmt_dataclass(value)
    return repr(value)


def _fmt_dataclass(obj: Any) -> str:
    parts = []
    for f in dataclasses.fields(obj):
        if not f.init:
            continue
        v = getattr(obj, f.name)
        if f.default is not dataclasses.MISSING and _same(v, f.default):
            continue
        parts.append(f"{f.name}={fmt(v)}")
    return f"{type(obj).__name__}({', '.join(parts)})"


def _same(a: Any, b: Any) -> bool:
    try:
        return bool(a == b)
    except Exception:
        return False


# ---------------------------------------------------------- targets (Python API)


@dataclasses.dataclass
class Obj:
    """An argument built from a declared class: ``cls(**fields)``; its fields are attacked."""

    cls: type
    fields: dict[str, Any]
    only: tuple[str, ...] | None = None
    skip: tuple[str, ...] = ("name",)
    ladder: bool = False


@dataclasses.dataclass
class Val:
    """A plain argument; ``decl`` is its declaration (``None``: found by the argument's name
    in the domain's parameter modules; :data:`UNDECLARED`: none). ``text`` shows the base
    value in reproductions."""

    value: Any
    decl: Any = None
    attacks: list[tuple[str, Any]] | None = None
    check: Callable[[Any], Any] | None = None
    text: str = ""


#: The ``decl`` of an argument without a declaration (not to be looked up by its name).
UNDECLARED: Any = "undeclared"


@dataclasses.dataclass
class Target:
    """A public function with a valid base call; every argument and field is attacked."""

    domain: str
    label: str
    func: Callable[..., Any]
    args: dict[str, Obj | Val]
    positional: tuple[str, ...] = ()
    oracle: Callable[[Any], str | None] | None = None
    attack: tuple[str, ...] | None = None
    tag: str = ""
    given: Callable[[Any, dict[str, Any]], str | None] | None = None
    template: str = ""

    def base_call(self) -> Any:
        """The base call (its answer tells which NaN fields are by design)."""
        return self.call({})

    def arguments(self, over: dict[str, Any]) -> dict[str, Any]:
        """The plain arguments of a call (objects left out), ``over`` applied."""
        return {n: over.get(n, s.value) for n, s in self.args.items() if isinstance(s, Val)}

    def judge_with(self, over: dict[str, Any]) -> Callable[[Any], str | None] | None:
        """The oracle of one call: ``oracle`` and ``given`` (which also sees the arguments)."""
        if self.given is None:
            return self.oracle
        args = self.arguments(over)
        given = self.given
        checks = [o for o in (self.oracle, lambda r: given(r, args)) if o is not None]
        return all_of(*checks)

    def call(self, over: dict[str, Any]) -> Any:
        """Call the function with the base arguments, ``over`` replacing some of them."""
        built = {name: self._build(name, spec, over) for name, spec in self.args.items()}
        pos = [built.pop(n) for n in self.positional]
        return self.func(*pos, **built)

    def _build(self, name: str, spec: Obj | Val, over: dict[str, Any]) -> Any:
        if isinstance(spec, Val):
            return over.get(name, spec.value)
        fields = dict(spec.fields)
        for key, v in over.items():
            if key.startswith(name + "."):
                fields[key[len(name) + 1 :]] = v
        return spec.cls(**fields)

    def repro(self, over: dict[str, Any]) -> str:
        """The call as one line of Python (``dl`` is designlab, classes by their names)."""
        parts, named = [], {}
        for name, spec in self.args.items():
            if isinstance(spec, Val):
                text = (
                    spec.text if name not in over and spec.text else fmt(over.get(name, spec.value))
                )
            else:
                fields = dict(spec.fields)
                fields.update({k[len(name) + 1 :]: v for k, v in over.items()
                               if k.startswith(name + ".")})  # fmt: skip
                inner = ", ".join(f"{k}={fmt(v)}" for k, v in fields.items())
                text = f"{spec.cls.__name__}({inner})"
            named[name] = text
            parts.append(text if name in self.positional else f"{name}={text}")
        if self.template:
            return self.template.format(**named)
        return f"{self.label}({', '.join(parts)})"


def _decl_for(func: Callable[..., Any], name: str, extra: Sequence[Any], base: Any) -> Any:
    """The module-level declaration of a function argument, found by its name.

    Only a declaration of the base value's kind: an argument that is an array shares its
    name with the declaration of its length (``gains``, ``speeds``), which is not its own.
    """
    from designlab.params import Param

    mod = sys.modules.get(getattr(func, "__module__", ""), None)
    pools = [vars(mod)] if mod is not None else []
    pools += [vars(m) for m in extra]
    scalar = base is None or isinstance(base, (int, float, str, bool))
    for pool in pools:
        found = [v for v in pool.values() if isinstance(v, Param) and v.name == name]
        if len(found) == 1:
            return found[0] if scalar else None
    return None


def target_cases(t: Target, decl_modules: Sequence[Any] = ()) -> list[Case]:
    """Every hostile case of a target: each declared field and argument, each attack."""
    from designlab.params import params_of

    cases = []
    for name, spec in t.args.items():
        if t.attack is not None and name not in t.attack:
            continue
        if isinstance(spec, Obj):
            for field, decl in params_of(spec.cls).items():
                if field in spec.skip or (spec.only is not None and field not in spec.only):
                    continue
                base = spec.fields.get(field, decl.default)
                for label, v in hostile_values(decl, base, field=True, ladder=spec.ladder):
                    path = f"{name}.{field}"
                    cases.append(_case(t, path, (field, path), label, v, expectation(decl, v)))
            continue
        decl = spec.decl
        if decl is None:
            decl = _decl_for(t.func, name, decl_modules, spec.value)
        decl = None if decl is UNDECLARED else decl
        attacks = spec.attacks if spec.attacks is not None else hostile_values(decl, spec.value)
        for label, v in attacks:
            names = (name,) + ((decl.name,) if decl is not None and decl.name else ())
            cases.append(_case(t, name, names, label, v, expectation(decl, v, spec.check)))
    return cases


def _case(t: Target, path: str, names: tuple[str, ...], label: str, v: Any, expect: str) -> Case:
    over = {path: v}
    return Case(
        domain=t.domain,
        name=f"{t.label}{t.tag} {path}={label}",
        call=lambda: t.call(over),
        names=names,
        value=v,
        expect=expect,
        oracle=t.judge_with(over),
        repro=t.repro(over),
        baseline=t.base_call,
    )


def simple_case(domain: str, label: str, func: Callable[[], Any], repro: str, *,
                names: tuple[str, ...] = (), value: Any = NOVALUE, expect: str = "either",
                oracle: Callable[[Any], str | None] | None = None) -> Case:  # fmt: skip
    """A hand-written case (a sibling of a reported failure)."""
    return Case(domain, label, func, names, value, expect, oracle, repro)


# ---------------------------------------------------------------------- oracles


def numbers_of(obj: Any, prefix: str = "", depth: int = 0) -> list[tuple[str, np.ndarray]]:
    """The numeric fields of a result (dataclass fields, arrays, frames), by name."""
    import pandas as pd

    out: list[tuple[str, np.ndarray]] = []
    if depth > 3:
        return out
    if isinstance(obj, (bool, np.bool_)):
        return out
    if isinstance(obj, (int, float, np.integer, np.floating)):
        return [(prefix, np.asarray(float(obj)))]
    if isinstance(obj, np.ndarray) and obj.dtype.kind in "fiu":
        return [(prefix, obj.astype(float))]
    if isinstance(obj, pd.DataFrame):
        num = obj.select_dtypes("number")
        return [(f"{prefix}.{c}", num[c].to_numpy(dtype=float)) for c in num.columns]
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        for f in dataclasses.fields(obj):
            child = getattr(obj, f.name)
            if f.name.startswith("_") or (depth == 0 and hasattr(child, "__params__")):
                continue  # an input model echoed on the answer is not part of the answer
            out += numbers_of(getattr(obj, f.name), f"{prefix}.{f.name}".lstrip("."), depth + 1)
    return out


def _honest(result: Any) -> bool:
    """The result says it failed or is doubtful (status other than ok, or warnings)."""
    status = getattr(result, "status", "ok")
    if isinstance(status, (np.ndarray, list, tuple)):
        bad = any(str(s) != "ok" for s in np.ravel(status))
    else:
        bad = str(status) != "ok"
    return bad or bool(getattr(result, "warnings", ()))


def finite_oracle(
    nonneg: Sequence[str] = (), positive: Sequence[str] = (), allow_nan: Sequence[str] = ()
) -> Callable[[Any], str | None]:
    """Every numeric field finite (unless the result says why not); some never negative."""

    def oracle(result: Any) -> str | None:
        honest = _honest(result)
        for name, arr in numbers_of(result):
            leaf = name.split(".")[-1]
            expected = name in _IGNORE[0] or any(p in allow_nan for p in name.split("."))
            if not honest and not expected and not np.isfinite(arr).all():
                return f"{name} is not finite ({_first_bad(arr)}) with status ok"
            finite = arr[np.isfinite(arr)]
            if leaf in nonneg and (finite < 0).any():
                return f"{name} is negative ({finite.min():.6g})"
            if leaf in positive and (finite <= 0).any() and not honest:
                return f"{name} is not positive ({finite.min():.6g}) with status ok"
        return None

    return oracle


def _first_bad(arr: np.ndarray) -> str:
    bad = np.ravel(arr)[~np.isfinite(np.ravel(arr))]
    return f"{bad[0]!r}" if bad.size else "?"


def all_of(*oracles: Callable[[Any], str | None]) -> Callable[[Any], str | None]:
    """The first objection of several oracles."""

    def oracle(result: Any) -> str | None:
        for o in oracles:
            problem = o(result)
            if problem:
                return problem
        return None

    return oracle


# -------------------------------------------------- impact: a 40-digit reference


def _impact_matrix(p: Sequence[float], v: float) -> Any:
    """The unconstrained model (docs/impact.md) as z' = A z, z = [d_r, d_r', d_h, d_h', s_c, 1]."""
    import mpmath

    m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h = (mpmath.mpf(x) for x in p)
    vv = mpmath.mpf(v)
    a = mpmath.zeros(6, 6)
    # f_c = K_c (d_r - d_h + s) + C_c (d_r' - d_h' + v)
    fc = [k_c, c_c, -k_c, -c_c, k_c, c_c * vv]
    a[0, 1] = 1
    a[2, 3] = 1
    a[4, 5] = vv
    for j in range(6):
        a[1, j] = -fc[j] / m_r
        a[3, j] = fc[j] / m_h
    a[1, 1] -= c_r / m_r
    a[1, 0] -= k_r / m_r
    a[3, 3] -= c_h / m_h
    a[3, 2] -= k_h / m_h
    return a, fc


def _full_joint_matrix(p: Sequence[float]) -> Any:
    """The full series joint (docs/impact_joint.md), v_c = 1: z = [d_r, d_r', d_e, d_h, d_h', s, 1].

    ``None`` where C_mech + C_cont = 0 (the node's equation is then algebraic).
    """
    import mpmath

    m_r, c_m, k_m, k_c, c_c, m_h, c_h, k_h, c_k, k_k = (mpmath.mpf(x) for x in p)
    if c_m + c_k == 0:
        return None
    a = mpmath.zeros(7, 7)
    fc = [k_c, c_c, 0, -k_c, -c_c, k_c, c_c]
    # K_m (d_r - d_e) + C_m (d_r' - d_e') = K_k d_e + C_k d_e'
    de = [k_m / (c_m + c_k), c_m / (c_m + c_k), -(k_m + k_k) / (c_m + c_k), 0, 0, 0, 0]
    ft = [c_k * de[j] for j in range(7)]
    ft[2] += k_k
    for j in range(7):
        a[1, j] = -(fc[j] + ft[j]) / m_r
        a[2, j] = de[j]
        a[4, j] = fc[j] / m_h
    a[0, 1] = 1
    a[3, 4] = 1
    a[4, 4] -= c_h / m_h
    a[4, 3] -= k_h / m_h
    a[5, 6] = 1
    return a, fc


def impact_reference(
    p: Sequence[float], v: float, max_steps: int = 6000, full: bool = False
) -> dict[str, float] | None:
    """First-lobe metrics of an impact at 40 digits (mpmath), or ``None``.

    ``p`` is the reduced model's parameter row (``PARAM_NAMES``), or with ``full`` the
    full joint's (``FULL_PARAM_NAMES``). The lobe ends at the first t > 0 where the head
    acceleration is <= 0 (docs/impact.md, "Metrics"); eps_max, a_h,max and f_c,max are
    maxima over it. ``None`` where the lobe is not found within ``max_steps`` grid steps.
    """
    import mpmath

    if not (v > 0 and math.isfinite(v)):
        return None
    # The model is linear in v_c: evaluate at 1 m/s and scale (the lobe does not move).
    with mpmath.workdps(40):
        built = _full_joint_matrix(p) if full else _impact_matrix(p, 1.0)
        if built is None:
            return None
        a, fc = built
        n = a.rows
        eps = [0] * n
        head = 3 if full else 2
        eps[0], eps[head], eps[n - 2] = 1, -1, 1
        rows = {
            "max_compression": mpmath.matrix([eps]),
            "peak_head_acceleration": a[head + 1, :],
            "peak_force": mpmath.matrix([fc]),
        }
        return _first_lobe(a, rows, max_steps, v)


def _first_lobe(a: Any, rows: dict[str, Any], max_steps: int, v: float) -> dict[str, float] | None:
    import mpmath

    ah = rows["peak_head_acceleration"]
    n = a.rows
    lam = np.linalg.eigvals(np.array(a.tolist(), dtype=float)[: n - 2, : n - 2])
    w = float(np.max(np.abs(lam))) if np.all(np.isfinite(lam)) else 0.0
    if not w > 0:
        return None
    h = mpmath.mpf(1) / (24 * w)
    step = mpmath.expm(a * h)
    zs = [mpmath.matrix([0] * (n - 1) + [1])]
    for _ in range(max_steps):
        zs.append(step * zs[-1])
        if len(zs) > 2 and (ah * zs[-1])[0] <= 0:
            break
    else:
        return None
    k = len(zs) - 2
    grid = _Grid(a, zs, h)
    t_end = mpmath.findroot(lambda t: grid.value(ah, t), (k * h, (k + 1) * h),
                            solver="anderson")  # fmt: skip
    out = {"impact_duration": float(t_end)}
    for key, row in rows.items():
        out[key] = float(grid.maximum(row, t_end) * mpmath.mpf(v))
    return out


class _Grid:
    """z(t) on grid nodes t_k = k h, between them by a Taylor series from the node."""

    def __init__(self, a: Any, zs: list[Any], h: Any) -> None:
        self.a, self.zs, self.h = a, zs, h

    def state(self, t: Any) -> Any:
        import mpmath

        k = min(max(int(mpmath.floor(t / self.h)), 0), len(self.zs) - 1)
        tau = t - k * self.h
        term, total = self.zs[k], self.zs[k]
        for n in range(1, 200):
            term = (self.a * term) * (tau / n)
            total = total + term
            if mpmath.mnorm(term, 1) <= mpmath.mpf(10) ** -45 * (1 + mpmath.mnorm(total, 1)):
                break
        return total

    def value(self, row: Any, t: Any) -> Any:
        return (row * self.state(t))[0]

    def maximum(self, row: Any, t_end: Any) -> Any:
        """The maximum over [0, t_end]: grid nodes, every near-best local maximum refined."""
        import mpmath

        vals = [(row * z)[0] for z in self.zs[:-1]]
        best = max([*vals, self.value(row, t_end)])
        d = row * self.a
        slopes = [(d * z)[0] for z in self.zs[:-1]] + [self.value(d, t_end)]
        knots = [i * self.h for i in range(len(vals))] + [t_end]
        turns = [i for i in range(len(vals)) if slopes[i] > 0 >= slopes[i + 1]]
        turns.sort(key=lambda i: -max(vals[i], vals[min(i + 1, len(vals) - 1)]))
        for i in turns[:6]:
            t = mpmath.findroot(lambda t: self.value(d, t), (knots[i], knots[i + 1]),
                                solver="anderson")  # fmt: skip
            if knots[i] <= t <= knots[i + 1]:
                best = max(best, self.value(row, t))
        return best


def reference_oracle(
    params_of_result: Callable[[Any], tuple[list[list[float]], list[float], bool]],
    rtol: float = 1e-6,
) -> Callable[[Any], str | None]:
    """An impact answer within ``rtol`` of the 40-digit reference, each finite metric."""

    def oracle(result: Any) -> str | None:
        rows, velocities, full = params_of_result(result)
        for i, (p, v) in enumerate(zip(rows, velocities, strict=True)):
            if not v > 0:
                continue
            got = _metric_row(result, i)
            if got is None:
                continue
            ref = impact_reference(p, v, full=full)
            if ref is None:
                continue
            for key, want in ref.items():
                have = got.get(key)
                if have is None or key == "impact_duration" or not math.isfinite(have):
                    continue
                if not math.isclose(have, want, rel_tol=rtol, abs_tol=1e-300):
                    return (f"{key} = {have:.8g} where a 40-digit evaluation gives {want:.8g} "
                            f"(status {_status_of(result, i)})")  # fmt: skip
        return None

    return oracle


def _status_of(result: Any, i: int) -> str:
    status = getattr(result, "design_status", None)
    if status is not None:
        return str(np.ravel(status)[i])
    return str(getattr(result, "status", "?"))


def _metric_row(result: Any, i: int) -> dict[str, float] | None:
    """The finite metrics of design ``i`` (a status flags a design, it does not excuse a
    wrong number; a metric the result leaves NaN is its own business)."""
    keys = ("max_compression", "peak_head_acceleration", "peak_force", "impact_duration")
    out = {}
    for key in keys:
        val = getattr(result, key, None)
        if val is not None:
            out[key] = float(np.ravel(val)[i]) if np.ndim(val) else float(val)
    return out


# ------------------------------------------------------------------ domain: impact

BASE_ROBOT = {"mass": 9.6, "stiffness": 20e3, "damping": 250.0}
BASE_FOAM = {"stiffness": 24.25e3, "damping": 71.9}
#: the declared fields of a speed limit's dl.codesign.SafetyCase (its defaults)
BASE_CASE = {"human_speed": 1.0, "reaction_time": 0.0, "deceleration": 10.0,
             "detection_distance": 0.0, "head_levels": 3}  # fmt: skip
#: a foam given by its compression curve (designlab.impact.contact.measured), crushed at 36 mm
BASE_CURVE_FOAM = {"strain": (0.1, 0.3, 0.6, 0.9), "stress": (20e3, 50e3, 120e3, 600e3),
                   "area": 0.01, "thickness": 0.04, "damping": 71.9}  # fmt: skip
#: the non-linear foam (Hunt-Crossley damping, densification): its own fields are attacked
BASE_HC_FOAM = {"stiffness": 24.25e3, "damping": 71.9, "densification_depth": 0.02}
BASE_HEAD = {"mass": 4.4, "stiffness": 4e3, "damping": 0.0}
BASE_JOINT = {
    "mass": 9.6,
    "transmission_stiffness": 2e5,
    "transmission_damping": 50.0,
    "control_stiffness": 2e4,
    "control_damping": 250.0,
}
IMPACT_METRICS = ("peak_head_acceleration", "max_compression", "peak_force", "impact_duration")


def _response_params(r: Any) -> tuple[list[list[float]], list[float], bool]:
    from designlab.impact.full_joint_model import full_joint_params
    from designlab.impact.model import param_vector

    if r.head is None or r.profile is not None:
        return [], [], False
    v = [float(r.impact_velocity)]
    if type(r.robot).__name__ == "FullJointContact":
        return [list(full_joint_params(r.robot, r.foam, r.head))], v, True
    if type(r.robot).__name__ != "ContactDynamics":
        return [], [], False
    return [list(param_vector(r.robot, r.foam, r.head))], v, False


def _metrics_params(m: Any) -> tuple[list[list[float]], list[float], bool]:
    if m.constrained:
        return [], [], False
    p = np.atleast_2d(np.asarray(m.params, dtype=float))
    v = np.broadcast_to(np.asarray(m.impact_velocity, dtype=float), (p.shape[0],))
    return p.tolist(), v.tolist(), p.shape[1] == 10


def impact_targets() -> list[Target]:
    """simulate, impact_metrics, the full joint, the envelope and the velocity functions."""
    import designlab.impact as im

    nonneg = finite_oracle(nonneg=IMPACT_METRICS, positive=("impact_duration",))
    sim_args = {
        "robot": Obj(im.ContactDynamics, BASE_ROBOT, ladder=True),
        "foam": Obj(im.Foam, BASE_FOAM, ladder=True),
        "head": Obj(im.HeadNeck, BASE_HEAD, ladder=True),
        "impact_velocity": Val(1.25, check=im.parameters.check_closing_velocity),
        "duration": Val(None),
        "samples": Val(2001),
        "stop_time": Val(0.05),
        "q2": Val("correct", attacks=list(CHOICE_ATTACKS)),
    }
    joint_args = {**sim_args, "robot": Obj(im.FullJointContact, BASE_JOINT, ladder=True)}
    return [
        Target("impact", "dl.impact.simulate", im.simulate, sim_args,
               ("robot", "foam", "head", "impact_velocity"),
               all_of(nonneg, reference_oracle(_response_params))),
        Target("impact", "dl.impact.simulate", im.simulate, joint_args,
               ("robot", "foam", "head", "impact_velocity"),
               all_of(nonneg, reference_oracle(_response_params)), attack=("robot",),
               tag="[full-joint]"),
        Target("impact", "dl.impact.simulate", im.simulate,
               {**sim_args, "foam": Obj(im.StressStrainFoam, BASE_CURVE_FOAM, ladder=True)},
               ("robot", "foam", "head", "impact_velocity"), None, attack=("foam",),
               tag="[stress-strain]"),
        Target("impact", "dl.impact.simulate", im.simulate,
               {**sim_args, "foam": Obj(im.HuntCrossleyFoam, BASE_HC_FOAM, ladder=True)},
               ("robot", "foam", "head", "impact_velocity"), nonneg, attack=("foam",),
               tag="[hunt-crossley]"),
        Target("impact", "dl.impact.foam_envelope", im.foam_envelope,
               {"robot": Obj(im.ContactDynamics, BASE_ROBOT), "impact_velocity": Val(1.25),
                "damping": Val([0.0, 60.0, 120.0]), "max_compression": Val(0.02),
                "rtol": Val(1e-6), "human_speed": Val(1.0), "stop_time": Val(0.05)},
               ("robot",), finite_oracle(nonneg=("upper", "stiffness_min", "stiffness_max"),
                                         allow_nan=("upper", "stiffness_min", "stiffness_max",
                                                    "worst_lever_arm"))),
        Target("impact", "dl.impact.max_safe_velocity", im.max_safe_velocity,
               {"robot": Obj(im.ContactDynamics, BASE_ROBOT, ladder=True),
                "foam": Obj(im.Foam, BASE_FOAM, ladder=True), "human_speed": Val(1.0)},
               ("robot", "foam"),
               finite_oracle(nonneg=("impact_velocity",))),
        Target("impact", "dl.impact.min_foam_thickness", im.min_foam_thickness,
               {"robot": Obj(im.ContactDynamics, BASE_ROBOT), "foam": Obj(im.Foam, BASE_FOAM),
                "impact_velocity": Val(1.25, check=im.parameters.check_closing_velocity)},
               ("robot", "foam"), finite_oracle(nonneg=("thickness", "linear_depth")),
               attack=("impact_velocity",)),
    ]  # fmt: skip


def impact_metrics_cases() -> list[Case]:
    """impact_metrics with one column of the parameter row attacked (declared per column)."""
    import designlab.impact as im
    from designlab.params import params_of

    decls = {
        "M_r": params_of(im.ContactDynamics)["mass"],
        "C_r": params_of(im.ContactDynamics)["damping"],
        "K_r": params_of(im.ContactDynamics)["stiffness"],
        "K_c": params_of(im.Foam)["stiffness"],
        "C_c": params_of(im.Foam)["damping"],
        "M_h": params_of(im.HeadNeck)["mass"],
        "C_h": params_of(im.HeadNeck)["damping"],
        "K_h": params_of(im.HeadNeck)["stiffness"],
    }
    base = [9.6, 250.0, 20e3, 24.25e3, 71.9, 4.4, 46.0, 3e3]
    oracle = all_of(finite_oracle(nonneg=IMPACT_METRICS), reference_oracle(_metrics_params))
    cases = []
    for j, (col, decl) in enumerate(decls.items()):
        for label, v in hostile_values(decl, base[j]):
            if isinstance(v, (list, str, bool)) or v is None:
                continue  # not numbers: numpy's business when it builds the array
            row = list(base)
            row[j] = v
            repro = f"dl.impact.impact_metrics([{fmt(row)}], 1.25, columns=dl.impact.PARAM_NAMES)"
            cases.append(Case("impact", f"dl.impact.impact_metrics {col}={label}",
                              _metrics_call(row), (col, decl.name, "params"), v,
                              expectation(decl, v), oracle, repro))  # fmt: skip
    for label, v in [*hostile_values(im.parameters.STOP_TIME), ("lobe 0", 0), ("lobe 1", 1)]:
        key = "max_lobe_steps" if label.startswith("lobe") else "stop_time"
        repro = (f"dl.impact.impact_metrics([{fmt(base)}], 1.25, columns=dl.impact.PARAM_NAMES, "
                 f"{key}={fmt(v)})")  # fmt: skip
        decl = im.parameters.MAX_LOBE_STEPS if key == "max_lobe_steps" else im.parameters.STOP_TIME
        cases.append(Case("impact", f"dl.impact.impact_metrics {key}={label}",
                          _metrics_call(base, **{key: v}), (key,), v, expectation(decl, v),
                          oracle, repro))  # fmt: skip
    return cases


def _metrics_call(row: list[Any], **kw: Any) -> Callable[[], Any]:
    def call() -> Any:
        import designlab as dl

        return dl.impact.impact_metrics([row], 1.25, columns=dl.impact.PARAM_NAMES, **kw)

    return call


#: Attacks on a 3-vector (a velocity or a normal).
VECTOR_ATTACKS: list[tuple[str, Any]] = [
    ("[nan]", [math.nan, 0.0, 0.0]), ("[inf]", [math.inf, 0.0, 0.0]),
    ("[1e300]", [1e300, 0.0, 0.0]), ("zeros", [0.0, 0.0, 0.0]), ("2 values", [1.0, 0.0]),
    ("text", "abc"), ("None", None), ("complex", [1 + 1j, 0.0, 0.0]), ("nested", [[1.0, 0.0, 0.0]]),
]  # fmt: skip


def _closing_given(r: Any, a: dict[str, Any]) -> str | None:
    """v_c = (v_r - v_h) . n / |n| (Sec. 3.4), where the inputs are three finite numbers."""
    try:
        vr, vh, n = (np.asarray(a[k], dtype=float) for k in
                     ("robot_velocity", "head_velocity", "normal"))  # fmt: skip
    except (TypeError, ValueError):
        return None
    if not all(x.shape == (3,) and np.isfinite(x).all() for x in (vr, vh, n)):
        return None
    n = n / np.abs(n).max() if np.abs(n).max() > 0 else n  # |n| of 1e300 is no inf
    want = float(np.dot(vr - vh, n) / np.linalg.norm(n))
    got = float(r.closing_speed)
    if not math.isclose(got, want, rel_tol=1e-12, abs_tol=1e-300):
        return f"closing speed {got!r}, (v_r - v_h) . n/|n| = {want!r}"
    return None


def impact_more_targets() -> list[Target]:
    """The joint, link and plane helpers of the impact domain."""
    import designlab.impact as im
    from designlab.params import params_of

    link = params_of(im.LinkImpact)
    fj = Val(im.FullJointContact(**BASE_JOINT), text="FullJointContact(9.6, 2e5, 50.0, 2e4, 250.0)")
    return [
        Target("impact", "dl.impact.band_fit_sweep", im.band_fit_sweep,
               {"robot": fj, "foam": Val(im.FOAM_1, text="FOAM_1"),
                "head": Val(im.TEST_HEAD, text="TEST_HEAD"), "impact_velocity": Val(1.25),
                "omega_max": Val([100.0, 1000.0], attacks=ARRAY_ATTACKS),
                "stop_time": Val(0.05)}, ("robot", "foam", "head", "impact_velocity"),
               finite_oracle(nonneg=("rms_ratio",)),
               attack=("impact_velocity", "omega_max", "stop_time")),
        Target("impact", "dl.impact.impact_point_sweep", im.impact_point_sweep,
               {"inertia": Val(0.059, decl=link["inertia"]),
                "joint_stiffness": Val(100.0, decl=link["joint_stiffness"]),
                "joint_damping": Val(2.0, decl=link["joint_damping"]),
                "joint_speed": Val(3.0, decl=link["joint_speed"]),
                "lever_arms": Val([0.05, 0.1], attacks=ARRAY_ATTACKS)},
               ("inertia", "joint_stiffness", "joint_damping", "joint_speed", "lever_arms"),
               finite_oracle(nonneg=("mass", "stiffness", "damping", "velocity"))),
        Target("impact", "dl.impact.closing_speed", im.closing_speed,
               {"robot_velocity": Val([1.0, 0.0, 0.0], attacks=VECTOR_ATTACKS),
                "head_velocity": Val([-0.5, 0.0, 0.0], attacks=VECTOR_ATTACKS),
                "normal": Val([1.0, 0.0, 0.0], attacks=VECTOR_ATTACKS)},
               ("robot_velocity", "head_velocity", "normal"),
               finite_oracle(allow_nan=("gamma_r", "gamma_c")),  # NaN for a zero velocity
               given=_closing_given),
        Target("impact", "dl.impact.check_worst_case", _worst_case,
               {"samples": Val(4), "seed": Val(0), "tolerance": Val(1e-6)}, (),
               finite_oracle(), template="dl.impact.check_worst_case(dl.impact.foam_envelope("
               "MANIPULATOR_1, 1.25, damping=[0.0, 60.0]), samples={samples}, seed={seed}, "
               "tolerance={tolerance})"),
    ]  # fmt: skip


def _worst_case(samples: Any, seed: Any, tolerance: Any) -> Any:
    import designlab.impact as im

    env = im.foam_envelope(im.MANIPULATOR_1, 1.25, damping=[0.0, 60.0])
    return im.check_worst_case(env, samples=samples, seed=seed, tolerance=tolerance)


def impact_extra_cases() -> list[Case]:
    """The issue's reported impact cases and their siblings."""
    import designlab as dl

    cases = []
    oracle = finite_oracle(nonneg=IMPACT_METRICS)
    for v in ("10**9", "10**7", "3"):
        cases.append(simple_case("impact", f"dl.impact.simulate samples={v}",
                                 _eval(f"dl.impact.simulate(dl.impact.MANIPULATOR_1, "
                                       f"dl.impact.FOAM_1, dl.impact.TEST_HEAD, 1.25, "
                                       f"samples={v})"),
                                 f"dl.impact.simulate(MANIPULATOR_1, FOAM_1, TEST_HEAD, 1.25, "
                                 f"samples={v})", names=("samples",), oracle=oracle))  # fmt: skip
    cases.append(simple_case("impact", "dl.impact.hic window=nan", _eval(
        "dl.impact.hic(np.linspace(0, 0.05, 101), np.ones(101) * 50, window=float('nan'))"),
        "dl.impact.hic(np.linspace(0, 0.05, 101), np.ones(101) * 50, window=float('nan'))",
        names=("window",), value=math.nan, expect="refuse"))  # fmt: skip
    cases.append(simple_case("impact", "dl.impact.hic t decreasing", _eval(
        "dl.impact.hic(np.linspace(0.05, 0, 101), np.ones(101) * 50)"),
        "dl.impact.hic(np.linspace(0.05, 0, 101), np.ones(101) * 50)", names=("t",),
        oracle=finite_oracle(nonneg=("",))))  # fmt: skip
    del dl
    return cases


def _eval(expr: str) -> Callable[[], Any]:
    """A case given as a Python expression (``dl``, ``np``, ``math`` in scope)."""

    def call() -> Any:
        import designlab as dl

        return eval(expr, {"dl": dl, "np": np, "math": math})

    return call


# ---------------------------------------------------------------- domain: codesign


def _stopping_given(r: Any, a: dict[str, Any]) -> str | None:
    v, t, dec = a["speed"], a["reaction_time"], a["deceleration"]
    want = v * t + v * v / (2.0 * dec)
    if not (isinstance(r, float) and math.isfinite(r) and r >= 0):
        return f"stopping distance {r!r} (must be finite and >= 0)"
    if not math.isclose(r, want, rel_tol=1e-12):
        return f"stopping distance {r!r}, closed form v T_r + v^2/(2 a_b) = {want!r}"
    return None


def _contact_given(r: Any, a: dict[str, Any]) -> str | None:
    if not (isinstance(r, float) and math.isfinite(r) and 0 <= r <= a["speed"]):
        return f"contact speed {r!r} (must be within [0, speed = {a['speed']!r}])"
    return None


def _max_speed_given(r: Any, a: dict[str, Any]) -> str | None:
    from designlab.codesign import contact_speed

    if not (isinstance(r, float) and math.isfinite(r) and r >= 0):
        return f"max robot speed {r!r} (must be finite and >= 0)"
    kw = {k: a[k] for k in ("human_speed", "reaction_time", "deceleration", "detection_distance")}
    at = contact_speed(r, **kw)
    if at > a["contact_limit"] * (1 + 1e-9) + 1e-12:
        return f"at the returned speed {r:.6g} the contact speed is {at:.6g} > the limit"
    return None


def _probability(r: Any) -> str | None:
    p = np.asarray(getattr(r, "probability", np.nan), dtype=float)
    if not _honest(r) and not (np.isfinite(p).all() and (p >= 0).all() and (p <= 1).all()):
        return f"probability {p!r} outside [0, 1] with status ok"
    return None


def _speed_limit_reference(r: Any) -> str | None:
    """unit metrics of the worst heads against the 40-digit impact reference."""
    keys = {"a_h": "peak_head_acceleration", "eps": "max_compression", "f_c": "peak_force"}
    robot = getattr(r, "_robot", None)
    if robot is None or type(robot).__name__ != "ContactDynamics":
        return None
    for crit, unit in r.unit_metric.items():
        key = next((v for k, v in keys.items() if crit.startswith(k)), None)
        head = r.worst_heads.get(crit)
        if key is None or head is None:
            continue
        p = [robot.mass, robot.damping, robot.stiffness, r._foam.stiffness, r._foam.damping,
             head.mass, head.damping, head.stiffness]  # fmt: skip
        ref = impact_reference(p, 1.0)
        if (
            ref is not None
            and math.isfinite(unit)
            and not math.isclose(unit, ref[key], rel_tol=1e-5)
        ):
            return (
                f"{crit}: metric per unit closing speed {unit:.8g}, 40-digit evaluation "
                f"{ref[key]:.8g} (status {r.status}, max_speed {r.max_speed:.6g})"
            )
    return None


def _speed_limit(robot: Any, foam: Any, **kw: Any) -> Any:
    """speed_limit, keeping the robot and foam on the answer for the reference oracle."""
    from designlab.codesign import speed_limit

    out = speed_limit(robot, foam, **kw)
    object.__setattr__(out, "_robot", robot)
    object.__setattr__(out, "_foam", foam)
    return out


def codesign_targets() -> list[Target]:
    """The braking functions, speed limits, injury probabilities and the design space."""
    import designlab.codesign as cd
    import designlab.impact as im

    braking = {"human_speed": Val(1.0), "reaction_time": Val(0.1), "deceleration": Val(5.0),
               "detection_distance": Val(0.5)}  # fmt: skip
    robot_foam = {
        "robot": Obj(im.ContactDynamics, BASE_ROBOT, ladder=True),
        "foam": Obj(im.Foam, BASE_FOAM, ladder=True),
    }
    limit_nan = ("joint_speed", "worst_lever_arm")
    return [
        Target("codesign", "dl.codesign.stopping_distance", cd.stopping_distance,
               {"speed": Val(1.0), "reaction_time": Val(0.1), "deceleration": Val(5.0)},
               ("speed", "reaction_time", "deceleration"), given=_stopping_given),
        Target("codesign", "dl.codesign.contact_speed", cd.contact_speed,
               {"speed": Val(1.0), **braking}, ("speed", *braking), given=_contact_given),
        Target("codesign", "dl.codesign.max_robot_speed", cd.max_robot_speed,
               {"contact_limit": Val(1.5), **braking}, ("contact_limit",),
               given=_max_speed_given),
        Target("codesign", "dl.codesign.speed_limit", _speed_limit,
               {**robot_foam, "case": Obj(cd.SafetyCase, BASE_CASE, only=tuple(BASE_CASE)),
                "refine": Val(True, attacks=list(FLAG_ATTACKS))},
               ("robot", "foam"),
               all_of(finite_oracle(nonneg=("max_speed", "closing_speed"),
                                    allow_nan=limit_nan), _speed_limit_reference)),
        Target("codesign", "dl.codesign.injury_probability", cd.injury_probability,
               {**robot_foam, "closing_speed": Val(1.0), "samples": Val(1000),
                "method": Val("importance"), "confidence": Val(0.95), "seed": Val(0)},
               ("robot", "foam", "closing_speed"), _probability),
        Target("codesign", "dl.codesign.fragility_curve", cd.fragility_curve,
               {**robot_foam, "speeds": Val([0.5, 1.0], attacks=ARRAY_ATTACKS),
                "samples": Val(1000), "confidence": Val(0.95)},
               ("robot", "foam", "speeds"), _probability, attack=("speeds", "samples",
                                                                   "confidence")),
        Target("codesign", "dl.codesign.speed_limit_map", cd.speed_limit_map,
               {"robot": Obj(im.ContactDynamics, BASE_ROBOT),
                "K_c": Val([2e4, 4e4], attacks=ARRAY_ATTACKS),
                "C_c": Val([50.0, 100.0], attacks=ARRAY_ATTACKS), "linear_depth": Val(0.02)},
               ("robot",), finite_oracle(nonneg=("max_speed", "closing_speed"),
                                         allow_nan=("max_speed", "closing_speed",
                                                    "grid_closing_speed")),
               attack=("K_c", "C_c", "linear_depth")),
        Target("codesign", "dl.codesign.DesignSpace", cd.DesignSpace, {}, ()),
        Target("codesign", "dl.codesign.RobotDescription", cd.RobotDescription, {}, ()),
        Target("codesign", "dl.codesign.assessment.iso_comparison", iso_comparison,
               {"robot": Obj(cd.RobotDescription, {"name": "robot"}),
                "foam": Obj(im.Foam, BASE_FOAM), "human_speed": Val(1.0)},
               ("robot", "foam"),
               all_of(finite_oracle(nonneg=ISO_COLUMNS, allow_nan=("zeng_robot_speed_m_per_s",)),
                      _iso_closed_form)),
    ]  # fmt: skip


#: Columns of :func:`designlab.codesign.assessment.iso_comparison` that are never negative.
ISO_COLUMNS = ("share", "m_H_kg", "k_N_per_m", "F_T_N", "mu_kg", "iso_closing_speed_m_per_s",
               "iso_robot_speed_m_per_s", "zeng_robot_speed_m_per_s")  # fmt: skip


def iso_comparison(robot: Any, foam: Any, human_speed: Any = 1.0) -> Any:
    """iso_comparison (imported on first use, like the other targets' functions)."""
    from designlab.codesign.assessment import iso_comparison as compare

    return compare(robot, foam, human_speed)


def _iso_closed_form(r: Any) -> str | None:
    """Each region's permissible speed is F_T / sqrt(mu k) (ISO/TS 15066 Annex A.3) with
    mu = (1/m_H + 1/m_R)^-1 <= m_H, and the shares a probability split."""
    if not hasattr(r, "columns"):
        return f"answer {type(r).__name__} is no table"
    want = r["F_T_N"] / np.sqrt(r["mu_kg"] * r["k_N_per_m"])
    if not np.allclose(r["iso_closing_speed_m_per_s"], want, rtol=1e-12, atol=0):
        return "iso_closing_speed_m_per_s is not F_T / sqrt(mu k)"
    if (r["mu_kg"] > r["m_H_kg"] * (1 + 1e-12)).any() or r["share"].sum() > 1 + 1e-9:
        return "mu above the body region's mass, or shares summing above 1"
    return None


#: Attacks on an argument that is an array of values.
ARRAY_ATTACKS: list[tuple[str, Any]] = [
    ("[nan]", [math.nan, 1.0]),
    ("[inf]", [math.inf, 1.0]),
    ("[-1]", [-1.0, 1.0]),
    ("[0]", [0.0, 1.0]),
    ("[1e300]", [1e300, 1.0]),
    ("[]", []),
    ("text", "ab"),
    ("None", None),
    ("nested", [[1.0, 2.0], [3.0, 4.0]]),
    ("complex", [1 + 1j, 1.0]),
    ("10**6 values", [1.0] * 10**6),
    ("bools", [True, False]),
]


def codesign_cases() -> list[Case]:
    import designlab.codesign as cd
    import designlab.impact as im
    from designlab.params import params_of

    out = []
    for t in codesign_targets():
        if t.label.endswith("DesignSpace"):
            t.args = {n: Val(d.default, decl=d) for n, d in params_of(cd.DesignSpace).items()}
        if t.label.endswith("RobotDescription"):
            t.args = {n: Val("robot" if n == "name" else d.default, decl=d)
                      for n, d in params_of(cd.RobotDescription).items()}  # fmt: skip
            t.args["contact"] = Val(im.MANIPULATOR_1, decl=UNDECLARED, attacks=[
                ("None", None), ("text", "link"), ("a foam", im.FOAM_1),
                ("heavier than the robot", im.ContactDynamics(mass=50.0, stiffness=20e3,
                                                              damping=250.0)),
            ])  # fmt: skip
        out += target_cases(t, [cd.parameters, im.parameters])
    out.append(simple_case("codesign", "dl.codesign.DesignSpace min above max",
                           _eval("dl.codesign.DesignSpace(stiffness_min=8e4, stiffness_max=5e3)"),
                           "dl.codesign.DesignSpace(stiffness_min=8e4, stiffness_max=5e3)",
                           names=("stiffness_m",), expect="refuse"))  # fmt: skip
    return out


def _codesign_warmup() -> None:
    import designlab as dl

    _impact_warmup()
    dl.codesign.speed_limit(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1)
    dl.codesign.injury_probability(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, 1.0, samples=1000)


# -------------------------------------------------------------- domain: navigation

#: Attacks on a point (x, y).
PAIR_ATTACKS: list[tuple[str, Any]] = [
    ("(nan, 0)", (math.nan, 0.0)),
    ("(inf, 0)", (math.inf, 0.0)),
    ("(1e300, 0)", (1e300, 0.0)),
    ("(1e6, 0)", (1e6, 0.0)),
    ("1 value", (1.0,)),
    ("3 values", (1.0, 0.0, 0.0)),
    ("text", "ab"),
    ("None", None),
    ("complex", (1 + 1j, 0.0)),
    ("bools", (True, False)),
]


def _arrival_given(r: Any, a: dict[str, Any]) -> str | None:
    """An arrival no faster than the robot can drive, and never at t = 0 from afar."""
    sc = a.get("scenario")
    t = getattr(r, "arrival_time", math.nan)
    if sc is None or not hasattr(sc, "start") or t is None or not math.isfinite(t):
        return None
    tol = a.get("arrival_tolerance", 0.15)
    tol = tol if isinstance(tol, (int, float)) and math.isfinite(tol) else 0.15
    dist = math.dist(sc.start, sc.goal) - tol
    fastest = dist / sc.robot.max_speed - 2 * sc.sample_time
    if dist > 0 and t < fastest:
        return (f"arrives at {t:g} s; the robot needs at least {fastest:g} s to drive "
                f"{dist:g} m at {sc.robot.max_speed:g} m/s")  # fmt: skip
    return None


def _nav_oracle() -> Callable[[Any], str | None]:
    return finite_oracle(
        nonneg=("arrival_time", "min_distance", "energy", "critical_time"),
        allow_nan=("arrival_time", "min_distance", "min_surface_distance", "collision_time",
                   "critical_time", "tie", "period", "power", "criteria", "stability",
                   "obstacle_positions", "energy", "distance", "nearest_distance",
                   "min_wall_distance", "pedestrian_positions", "heading"),
    )  # fmt: skip


def _regions_given(r: Any, a: dict[str, Any]) -> str | None:
    if _honest(r):
        return None
    if not (math.isfinite(r.r2) and math.isfinite(r.r3) and r.r2 >= r.r3 > 0):
        return f"regions r2 = {r.r2!r}, r3 = {r.r3!r} (need r2 >= r3 > 0) with status ok"
    return None


#: The base scenario of the navigation cases, as Python.
SC_TEXT = (
    "dl.navigation.Scenario('hostile', start=(3.9, 0.6), goal=(0.0, 0.6), horizon=15.0, "
    "obstacles=dl.navigation.configuration(1).obstacles)"
)

#: The reproduction of a run with one obstacle.
OBSTACLE_RUN = (
    "dl.navigation.simulate(Scenario('hostile', start=(3.9, 0.6), goal=(0.0, 0.6), "
    "horizon=15.0, obstacles=({obstacle},)), dl.navigation.EXPERIMENT_GAINS)"
)


def _with_obstacle(obstacle: Any, gains: Any = None) -> Any:
    import designlab.navigation as nav

    sc = nav.Scenario("hostile", start=(3.9, 0.6), goal=(0.0, 0.6), obstacles=(obstacle,),
                      horizon=15.0)  # fmt: skip
    return nav.simulate(sc, gains or nav.EXPERIMENT_GAINS)


def _scenario_run(scenario: Any, gains: Any = None) -> Any:
    import designlab.navigation as nav

    return nav.simulate(scenario, gains or nav.EXPERIMENT_GAINS)


def navigation_targets() -> list[Target]:
    import designlab.navigation as nav
    import designlab.navigation.planners as pl

    sc = nav.Scenario("hostile", start=(3.9, 0.6), goal=(0.0, 0.6), horizon=15.0,
                      obstacles=nav.configuration(1).obstacles)  # fmt: skip
    gains = {"k1": 3.0, "b": 0.25, "k3": 20.0, "k5": 17.0}
    pairs = [
        ("nan", (math.nan, 4.0)),
        ("-4", (-4.0, 4.0)),
        ("1e300", (1e300, 4.0)),
        ("text", ("ab", 4.0)),
        ("1 value", (4.0,)),
        ("None", None),
        ("0", (0.0, 4.0)),
    ]
    weights = [
        ("nan", (math.nan, 0.5, 0.5)),
        ("negative", (-1.0, 1.0, 1.0)),
        ("zeros", (0.0, 0.0, 0.0)),
        ("2 values", (0.5, 0.5)),
        ("text", "abc"),
    ]
    choice = list(CHOICE_ATTACKS)
    oracle = _nav_oracle()
    disc = {"name": "d", "radius": 0.1, "r2": 0.8, "r3": 0.4,
            "motion": nav.Stationary((2.45, 0.595))}  # fmt: skip
    rect = {"name": "r", "center": (2.0, 0.6), "length": 0.5, "width": 0.3, "r2": 0.9,
            "r3": 0.5}  # fmt: skip
    small = {
        "vo": (pl.VOSettings, {"horizon": 2.0}),
        "errt": (pl.ERRTSettings, {}),
        "field_dstar": (pl.FieldDStarSettings, {"cell": 0.5, "margin": 0.5}),  # 1 s, not 15
    }
    out = [
        Target("navigation", "dl.navigation.simulate", nav.simulate,
               {"scenario": Val(sc, text=SC_TEXT), "gains": Obj(nav.VFFGains, gains),
                "arrival_tolerance": Val(0.15), "dynamics_step": Val(0.001),
                "cbf_gains": Val((4.0, 4.0), attacks=pairs), "weights": Val(
                    (1 / 3, 1 / 3, 1 / 3), attacks=weights),
                "method": Val("vff", attacks=choice), "stabilising": Val(
                    "lyapunov", attacks=choice), "tie_side": Val("+y", attacks=choice)},
               ("scenario", "gains"), oracle, given=_arrival_given,
               attack=("gains", "arrival_tolerance", "dynamics_step", "weights", "method",
                       "stabilising", "tie_side")),
        Target("navigation", "dl.navigation.simulate", nav.simulate,
               {"scenario": Val(sc, text=SC_TEXT), "gains": Val(None), "method": Val("cbf"),
                "cbf_gains": Val((4.0, 4.0), attacks=pairs)}, ("scenario",), oracle,
               attack=("cbf_gains",), tag="[cbf]"),
        Target("navigation", "dl.navigation.simulate", _scenario_run,
               {"scenario": Obj(nav.Scenario, {"name": "s", "start": (3.9, 0.6),
                                               "goal": (0.0, 0.6), "horizon": 15.0})},
               ("scenario",), oracle,
               template="dl.navigation.simulate({scenario}, dl.navigation.EXPERIMENT_GAINS)",
               tag="[Scenario]"),
        Target("navigation", "dl.navigation.simulate", _with_obstacle,
               {"obstacle": Obj(nav.Disc, disc)}, ("obstacle",), oracle, tag="[disc]",
               template=OBSTACLE_RUN),
        Target("navigation", "dl.navigation.simulate", _with_obstacle,
               {"obstacle": Obj(nav.Rectangle, rect)}, ("obstacle",), oracle, tag="[rect]",
               template=OBSTACLE_RUN),
        Target("navigation", "dl.navigation.region_sizes", nav.region_sizes,
               {"obstacle": Obj(nav.Human, {}), "robot": Obj(nav.HolonomicRobot, {}),
                "sample_time": Val(0.06), "critical_radius": Val(None),
                "sidestep_time": Val(None), "turn_time": Val(None), "active_radius": Val(None)},
               ("obstacle", "robot", "sample_time"), finite_oracle(), given=_regions_given),
        Target("navigation", "dl.navigation.region_sizes", nav.region_sizes,
               {"obstacle": Obj(nav.RectangularObstacle, {}),
                "robot": Obj(nav.NonholonomicRobot, {}), "sample_time": Val(0.06)},
               ("obstacle", "robot", "sample_time"), finite_oracle(), given=_regions_given,
               tag="[rect,nonholonomic]"),
    ]  # fmt: skip
    for method, (cls, fields) in small.items():
        out.append(
            Target(
                "navigation",
                "dl.navigation.planners.simulate_planner",
                pl.simulate_planner,
                {
                    "scenario": Val(sc, text=SC_TEXT),
                    "method": Val(method),
                    "settings": Obj(cls, fields),
                    "arrival_tolerance": Val(0.15),
                },
                ("scenario", "method"),
                oracle,
                given=_arrival_given,
                attack=("settings", "arrival_tolerance"),
                tag=f"[{method}]",
            )
        )
    return out


#: Attacks on an (n, 4) array of VFF gain sets.
GAIN_SET_ATTACKS: list[tuple[str, Any]] = [
    ("[[nan, ...]]", [[math.nan, 0.25, 20.0, 17.0]]), ("[[-1, ...]]", [[-1.0, 0.25, 20.0, 17.0]]),
    ("[[1e300, ...]]", [[1e300, 0.25, 20.0, 17.0]]), ("[]", []),
    ("flat 4", [3.0, 0.25, 20.0, 17.0]),
    ("3 columns", [[3.0, 0.25, 20.0]]), ("text", "ab"), ("None", None),
    ("10**5 sets", [[3.0, 0.25, 20.0, 17.0]] * 10**5),
]  # fmt: skip


def _walker(walk: Any) -> Any:
    """A run with a person walking head-on toward the robot (``walk`` is attacked)."""
    import designlab.navigation as nav

    human = nav.Disc("h", 0.2, 2.1, 0.8, walk)
    sc = nav.Scenario("hostile", start=(3.9, 0.6), goal=(0.0, 0.6), horizon=15.0,
                      obstacles=(human,))  # fmt: skip
    return nav.simulate(sc, nav.EXPERIMENT_GAINS)


def _criteria_given(r: Any, a: dict[str, Any]) -> str | None:
    h = [r.H_T, r.H_D, r.H_E, r.H]
    if not all(isinstance(x, float) and math.isfinite(x) for x in h) and not _honest(r):
        return f"criteria H_T, H_D, H_E, H = {h} (finite numbers) with status ok"
    return None


def navigation_more_targets() -> list[Target]:
    """Batches, sensor noise, a walking person and the criteria of Sec. 6.3."""
    import designlab.navigation as nav

    sc = nav.Scenario("hostile", start=(3.9, 0.6), goal=(0.0, 0.6), horizon=15.0,
                      obstacles=nav.configuration(1).obstacles)  # fmt: skip
    oracle = _nav_oracle()
    walk = {"start": (0.5, 0.6), "end": (3.5, 0.6), "speed": 1.0}
    return [
        Target("navigation", "dl.navigation.simulate_batch", nav.simulate_batch,
               {"scenarios": Val([sc], text=f"[{SC_TEXT}]"),
                "gains": Val([[3.0, 0.25, 20.0, 17.0]], attacks=GAIN_SET_ATTACKS)},
               ("scenarios", "gains"), oracle, attack=("gains",)),
        Target("navigation", "dl.navigation.simulate", nav.simulate,
               {"scenario": Val(sc, text=SC_TEXT),
                "gains": Val(nav.EXPERIMENT_GAINS, text="EXPERIMENT_GAINS"),
                "noise": Obj(nav.SensorNoise, {})}, ("scenario", "gains"), oracle,
               attack=("noise",), tag="[noise]"),
        Target("navigation", "dl.navigation.simulate", _walker, {"walk": Obj(nav.Walk, walk)},
               (), oracle, tag="[walker]",
               template="dl.navigation.simulate(Scenario('hostile', start=(3.9, 0.6), "
                        "goal=(0.0, 0.6), horizon=15.0, obstacles=(Disc('h', 0.2, 2.1, 0.8, "
                        "{walk}),)), EXPERIMENT_GAINS)"),
        Target("navigation", "dl.navigation.criteria", nav.criteria,
               {"arrival_time": Val(10.0), "nominal_arrival_time": Val(8.0), "energy": Val(5.0),
                "nominal_energy": Val(4.0), "surface_clearance": Val({"a": 0.5}, attacks=[
                    ("nan", {"a": math.nan}), ("-1", {"a": -1.0}), ("{}", {}), ("text", "a")]),
                "nominal_clearance": Val({"a": 0.4}, attacks=[
                    ("0", {"a": 0.0}), ("other key", {"b": 0.4})])},
               (), finite_oracle(), given=_criteria_given),
    ]  # fmt: skip


def _pair_cases() -> list[Case]:
    """start and goal of a scenario, the position of a stationary disc."""
    import designlab.navigation as nav

    out = []
    for key in ("start", "goal"):
        for label, v in PAIR_ATTACKS:
            kw = {"start": (3.9, 0.6), "goal": (0.0, 0.6), key: v}
            repro = (
                f"dl.navigation.simulate(dl.navigation.Scenario('s', start={fmt(kw['start'])}"
                f", goal={fmt(kw['goal'])}), dl.navigation.EXPERIMENT_GAINS)"
            )
            out.append(
                simple_case(
                    "navigation",
                    f"Scenario {key}={label}",
                    _eval(repro),
                    repro,
                    names=(key,),
                    value=v,
                    oracle=_nav_oracle(),
                    expect="either" if "1e" in label else "refuse",
                )
            )
    del nav
    return out


def navigation_extra_cases() -> list[Case]:
    """Sizes nobody bounded, and the reported crowd and planner cases."""
    many = (
        "dl.navigation.simulate(dl.navigation.Scenario('s', start=(3.9, 0.6), "
        "goal=(0.0, 0.6), obstacles=tuple(dl.navigation.Disc(f'd{i}', 0.05, 0.3, 0.2, "
        "dl.navigation.Stationary((i % 50 * 0.1 - 10, i // 50 * 0.1 + 5))) "
        "for i in range(2000))), dl.navigation.EXPERIMENT_GAINS)"
    )
    crowd = "dl.navigation.crowd('corridor_counterflow', 4, length=8.0, horizon=0.5{})"
    run = "dl.navigation.simulate(" + crowd + ", dl.navigation.EXPERIMENT_GAINS{})"
    rows = [
        ("Scenario with 2000 discs", many, ("obstacles",), "refuse"),
        ("crowd neighbours=1", run.format(", neighbours=1", ""), ("neighbours",), "either"),
        ("crowd cbf_gains=nan", run.format("", ", method='cbf', cbf_gains=(float('nan'), 4.0)"),
         ("cbf_gains",), "refuse"),
        ("crowd cbf_gains=-4", run.format("", ", method='cbf', cbf_gains=(-4.0, 4.0)"),
         ("cbf_gains",), "refuse"),
        ("crowd cbf_gains=1e300", run.format("", ", method='cbf', cbf_gains=(1e300, 4.0)"),
         ("cbf_gains",), "refuse"),
        ("crowd cbf_gains=text", run.format("", ", method='cbf', cbf_gains=('ab', 4.0)"),
         ("cbf_gains",), "refuse"),
        ("crowd lenght typo", crowd.format(", lenght=8"), ("lenght",), "refuse"),
        ("crowd pedestrians=10**6", crowd.format("").replace(" 4,", " 10**6,"),
         ("pedestrians",), "refuse"),
        ("crowd density=nan", "dl.navigation.crowd('corridor_counterflow', density=float('nan'))",
         ("density",), "refuse"),
        ("Rectangle.from_corners of 3 points",
         "dl.navigation.Rectangle.from_corners('r', [(0, 0), (1, 0), (0.3, 2)], r2=1, r3=0.5)",
         ("corners",), "refuse"),
        ("field_dstar cell=0.0101",
         "dl.navigation.planners.simulate_planner(dl.navigation.configuration(1), 'field_dstar', "
         "dl.navigation.planners.FieldDStarSettings(cell=0.0101))", ("cell",), "either"),
    ]  # fmt: skip
    return [simple_case("navigation", n, _eval(e), e, names=k, expect=x, oracle=_nav_oracle())
            for n, e, k, x in rows]  # fmt: skip


def navigation_cases() -> list[Case]:
    import designlab.navigation as nav
    import designlab.navigation.planners as pl

    mods = [nav.parameters, pl.parameters]
    targets = navigation_targets() + navigation_more_targets()
    out = [c for t in targets for c in target_cases(t, mods)]
    return (out + _pair_cases() + navigation_extra_cases() + crowd_constructor_cases()
            + crowd_baseline_cases())  # fmt: skip


def crowd_baseline_cases() -> list[Case]:
    """Every declared field of the field's crowd baselines' settings (ORCA through RVO2, the
    social-force robot), constructed (the declarations refuse; a run is slow), and a short
    crowd run of each with its defaults."""
    from designlab.navigation.methods.orca import ORCASettings
    from designlab.navigation.methods.social_force import SocialForceSettings
    from designlab.params import params_of

    out: list[Case] = []
    for cls, path in ((ORCASettings, "orca"), (SocialForceSettings, "social_force")):
        decls = params_of(cls)
        args = {n: Val(getattr(cls(), n), decl=d) for n, d in decls.items()}
        t = Target("navigation", f"dl.navigation.methods.{path}.{cls.__name__}", cls, args)
        out += target_cases(t)
    crowd = "dl.navigation.crowd('corridor_counterflow', 4, length=8.0, horizon=0.5)"
    for m in ("orca", "social_force"):
        e = f"dl.navigation.simulate({crowd}, method={m!r})"
        out.append(simple_case("navigation", f"crowd run {m}", _eval(e), e, names=("method",),
                               expect="accept", oracle=_nav_oracle()))  # fmt: skip
    return out


def crowd_constructor_cases() -> list[Case]:
    """Every declared field of a crowd, through dl.navigation.crowd (no run: they are slow)."""
    import designlab.navigation as nav

    t = Target("navigation", "dl.navigation.crowd", nav.crowd,
               {"layout": Val("corridor_counterflow", attacks=list(CHOICE_ATTACKS)),
                "pedestrians": Val(4), "length": Val(8.0), "width": Val(4.0),
                "seed": Val(0), "model": Val("collision_free_speed", attacks=list(CHOICE_ATTACKS)),
                "density": Val(None)}, ("layout", "pedestrians"), None)  # fmt: skip
    from designlab.params import params_of

    decls = params_of(nav.CrowdScenario)
    for name, spec in t.args.items():
        if isinstance(spec, Val) and spec.decl is None and name in decls:
            optional = name in ("pedestrians", "density")  # one of the two, the other None
            spec.decl = dataclasses.replace(decls[name], optional=optional)
    return target_cases(t)


def _navigation_warmup() -> None:
    import designlab.navigation as nav
    import designlab.navigation.planners as pl
    from designlab.navigation.planners import simulate_planner

    sc = nav.configuration(1)
    nav.simulate(sc, nav.EXPERIMENT_GAINS)
    nav.simulate(sc, method="cbf")
    simulate_planner(sc, "vo")
    simulate_planner(sc, "errt")
    simulate_planner(sc, "field_dstar", pl.FieldDStarSettings(cell=0.5, margin=0.5))
    nav.simulate(nav.crowd("corridor_counterflow", 4, length=8.0, horizon=0.5),
                 nav.EXPERIMENT_GAINS)  # fmt: skip


# --------------------------------------------------------------- domain: following


def _follow_oracle() -> Callable[[Any], str | None]:
    return finite_oracle(nonneg=("tether_length",),
                         allow_nan=("tether_angle", "beta_change", "tracked_xy",
                                    "tracked_s_leader", "d_col", "readings", "measured_error",
                                    "sensor_pose", "target_change",
                                    # NaN by definition (accompanying/metrics.py):
                                    "settling_time", "overshoot"))  # fmt: skip


def _snag_gap_given(r: Any, a: dict[str, Any]) -> str | None:
    if not (isinstance(r, float) and math.isfinite(r) and r > 0):
        return f"first snag gap {r!r} (a gap is a positive length)"
    return None


def _limits_given(r: Any, a: dict[str, Any]) -> str | None:
    bad = {k: v for k, v in dict(r).items() if not (math.isfinite(v) and v > 0)}
    return f"gap limits {bad} (positive lengths)" if bad else None


def _path_given(r: Any, a: dict[str, Any]) -> str | None:
    xy = np.asarray(getattr(r, "xy", getattr(r, "points", np.zeros((2, 2)))), dtype=float)
    if xy.size == 0 or not np.isfinite(xy).all():
        return f"a leader path of {xy.size // 2} points, not all finite"
    return None


def following_targets() -> list[Target]:
    import designlab.following as fo
    import designlab.following.tether as te
    import designlab.following.tether.parameters as tp
    from designlab.following.tether import snag

    oracle = _follow_oracle()
    fol_args = {"controller": Obj(te.PseudoJoystick, {}), "path": Val("slalom"),
                "speed": Val(0.5), "robot": Obj(te.FollowerRobot, {}),
                "duration": Val(8.0, decl=dataclasses.replace(tp.DURATION, optional=True)),
                "settle_time": Val(5.0), "lead_in": Val(0.0), "seed": Val(0)}  # fmt: skip
    pid = {"kp": 2.0}
    return [
        Target("following", "dl.following.simulate", fo.simulate, fol_args,
               ("controller", "path"), oracle),
        Target("following", "dl.following.simulate", fo.simulate,
               {**fol_args, "controller": Obj(te.FollowTheLeader, {})}, ("controller", "path"),
               oracle, attack=("controller",), tag="[FollowTheLeader]"),
        Target("following", "dl.following.simulate", fo.simulate,
               {**fol_args, "controller": Obj(te.SideJoystick, {})}, ("controller", "path"),
               oracle, attack=("controller",), tag="[SideJoystick]"),
        Target("following", "dl.following.simulate", _brake_run,
               {"mode": Val(te.SideJoystick(), text="SideJoystick()"), "engage_margin": Val(0.02),
                "release_margin": Val(0.05)}, (), oracle, tag="[BrakeMode]",
               template="dl.following.simulate(BrakeMode(SideJoystick(), engage_margin="
                        "{engage_margin}, release_margin={release_margin}), 'slalom', 0.5, "
                        "duration=8.0)"),
        Target("following", "first_snag_gap", snag.first_snag_gap, {"width": Val(1.0)},
               ("width",), given=_snag_gap_given),
        Target("following", "thesis_gap_limits", snag.thesis_gap_limits,
               {"width": Val(1.0), "vehicle_length": Val(0.67)}, ("width", "vehicle_length"),
               given=_limits_given),
        Target("following", "simulate_snag", snag.simulate_snag,
               {"scenario": Obj(snag.SnagScenario, {"gap": 2.0})}, ("scenario",), oracle),
        Target("following", "dl.following.accompany", fo.accompany,
               {"task": Val(fo.walking_task("forward"), text="walking_task('forward')"),
                "controller": Obj(fo.UserFramePID, pid),
                "platform": Obj(fo.MecanumPlatform, {}), "sensor": Obj(fo.StringPotSensor, {}),
                "initial_offset": Val((0.0, 0.0), attacks=PAIR_ATTACKS), "seed": Val(0),
                "settle_band": Val(0.02)}, ("task", "controller"), oracle,
               attack=("controller", "platform", "sensor", "initial_offset", "settle_band")),
        Target("following", "dl.following.walking_task", fo.walking_task,
               {"name": Val("forward", attacks=list(CHOICE_ATTACKS)), "speed": Val(None),
                "yaw_rate": Val(0.7854), "distance": Val(None), "turn_angle": Val(1.5708),
                "radius": Val(0.9), "ramp_time": Val(0.6), "pause": Val(0.5),
                "settle_time": Val(10.0), "step_frequency": Val(1.8)}, ("name",), None),
        Target("following", "dl.following.tether.circle", te.circle,
               {"radius": Val(2.0, decl=UNDECLARED), "turns": Val(1.0, decl=UNDECLARED),
                "points_per_turn": Val(720, decl=UNDECLARED)}, (), given=_path_given),
        Target("following", "dl.following.tether.corridor_corner", te.corridor_corner,
               {"width": Val(1.0, decl=UNDECLARED), "leg": Val(3.0, decl=UNDECLARED),
                "radius": Val(None, decl=UNDECLARED)}, (), given=_path_given),
    ]  # fmt: skip


def _brake_run(mode: Any, engage_margin: Any, release_margin: Any) -> Any:
    import designlab.following as fo
    import designlab.following.tether as te

    brake = te.BrakeMode(mode, engage_margin=engage_margin, release_margin=release_margin)
    return fo.simulate(brake, "slalom", 0.5, duration=8.0)


def following_extra_cases() -> list[Case]:
    """The reported tether cases and siblings."""
    rows = [
        ("brake_timeline desired_length=nan",
         "dl.following.tether.brake_timeline(np.ones(10), float('nan'), 0.02, 0.05)",
         ("desired_length",), "refuse"),
        ("brake_timeline engage above release",
         "dl.following.tether.brake_timeline(np.ones(10), 1.0, 0.5, 0.05)",
         ("engage_margin", "release_margin"), "either"),
        ("simulate path dict typo", "dl.following.simulate(dl.following.tether.PseudoJoystick(),"
         " {'type': 'slalom', 'spcing': 1.0}, 0.5, duration=5.0)", ("spcing",), "refuse"),
        ("simulate path unknown", "dl.following.simulate(dl.following.tether.PseudoJoystick(),"
         " 'nope', 0.5, duration=5.0)", ("nope", "path"), "refuse"),
        ("make_path 10**7 points", "dl.following.make_path({'type': 'circle', "
         "'points_per_turn': 10**7, 'turns': 100})", ("points_per_turn", "turns"), "refuse"),
        ("normal_path_deviation empty", "dl.following.tether.normal_path_deviation("
         "np.zeros((0, 2)), np.zeros((0, 2)))", ("leader_xy", "robot_xy"), "refuse"),
        ("normal_path_deviation nan", "dl.following.tether.normal_path_deviation("
         "np.full((5, 2), np.nan), np.zeros((5, 2)))", ("leader_xy",), "refuse"),
        ("from_array 1 point", "dl.following.tether.from_array([[0.0, 0.0]])", ("xy", "points"),
         "refuse"),
    ]  # fmt: skip
    return [simple_case("following", n, _eval(e), e, names=k, expect=x, oracle=_follow_oracle())
            for n, e, k, x in rows]  # fmt: skip


def following_cases() -> list[Case]:
    import designlab.following.accompanying.parameters as ap
    import designlab.following.tether.parameters as tp

    out = [c for t in following_targets() for c in target_cases(t, [tp, ap])]
    return out + following_extra_cases()


def _following_warmup() -> None:
    import designlab.following as fo
    import designlab.following.tether as te
    from designlab.following.tether import snag

    fo.simulate(te.PseudoJoystick(), "slalom", 0.5, duration=8.0)
    fo.simulate(te.FollowTheLeader(), "slalom", 0.5, duration=8.0)
    _brake_run(te.SideJoystick(), 0.02, 0.05)
    fo.accompany(fo.walking_task("forward"))
    snag.simulate_snag(snag.SnagScenario(gap=2.0))


# --------------------------------------------------------------------- domain: yaml

#: One small valid study of each kind (as the fuzz test of the studies,
#: tests/study/test_fuzz_studies.py): the carriers of the hostile values.
STUDY_BASE: dict[str, dict[str, Any]] = {
    "impact_cases": {"cases": [{"robot": "MANIPULATOR_1", "foam": "FOAM_1", "head": "TEST_HEAD",
                                "impact_velocity": 0.4}]},
    "impact_sweep": {"base": {"robot": "MANIPULATOR_1", "foam": "FOAM_1", "head": "HEAD_MIN",
                              "impact_velocity": 1.25},
                     "sweep": {"method": "grid",
                               "parameters": {"foam.stiffness": {"values": [2.0e4, 4.0e4]}}}},
    "foam_envelope_sweep": {"base": {"robot": "MANIPULATOR_1", "foam": "FOAM_1"},
                      "damping": {"low": 0, "high": 200, "num": 5}},
    "foam_design": {"robots": ["MANIPULATOR_1"], "foams": ["FOAM_1"],
                    "damping": {"low": 20, "high": 100, "num": 3}, "optimal": False,
                    "worst_case_check": False},
    "joint_reduction": {"joints": [{"name": "geared", "inertia": 0.059, "k_mech": 2000,
                                    "c_mech": 2.0, "k_cont": 1500, "c_cont": 30,
                                    "lever_arm": 0.2}],
                        "ratios": {"low": 0.1, "high": 100, "num": 4}},
    "zeng_ch3_claims": {"readings": [{"name": "b", "impact_velocity": 0.25,
                                      "feedforward": False}], "speed_ratios": [1.0]},
    "tether_comparison": {"paths": [{"type": "slalom"}],
                            "controllers": [{"type": "PseudoJoystick"}],
                            "desired_lengths": [0.6]},
    "tether_tuning": {"laws": ["FollowTheLeader"], "paths": [{"type": "slalom"}],
                        "validation_paths": [{"type": "square_s"}]},
    "tether_sweep": {"base": {"controller": {"type": "FollowTheLeader"},
                                "path": {"type": "slalom"}},
                       "sweep": {"method": "grid",
                                 "parameters": {"controller.lookahead": {"values": [0.1, 0.5]}}}},
    "navigation_sweep": {"base": {"gains": {"k1": 4.3, "b": 0.68, "k3": 20.3, "k5": 240.7},
                           "scenarios": [[1, 6]], "stabilising": "off"},
                  "sweep": {"method": "grid",
                            "parameters": {"gains.k1": {"values": [3.0, 4.3]}}}},
    "navigation_gains": {"modes": ["off"], "max_evaluations": 32},
    "navigation_account": {"tables": ["6.2"], "methods": ["New VFF*"]},
    "navigation_planners": {"scenarios": [{"configuration": 1}], "mirror": False,
                            "planners": [{"method": "vo", "settings": {"horizon": 2.0}}],
                            "methods": []},
    "navigation_regions": {"robot": {"type": "holonomic", "max_speed": 1.0},
                           "obstacles": [{"name": "h", "type": "human", "max_speed": 1.4},
                                         {"name": "b", "type": "rectangle", "offset": 0.3,
                                          "critical_radius": 0.5, "active_radius": 1.0}]},
    "navigation_scenarios": {"scenarios": [{"name": "s", "start": [3.0, 0.0],
                                            "goal": [0.0, 0.0], "horizon": 8,
                                            "obstacles": [{"kind": "disc", "name": "d",
                                                           "radius": 0.1,
                                                           "position": [1.5, 0.05],
                                                           "r2": 0.8, "r3": 0.4}]}],
                             "methods": [{"label": "vff", "method": "vff",
                                          "gains": {"k1": 3, "b": 0.25, "k3": 20, "k5": 17}}]},
    "accompanying": {"tasks": ["forward"],
                     "tuning": {"tune_on": ["forward"], "derivative_free": False}},
    "tether_stability": {"controllers": [{"type": "PseudoJoystick"}],
                         "lengths": {"low": 0.5, "high": 2.0, "num": 2}, "angles": 3,
                         "max_time": 5},
    "tether_step_size": {"paths": [{"type": "square_s"}], "min_steps": [0.01, 0.4]},
    "tether_snagging": {"gaps": {"low": 1.0, "high": 2.5, "num": 3}, "detail_gaps": [2.5]},
    "tether_modes": {"paths": [{"type": "straight_line", "length": 3.0}],
                     "modes": ["SideJoystick"], "side_offsets": [0.5],
                     "brake_laws": ["PseudoJoystick"]},
    "codesign": {"scenarios": [{"configuration": 2}],
                 "front": {"objectives": ["arrival_time", "foam_thickness"], "population": 4,
                           "generations": 1},
                 "speed_map": {"stiffness": {"num": 3}, "damping": {"num": 3}},
                 "risk": {"foams": ["FOAM_1"], "speeds": {"num": 3}, "samples": 1000}},
    "navigation_crowds": {"scenarios": ["corridor_counterflow"], "densities": [0.1],
                          "seeds": [0], "methods": [{"method": "vff"}],
                          "models": ["collision_free_speed"],
                          "crowd": {"length": 8.0, "horizon": 0.5}, "animations": False},
}  # fmt: skip

#: Kinds whose small study runs (and writes its report) within a few seconds: an accepted
#: hostile value in them is run through the report writer; the others are validated only.
STUDY_RUN = {"impact_cases", "impact_sweep", "foam_envelope_sweep", "foam_design",
             "navigation_sweep", "navigation_planners", "navigation_regions",
             "navigation_scenarios", "tether_step_size", "tether_snagging", "tether_modes",
             "tether_stability", "navigation_crowds", "navigation_account",
             "codesign"}  # fmt: skip

#: Leaves not attacked: flags that only switch on heavy but valid output.
STUDY_SKIP = {"navigation_crowds": ("animations",)}

#: Result columns that are NaN by definition in some valid runs (docs of the result): the
#: shares of the Lyapunov audit are NaN without a sample in an active region
#: (navigation/lyapunov.py).
STUDY_NAN = ("lyapunov_share", "share_satisfied", "share_satisfied_hold", "share_V_rose_over_hold")

#: The values put in place of a leaf of a study.
YAML_ATTACKS: list[tuple[str, Any]] = [
    ("nan", math.nan), ("inf", math.inf), ("-1", -1), ("0", 0), ("1e300", 1e300),
    ("1e-300", 1e-300), ("text", "abc"), ("bool", True), ("null", None), ("list", [1, 2]),
    ("mapping", {"x": 1}), ("10**12", 10**12), ("[]", []),
]  # fmt: skip


def _leaves(node: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    if isinstance(node, dict):
        return [p for k, v in node.items() for p in _leaves(v, (*path, k))]
    if isinstance(node, list):
        return [p for i, v in enumerate(node) for p in _leaves(v, (*path, i))] + [path]
    return [path]


def _replace(node: Any, path: tuple[Any, ...], value: Any) -> Any:
    if not path:
        return value
    head, rest = path[0], path[1:]
    if isinstance(node, dict):
        return {**node, head: _replace(node[head], rest, value)}
    out = list(node)
    out[head] = _replace(out[head], rest, value)
    return out


def study_text(kind: str, body: dict[str, Any]) -> str:
    """The YAML text of a study of ``kind``."""
    import yaml

    return yaml.safe_dump({"designlab": 1, "kind": kind, "name": f"hostile_{kind}", **body},
                          sort_keys=False)  # fmt: skip


def run_study_text(text: str, run: bool = True) -> Any:
    """What ``designlab run`` does with a study text: validate, run, write the report."""
    from designlab.study import RunContext, parse_study, run_study

    spec = parse_study(text, file="hostile.yaml")
    if not run:
        return None
    from designlab.report import write_report

    result = run_study(spec, RunContext(progress=False))
    with tempfile.TemporaryDirectory(prefix="hostile-") as out:
        write_report(result, Path(out), command="designlab run hostile.yaml", study_text=text)
    return result


def _nonfinite_columns(result: Any) -> set[str]:
    """The non-finite columns of a study's results: its table and its other tables."""
    frame = result.to_frame()
    cols = [c for c in frame.columns if not str(c).startswith(("ref_", "err_", "exp_"))]
    num = frame[cols].select_dtypes("number")
    out = {str(c) for c in num.columns if not np.isfinite(num[c].to_numpy(dtype=float)).all()}
    import pandas as pd

    for name in dir(result):
        if name.startswith("_") or name == "study":
            continue
        try:
            value = getattr(result, name)
            if callable(value) and name.endswith("_frame") and name != "to_frame":
                value = value()  # the kind's other tables (brake_frame, ...)
        except Exception:  # a table that fails is the report writer's business
            continue
        if isinstance(value, pd.DataFrame):
            out |= {f"{name}.{n.split('.', 1)[-1]}" for n, a in numbers_of(value)
                    if not np.isfinite(a).all()}  # fmt: skip
    return out


_BASE_NONFINITE: dict[str, set[str]] = {}


def _study_oracle(kind: str) -> Callable[[Any], str | None]:
    """No non-finite result where the kind's small base study has only finite ones.

    Some kinds' results carry NaN by design (a run that never arrives has no arrival
    time); a column is suspect only where the base study's column is finite.
    """

    def oracle(result: Any) -> str | None:
        if result is None:
            return None
        if kind not in _BASE_NONFINITE:
            base = run_study_text(study_text(kind, STUDY_BASE[kind]))
            _BASE_NONFINITE[kind] = _nonfinite_columns(base)
        new = sorted(c for c in _nonfinite_columns(result) - _BASE_NONFINITE[kind]
                     if c.split(".")[-1] not in STUDY_NAN)  # fmt: skip
        if new and not _honest(result):
            return f"non-finite {', '.join(new[:4])} (finite in the base study) with status ok"
        return None

    return oracle


def yaml_cases() -> list[Case]:
    """Every leaf of every kind's small study, each replaced by each hostile value."""
    out = []
    for kind, body in STUDY_BASE.items():
        text = study_text(kind, body)
        run = kind in STUDY_RUN
        out.append(Case("yaml", f"{kind} (base)", _study_call(text, run), (), NOVALUE,
                        "accept", None, f"kind {kind}, the small base study"))  # fmt: skip
        for path in _leaves(body):
            if not path:
                continue
            keys = [str(p) for p in path if isinstance(p, str)][-2:] or [kind]
            names = tuple({*keys, *(k.rstrip("s") for k in keys)})
            dotted = ".".join(str(p) for p in path)
            if any(k in STUDY_SKIP.get(kind, ()) for k in keys):
                continue
            for label, v in YAML_ATTACKS:
                mutated = study_text(kind, _replace(body, path, v))
                out.append(Case("yaml", f"{kind} {dotted}={label}", _study_call(mutated, run),
                                names, v, "either", _study_oracle(kind),
                                f"kind {kind}, small study with {dotted}: {fmt(v)}"))  # fmt: skip
    return out


def yaml_extra_cases() -> list[Case]:
    """The reported study cases and their siblings: valid files that must run or be refused."""
    nav = STUDY_BASE["navigation_scenarios"]
    bare = {**nav, "scenarios": [{k: v for k, v in nav["scenarios"][0].items()
                                  if k != "obstacles"}]}  # fmt: skip
    crowds = STUDY_BASE["navigation_crowds"]
    masoud = {**crowds, "methods": [{"method": "masoud", "gains": {"direction": -1}}]}
    cbf = {**crowds, "methods": [{"method": "cbf"}]}
    code = STUDY_BASE["codesign"]
    sobol = {**code, "sensitivity": {"samples": 2**20}}
    modes = {**STUDY_BASE["tether_modes"], "brake_walk": 1.0}
    rows = [
        ("tether_modes", "brake_walk 1.0", modes, ("brake_walk",)),
        ("navigation_scenarios", "no obstacles", bare, ("obstacles",)),
        ("navigation_crowds", "masoud gains direction -1", masoud, ("direction",)),
        ("navigation_crowds", "cbf method", cbf, ("cbf",)),
        ("codesign", "sensitivity.samples=2**20", sobol, ("samples",)),
    ]
    out = []
    for kind, label, body, names in rows:
        text = study_text(kind, body)
        out.append(Case("yaml", f"{kind} {label}", _study_call(text, True), names, NOVALUE,
                        "either", _study_oracle(kind), f"kind {kind}: {label}"))  # fmt: skip
    return out


def _study_call(text: str, run: bool) -> Callable[[], Any]:
    return lambda: run_study_text(text, run)


def _yaml_warmup() -> None:
    import designlab.impact
    import designlab.navigation  # noqa: F401
    from designlab.study import parse_study

    parse_study(study_text("impact_cases", STUDY_BASE["impact_cases"]))


# ---------------------------------------------------------------------- domain: cli

#: A small valid study: the carrier of the file-level attacks.
SMALL_STUDY = """designlab: 1
kind: impact_cases
name: hostile_cli
cases:
  - {robot: MANIPULATOR_1, foam: FOAM_1, head: TEST_HEAD, impact_velocity: 0.4}
"""


def _deep(levels: int, mapping: bool) -> str:
    inner = "{a: " * levels + "1" + "}" * levels if mapping else "[" * levels + "1" + "]" * levels
    return SMALL_STUDY.replace("cases:\n", f"extra: {inner}\ncases:\n")


def _file_attacks(tmp: Path) -> list[tuple[str, Any, tuple[str, ...], str]]:
    """(label, file content or path, words a clear message has, expectation)."""
    s = SMALL_STUDY
    big_int = "1" + "0" * 5000
    return [
        ("duplicate top key", s + "name: again\n", ("duplicate",), "refuse"),
        ("duplicate nested key", s.replace("head: TEST_HEAD,", "head: TEST_HEAD, head: HEAD_MIN,"),
         ("duplicate",), "refuse"),
        ("NUL byte", s.replace("hostile_cli", "hostile\x00cli"), ("nul", "null", "control",
                                                                  "character", "byte"), "refuse"),
        ("5000-digit integer", s.replace("0.4}", big_int + "}"), ("impact_velocity",), "refuse"),
        ("5000-digit integer in name", s.replace("name: hostile_cli", f"name: {big_int}"),
         ("name", "digits"), "refuse"),
        ("5000 nested lists", _deep(5000, False), ("nest", "deep", "depth", "level"), "refuse"),
        ("5000 nested mappings", _deep(5000, True), ("nest", "deep", "depth", "level"), "refuse"),
        ("6 MB file", s + "# " + "x" * (6 * 2**20) + "\n", ("mb", "large", "size", "bytes"),
         "refuse"),
        ("unknown top key", s + "extra_key: 1\n", ("extra_key",), "refuse"),
        ("unknown nested key", s.replace("impact_velocity", "impact_velocty"),
         ("impact_velocty",), "refuse"),
        ("kind is a number", s.replace("kind: impact_cases", "kind: 3"), ("kind",), "refuse"),
        ("cases is text", s.split("cases:")[0] + "cases: abc\n", ("cases",), "refuse"),
        ("empty file", "", ("empty", "kind", "designlab"), "refuse"),
        ("not UTF-8", s.encode() + b"# \xff\xfe\n", ("utf-8", "utf8", "encoding", "decode"),
         "refuse"),
        ("alias bomb", s + "bomb: &a [1,1,1,1,1,1,1,1,1]\nb2: &b [*a,*a,*a,*a,*a,*a,*a,*a,*a]\n"
         "b3: &c [*b,*b,*b,*b,*b,*b,*b,*b,*b]\nb4: &d [*c,*c,*c,*c,*c,*c,*c,*c,*c]\n"
         "b5: [*d,*d,*d,*d,*d,*d,*d,*d,*d]\n", ("alias", "bomb", "b5", "bomb"), "refuse"),
        ("python tag", s + "x: !!python/object/apply:os.system ['true']\n",
         ("tag", "python"), "refuse"),
        ("/dev/zero", Path("/dev/zero"), ("regular", "device", "file", "size"), "refuse"),
        ("a FIFO", "FIFO", ("regular", "fifo", "pipe", "file"), "refuse"),
        ("a directory", tmp, ("directory", "regular", "file"), "refuse"),
        ("a missing file", tmp / "missing.yaml", ("missing", "not found", "no such", "exist"),
         "refuse"),
        ("symlink to /dev/zero", "LINK", ("regular", "device", "file", "size"), "refuse"),
        ("BOM", "\ufeff" + s, (), "either"),
        ("tab indent", s.replace("  - {", "\t- {"), ("tab", "indent", "line"), "refuse"),
        ("valid small study", s, (), "accept"),
    ]  # fmt: skip


def _materialise(tmp: Path, label: str, content: Any) -> Path:
    if isinstance(content, Path):
        return content
    path = tmp / (re.sub(r"\W+", "_", label) + ".yaml")
    if content == "FIFO":
        os.mkfifo(path)
    elif content == "LINK":
        path.symlink_to("/dev/zero")
    elif isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content, encoding="utf-8")
    return path


def cli_command(args: Sequence[str], timeout: float) -> dict[str, Any]:
    """Run ``python -m designlab ARGS`` (this checkout first on the path) with a timeout."""
    env = {**os.environ, "PYTHONPATH": f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    try:
        done = subprocess.run([sys.executable, "-m", "designlab", *args], capture_output=True,
                              text=True, timeout=timeout, env=env, stdin=subprocess.DEVNULL,
                              errors="replace")  # fmt: skip
    except subprocess.TimeoutExpired:
        return {"hang": True, "args": list(args)}
    return {"code": done.returncode, "out": done.stdout, "err": done.stderr, "args": list(args)}


def cli_judge(words: tuple[str, ...], expect: str, names: tuple[str, ...] = ()):
    """Classify a CLI run: exit 0, a clean error message, a traceback or a hang."""

    def judge(r: Any) -> tuple[str, str]:
        if isinstance(r, BaseException):
            return "traceback", f"{type(r).__name__}: {r}"[:240]
        if r.get("hang"):
            return "hang", "the command did not finish within its timeout"
        err = r["err"].strip()
        last = (err.splitlines() or [""])[-1][:200]
        if r["code"] == 0:
            if expect == "refuse":
                return "silent", f"exit 0: accepted ({r['out'].strip()[:120]})"
            return "accepted", ""
        if "Traceback (most recent call last)" in err:
            return "traceback", f"exit {r['code']}: {last}"
        low = err.lower()
        named = all(n.lower() in low for n in names)
        said = not words or any(w in low for w in words)
        if named and said:
            return "clear", f"exit {r['code']}: {last}"
        return "unclear", f"exit {r['code']}: {last}"

    return judge


#: Seconds a command may take: a fresh interpreter that imports every domain (to list the
#: study kinds, say) takes 5 s of CPU, 25 s of wall time on a busy machine.
CLI_TIMEOUT = 45.0


def cli_cases(timeout: float = CLI_TIMEOUT) -> list[Case]:
    """File-level attacks on validate and run, and hostile command-line options."""
    tmp = Path(tempfile.mkdtemp(prefix="hostile-cli-"))
    out = []
    for label, content, words, expect in _file_attacks(tmp):
        path = _materialise(tmp, label, content)
        for command in ("validate", "run"):
            args = [command, str(path)] + (["-o", str(tmp / "reports")] if command == "run" else [])
            out.append(Case("cli", f"designlab {command} <{label}>",
                            _cli_call(args, timeout - 2), judge=cli_judge(words, expect),
                            repro=f"designlab {' '.join(args)}", timeout=timeout))  # fmt: skip
    small = _materialise(tmp, "small", SMALL_STUDY)
    options = [
        ("-j 0", ["-j", "0"], "workers"),
        ("-j 10**9", ["-j", str(10**9)], "workers"),
        ("-e bogus", ["-e", "bogus"], "executor"),
        ("--timeout nan", ["--timeout", "nan"], "timeout"),
        ("--timeout -1", ["--timeout", "-1"], "timeout"),
        ("--worker-timeout inf", ["-e", "processes", "--worker-timeout", "inf"], "worker-timeout"),
        ("-o a file", ["-o", str(small)], str(small)),
        ("--cache-dir /dev/null", ["--cache-dir", "/dev/null"], "cache"),
        ("-e processes -j 10**6", ["-e", "processes", "-j", str(10**6)], "workers"),
    ]
    for label, extra, name in options:
        args = ["run", str(small), "-o", str(tmp / "reports"), *extra]
        out.append(Case("cli", f"designlab run {label}", _cli_call(args, timeout - 2),
                        judge=cli_judge((), "either", (name,)),
                        repro=f"designlab {' '.join(args)}", timeout=timeout))  # fmt: skip
    return out + scenario_file_cases(tmp)


def _cli_call(args: list[str], timeout: float) -> Callable[[], Any]:
    return lambda: cli_command(args, timeout)


def scenario_file_cases(tmp: Path) -> list[Case]:
    """dl.navigation.scenario_io.load_scenario on hostile files (a Python API of the files)."""
    base = "name: s\nstart: [3.0, 0.0]\ngoal: [0.0, 0.0]\n"
    files = [
        ("5000 nested lists", base + "obstacles: " + "[" * 5000 + "]" * 5000 + "\n",
         ("nest", "deep", "depth", "level")),
        ("duplicate key", base + "goal: [1.0, 0.0]\n", ("duplicate", "goal")),
        ("not a mapping", "- 1\n- 2\n", ("mapping",)),
        ("syntax error", base + "obstacles: [\n", ("line", "yaml")),
        ("/dev/zero", Path("/dev/zero"), ("regular", "device", "size")),
    ]  # fmt: skip
    out = []
    for label, content, words in files:
        path = _materialise(tmp, "scenario_" + label, content)
        expr = f"load_scenario({str(path)!r})"
        out.append(Case("cli", f"load_scenario <{label}>", _load_scenario_call(path), (),
                        NOVALUE, "refuse", None,
                        f"from designlab.navigation.scenario_io import load_scenario; {expr}",
                        judge=_scenario_judge(words)))  # fmt: skip
    return out


def _load_scenario_call(path: Path) -> Callable[[], Any]:
    def call() -> Any:
        from designlab.navigation.scenario_io import load_scenario

        return load_scenario(path)

    return call


def _scenario_judge(words: tuple[str, ...]) -> Callable[[Any], tuple[str, str]]:
    def judge(r: Any) -> tuple[str, str]:
        if not isinstance(r, BaseException):
            return "silent", "accepted"
        from designlab.errors import DesignlabError

        line = f"{type(r).__name__}: {r}".splitlines()[0][:200]
        if not isinstance(r, (DesignlabError, ValueError)):
            return "traceback", line
        ok = not words or any(w in str(r).lower() for w in words)
        return ("clear" if ok else "unclear"), line

    return judge


# ------------------------------------------------------------------------ main


def _impact_cases() -> list[Case]:
    import designlab.impact as im

    targets = impact_targets() + impact_more_targets()
    cases = [c for t in targets for c in target_cases(t, [im.parameters])]
    return cases + impact_metrics_cases() + impact_extra_cases()


def _impact_warmup() -> None:
    import designlab as dl

    im = dl.impact
    im.simulate(im.MANIPULATOR_1, im.FOAM_1, im.TEST_HEAD, 1.25)
    im.simulate(im.FullJointContact(**BASE_JOINT), im.FOAM_1, im.TEST_HEAD, 1.25)
    im.impact_metrics([[9.6, 250, 2e4, 24.25e3, 71.9, 4.4, 46, 3e3]], 1.25,
                      columns=im.PARAM_NAMES)  # fmt: skip
    im.foam_envelope(im.MANIPULATOR_1, 1.25, damping=[0.0, 60.0])


#: domain -> (cases, warm-up of each worker)
DOMAINS: dict[str, tuple[Callable[[], list[Case]], Callable[[], None] | None]] = {
    "impact": (_impact_cases, _impact_warmup),
    "codesign": (codesign_cases, _codesign_warmup),
    "navigation": (navigation_cases, _navigation_warmup),
    "following": (following_cases, _following_warmup),
    "yaml": (lambda: yaml_extra_cases() + yaml_cases(), _yaml_warmup),
    "cli": (cli_cases, None),
}


def tally(rows: Sequence[dict[str, Any]]) -> dict[str, Counter]:
    """Outcome counts per domain."""
    out: dict[str, Counter] = {}
    for r in rows:
        out.setdefault(r["domain"], Counter())[r["outcome"]] += 1
    return out


def table(rows: Sequence[dict[str, Any]]) -> str:
    """The per-domain Markdown table of outcomes."""
    counts = tally(rows)
    head = "| domain | cases | " + " | ".join(OUTCOMES) + " |"
    lines = [head, "|" + "---|" * (len(OUTCOMES) + 2)]
    total: Counter = Counter()
    for domain, c in sorted(counts.items()):
        total.update(c)
        lines.append(f"| {domain} | {sum(c.values())} | "
                     + " | ".join(str(c[o]) for o in OUTCOMES) + " |")  # fmt: skip
    if len(counts) > 1:
        lines.append(f"| all | {sum(total.values())} | "
                     + " | ".join(str(total[o]) for o in OUTCOMES) + " |")  # fmt: skip
    return "\n".join(lines)


#: Outcomes in the order the findings list them (the worst first).
_ORDER = ("hang", "traceback", "silent", "unclear")


def _pattern(row: dict[str, Any]) -> tuple[str, str, str]:
    """(outcome, function, detail with its numbers and quoted values blanked): a group key."""
    func = row["name"].split(" ")[0]
    detail = re.sub(r"hostile\.yaml:\d+: [^:]*: ", "", row["detail"])
    detail = re.sub(r"'[^']*'|\"[^\"]*\"|\(.*?\)|[-+]?\d[\d.e+-]*", "#", detail)
    return row["outcome"], func, detail[:160]


def findings(rows: Sequence[dict[str, Any]], group: bool = True) -> str:
    """The non-clean cases as Markdown: per outcome and function, one line per kind of fault.

    Cases with the same outcome, function and detail (numbers aside) are one line with
    their count, the cases' names and the first one's reproduction (``group=False``: one
    line per case).
    """
    bad = [r for r in rows if r["outcome"] not in ("clear", "accepted")]
    bad.sort(key=lambda r: (_ORDER.index(r["outcome"]), r["domain"], r["name"]))
    groups: dict[tuple[str, str, str], list[dict[str, Any]]] = {}
    for r in bad:
        groups.setdefault(_pattern(r) if group else (r["name"], "", ""), []).append(r)
    lines = []
    for members in groups.values():
        first = members[0]
        names = ", ".join(m["name"].split(" ", 1)[-1] for m in members[:8])
        more = f" and {len(members) - 8} more" if len(members) > 8 else ""
        count = f" (x{len(members)}: {names}{more})" if len(members) > 1 else ""
        lines.append(f"- **{first['outcome']}** `{first['name']}`{count}: {first['detail']}  \n"
                     f"  repro: `{first['repro']}`")  # fmt: skip
    return "\n".join(lines)


def _arguments(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--domain", choices=sorted(DOMAINS), help="the domain to run")
    parser.add_argument("--timeout", type=float, default=20.0, help="seconds per case")
    parser.add_argument("--memory", type=float, default=6.0, help="GiB per worker")
    parser.add_argument("--filter", default="", help="only cases whose name contains this "
                        "(several: a|b)")  # fmt: skip
    parser.add_argument("--limit", type=int, default=0, help="at most this many cases")
    parser.add_argument("--json", help="write every row to this JSON file")
    parser.add_argument("--findings", help="append the non-clean cases (Markdown) to this file")
    parser.add_argument("--title", default="", help="the heading of the appended findings")
    parser.add_argument("--quiet", action="store_true", help="no line per non-clean case")
    parser.add_argument("--merge", nargs="+", metavar="JSON",
                        help="no run: the table and findings of earlier --json files")  # fmt: skip
    args = parser.parse_args(argv)
    if not args.domain and not args.merge:
        parser.error("give --domain (to run) or --merge (earlier runs)")
    return args


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: run one domain's cases, print the tally and the non-clean cases."""
    args = _arguments(argv)
    if args.merge:
        rows = [r for f in args.merge for r in json.loads(Path(f).read_text())]
    else:
        make, warmup = DOMAINS[args.domain]
        wanted = args.filter.split("|")
        cases = [c for c in make() if any(w in c.name for w in wanted)]
        if args.limit:
            cases = cases[: args.limit]
        start = time.monotonic()
        print(f"{args.domain}: {len(cases)} cases, {args.timeout:g} s each at most", flush=True)
        rows = run_cases(cases, args.timeout, args.memory, not args.quiet, warmup)
        print(f"\n{len(rows)} cases in {time.monotonic() - start:.0f} s")
    print(f"\n{table(rows)}\n")
    found = "\n\n".join(
        f"### {d}\n\n{f}" for d in sorted({r["domain"] for r in rows})
        if (f := findings([r for r in rows if r["domain"] == d]))
    )  # fmt: skip
    print(found or "no non-clean case")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1, default=str))
    if args.findings:
        stamp = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
        title = args.title or f"hostile.py {args.domain or 'merged'}"
        with open(args.findings, "a", encoding="utf-8") as fh:
            fh.write(f"\n## {stamp}: {title}\n\n{table(rows)}\n\n{found}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
