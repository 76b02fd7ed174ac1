"""The crowd layer's heavy dependencies, imported on first use (issue 39, item 2).

JuPedSim (the pedestrian simulation) and pedpy (the crowd the robot met) are installed by the
``crowds`` extra, ``pip install 'designlab[crowds]'``; together with what they pull in (PySide6
and VTK for JuPedSim's viewer) they are most of a full install. Nothing outside the crowd
layer needs them, so :mod:`designlab.navigation` imports neither: :func:`jupedsim` and
:func:`pedpy` import them when a crowd is simulated or measured, and raise
:class:`~designlab.errors.MissingExtraError` naming the extra when they are missing.

pedpy configures the root logger when imported (``logging.basicConfig`` in
``pedpy.preprocessing``), which would print designlab's INFO lines in a user's own script;
:func:`pedpy` imports it with the logging and warnings configuration put back as it was.
"""

from __future__ import annotations

import importlib
import logging
import warnings
from types import ModuleType

from designlab.errors import MissingExtraError

__all__ = ["EXTRA", "jupedsim", "pedpy"]

#: The extra that installs the crowd layer's dependencies.
EXTRA = "crowds"


def jupedsim() -> ModuleType:
    """The ``jupedsim`` module (imported on first use).

    Raises
    ------
    MissingExtraError
        If JuPedSim is not installed (``pip install 'designlab[crowds]'``).
    """
    return _quietly("jupedsim", "crowd simulations (JuPedSim's pedestrians)")


def pedpy() -> ModuleType:
    """The ``pedpy`` module (imported on first use, leaving logging configured as it was).

    Raises
    ------
    MissingExtraError
        If pedpy is not installed (``pip install 'designlab[crowds]'``).
    """
    return _quietly("pedpy", "measures of the crowd a robot met (pedpy)")


def _quietly(name: str, needed_for: str) -> ModuleType:
    """Import ``name``; put back the root logger's handlers and level and the warnings filters."""
    root = logging.getLogger()
    handlers, level = list(root.handlers), root.level
    try:
        with warnings.catch_warnings():
            return importlib.import_module(name)
    except ImportError as exc:
        raise MissingExtraError(name, EXTRA, needed_for, str(exc)) from exc
    finally:
        root.handlers[:] = handlers
        root.setLevel(level)
