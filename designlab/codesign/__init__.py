"""Co-design: foam, speed limit and navigation gains chosen together (issue 24)."""

from __future__ import annotations

# --- contact speeds and the Pareto front (cdfront) ---
from designlab.codesign.contacts import (
    ContactSpeeds,
    ContactStatus,
    contact_speeds,
    navigation_contacts,
)
from designlab.codesign.front import (
    OBJECTIVES,
    THESIS_DESIGN,
    Design,
    DesignScore,
    DesignSpace,
    FrontStatus,
    ParetoFront,
    evaluate_design,
    nondominated,
    nsga2,
    pareto,
)

__all__ = [
    "OBJECTIVES",
    "THESIS_DESIGN",
    "ContactSpeeds",
    "ContactStatus",
    "Design",
    "DesignScore",
    "DesignSpace",
    "FrontStatus",
    "ParetoFront",
    "contact_speeds",
    "evaluate_design",
    "navigation_contacts",
    "nondominated",
    "nsga2",
    "pareto",
]
