"""Importing designlab is light and changes nothing of the user's process (issue 39, item 2).

* No module of designlab configures logging or changes the warnings filters when imported
  (pedpy's ``logging.basicConfig`` made designlab's INFO lines appear in users' scripts).
* The crowd layer's heavy dependencies (JuPedSim, pedpy and, through pedpy, pyplot) are
  imported only when a crowd is simulated or measured (``designlab.navigation.crowds.extra``),
  and a missing one is a clear error naming the ``crowds`` extra.

Each check runs in a fresh interpreter: this process has imported everything already.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("jupedsim", "pedpy", "matplotlib.pyplot")

_PROBE = """
import json, logging, sys, warnings
import numpy, casadi, scipy.signal  # each adds warnings filters of its own (not designlab)
root = logging.getLogger()
before = (list(root.handlers), root.level, list(warnings.filters))
import importlib
for name in sys.argv[1:]:
    importlib.import_module(name)
after = (list(root.handlers), root.level, list(warnings.filters))
print(json.dumps({
    "logging_unchanged": before[:2] == after[:2],
    "filters_unchanged": before[2] == after[2],
    "heavy": [m for m in HEAVY if m in sys.modules],
}))
""".replace("HEAVY", repr(HEAVY))


def _probe(*modules: str, code: str = _PROBE) -> dict:
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
    }
    env.pop("MPLBACKEND", None)
    done = subprocess.run(
        [sys.executable, "-c", code, *modules], capture_output=True, text=True, env=env, timeout=300
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


DOMAINS = ("designlab", "designlab.impact", "designlab.navigation", "designlab.following",
           "designlab.codesign", "designlab.study", "designlab.cli")  # fmt: skip


def test_importing_designlab_changes_no_logging_or_warnings_and_loads_no_crowd_deps() -> None:
    """Every domain in one interpreter: what none of them does, each of them does not do."""
    seen = _probe(*DOMAINS)
    assert seen == {"logging_unchanged": True, "filters_unchanged": True, "heavy": []}


def test_the_crowd_deps_load_on_use_without_configuring_logging() -> None:
    code = _PROBE.replace(
        "for name in sys.argv[1:]:\n    importlib.import_module(name)",
        "from designlab.navigation.crowds import extra\nextra.pedpy(); extra.jupedsim()",
    )
    seen = _probe(code=code)
    assert seen["logging_unchanged"] and seen["filters_unchanged"]
    assert {"jupedsim", "pedpy"} <= set(seen["heavy"])


def test_a_missing_crowd_dependency_names_the_extra() -> None:
    code = """
import json, sys
sys.modules["jupedsim"] = None  # as if not installed: importing it raises ImportError
import designlab as dl
nav = dl.navigation
try:
    nav.simulate_pedestrians(nav.crowd("corridor_counterflow", pedestrians=4, seed=0, horizon=0.1))
except dl.errors.MissingExtraError as exc:
    print(json.dumps({"message": str(exc), "import_error": isinstance(exc, ImportError)}))
"""
    seen = _probe(code=code)
    assert seen["import_error"]
    assert "jupedsim" in seen["message"] and "pip install 'designlab[crowds]'" in seen["message"]


#: Libraries a package import must not load: each costs 0.1-1 CPU s, and a call loads the
#: ones it needs (issue 39, item 2: ``import designlab`` and each domain under 0.5 CPU s).
NOT_ON_IMPORT = ("numpy", "scipy", "pandas", "matplotlib", "numba", "casadi", "pydantic",
                 "yaml", "jupedsim", "pedpy", "tqdm", "control")  # fmt: skip

_LOADED = """
import json, sys, importlib
importlib.import_module(sys.argv[1])
print(json.dumps(sorted(m for m in sys.modules if m.split(".")[0] in NAMES)))
"""


def _loaded_after(code: str, *args: str) -> set[str]:
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
    }
    done = subprocess.run(
        [sys.executable, "-c", code, *args], capture_output=True, text=True, env=env, timeout=300
    )
    assert done.returncode == 0, done.stderr
    return set(json.loads(done.stdout.strip().splitlines()[-1]))


@pytest.mark.parametrize("package", DOMAINS[:5])
def test_a_package_import_loads_no_numeric_library(package: str) -> None:
    code = _LOADED.replace("NAMES", repr((*NOT_ON_IMPORT, "designlab")))
    loaded = _loaded_after(code, package)
    assert not {m.split(".")[0] for m in loaded} - {"designlab"}
    # only the package itself and the core it is made of: no module of a domain is run
    assert {m for m in loaded if m.count(".") and not m.endswith("__init__")} <= {
        "designlab._lazy", "designlab._version", package,
        *(f"designlab.{d}" for d in ("impact", "navigation", "following", "codesign")),
    }  # fmt: skip


def test_a_name_is_imported_with_its_module_only() -> None:
    """``dl.impact.simulate`` loads the impact model and not the other domains or plotting."""
    code = """
import json, sys
import designlab as dl
dl.impact.simulate, dl.impact.FOAM_1
print(json.dumps(sorted(sys.modules)))
"""
    loaded = _loaded_after(code)
    assert not {m for m in loaded if m.split(".")[0] in ("matplotlib", "jupedsim", "pedpy")}
    others = ("designlab.navigation", "designlab.following", "designlab.codesign")
    assert not [m for m in loaded if m.startswith(others)]
    assert {"designlab.impact.simulate", "designlab.impact.parameters"} <= loaded


def test_a_function_named_as_its_module_stays_the_function() -> None:
    """``designlab.navigation.criteria`` (module) imported first: the name is still the function."""
    code = """
import json, sys
import designlab.navigation.criteria, designlab.impact.simulate
import designlab as dl
from designlab.navigation import criteria
print(json.dumps([callable(dl.navigation.criteria), callable(dl.impact.simulate),
                  callable(criteria), dl.navigation.engine.__name__]))
"""
    assert _loaded_after(code) == {True, "designlab.navigation.engine"}


_ENGINES = """
import importlib, json, sys
for name in sys.argv[1:]:
    importlib.import_module(name)
print(json.dumps(sorted(m for m in ("numba", "matplotlib.pyplot", "designlab.impact.kernel",
                                    "designlab.analysis.lhs_kernel") if m in sys.modules)))
"""


def test_a_sweep_kind_and_its_report_load_no_compiled_engine() -> None:
    """Loading the impact sweep kind (what a resumed run and a rebuilt report do) and its report
    writer imports neither numba, the impact kernel, the compiled sampler nor pyplot (issue
    40.1): the evaluators and the sampler import them when they compute."""
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
    }
    names = ("designlab.study.kinds.impact_sweep", "designlab.report.sweep", "designlab.cli")
    done = subprocess.run([sys.executable, "-c", _ENGINES, *names], capture_output=True,
                          text=True, env=env, timeout=300)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout.strip().splitlines()[-1]) == []
