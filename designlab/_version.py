"""The designlab version (one place; the package and the store keys read it)."""

__version__ = "0.1.0"
