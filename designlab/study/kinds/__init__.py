"""The study kinds shipped with designlab: one module per kind.

Each module defines its schema (a :class:`~designlab.study.base.StudyBase`
subclass), its runner and ``KIND = StudyKind(...)``. To add a kind, write the
module and add its name to :data:`MODULES`.
"""

#: Kind modules, in the order ``designlab list`` and the JSON Schema show them.
MODULES: tuple[str, ...] = (
    "impact_cases",
    "impact_sweep",
    "foam_envelope_sweep",
    "foam_design",
    "joint_reduction",
    "zeng_ch3_claims",
    "tether_comparison",
    "tether_tuning",
    "tether_sweep",
    "tether_stability",
    "tether_step_size",
    "tether_snagging",
    "tether_modes",
    "navigation_scenarios",
    "navigation_sweep",
    "navigation_gains",
    "navigation_account",
    "navigation_regions",
    "navigation_planners",
    "navigation_crowds",
    "accompanying",
    "codesign",
)
