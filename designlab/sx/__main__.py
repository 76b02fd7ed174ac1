"""``python -m designlab.sx [info|clear]``: where compiled code is cached; clear it.

Examples
--------
>>> main(["info"])  # doctest: +SKIP
cache directory: /home/me/.cache/designlab (DESIGNLAB_CACHE_DIR to change)
"""

from __future__ import annotations

import argparse
import sys

from designlab.sx.cache import ENV, cache_dir, clear_cache
from designlab.sx.compiler import compiler_missing_reason, find_compiler


def main(argv: list[str] | None = None) -> int:
    """Print the cache directory and the compiler (``info``) or clear the cache (``clear``)."""
    ap = argparse.ArgumentParser(prog="python -m designlab.sx", description=__doc__.splitlines()[0])
    ap.add_argument("command", choices=("info", "clear"), nargs="?", default="info")
    args = ap.parse_args(argv)
    if args.command == "clear":
        sys.stdout.write(f"removed {clear_cache()} compiled entries from {cache_dir()}\n")
        return 0
    reason = compiler_missing_reason()
    compiler = " ".join(find_compiler().command) if reason is None else reason
    sys.stdout.write(f"cache directory: {cache_dir()} ({ENV} to change)\nC compiler: {compiler}\n")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
