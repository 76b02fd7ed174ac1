"""Drop the navigation files (``SUMMARY.md``, read by literate-nav) from the built site.

literate-nav reads each ``SUMMARY.md`` (the site's and the generated gallery, examples and
API ones) to make the navigation; built as pages they were stray pages ("SUMMARY", with
links that do not resolve from where the page stands). Once the navigation is made, this
hook removes them from the files to build.
"""

from __future__ import annotations

from typing import Any

from mkdocs.plugins import event_priority


@event_priority(-100)  # after literate-nav has read them
def on_nav(nav: Any, config: Any, files: Any) -> Any:
    for file in [f for f in files if f.src_uri.split("/")[-1] == "SUMMARY.md"]:
        files.remove(file)
    return nav
