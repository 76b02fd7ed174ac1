"""``python -m designlab``: the same as the ``designlab`` command."""

from designlab.cli import app

app()
