"""Co-design: foam, speed limit and navigation gains chosen together (issue 24)."""

from __future__ import annotations

# --- contact speeds and the Pareto front (cdfront) ---
from designlab.codesign.contacts import (
    ContactSpeeds,
    ContactStatus,
    contact_speeds,
    navigation_contacts,
)

__all__ = [
    "ContactSpeeds",
    "ContactStatus",
    "contact_speeds",
    "navigation_contacts",
]
