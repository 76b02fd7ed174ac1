"""The arguments of the co-design functions, declared once (:mod:`designlab.params`).

The robot, foam, head-neck and criterion parameters are declared on their
impact models (:mod:`designlab.impact.parameters`); this module declares only
what the co-design layer adds: the braking model of the speed limit, the map's
grid sizes and the Monte Carlo settings of the injury probability.

Examples
--------
>>> REACTION_TIME.check(0.06)
0.06
>>> RISK_METHOD.check("importance")
'importance'
"""

from __future__ import annotations

from designlab.params import ARG, Param

__all__ = [
    "BRAKING_SPEED",
    "CONFIDENCE",
    "CONTACT_LIMIT",
    "CURVE_POINTS",
    "DECELERATION",
    "DETECTION_DISTANCE",
    "MAP_POINTS",
    "REACTION_TIME",
    "RISK_METHOD",
    "RISK_SAMPLES",
    "SEED",
    "SENSITIVITY_SAMPLES",
    "SUBSET_SAMPLES",
]

#: Time between the robot's detection of a person and the start of its braking: the
#: robot keeps its speed meanwhile (Zeng 2011, Sec. 5.3 treats the period T_s so).
REACTION_TIME = Param(
    "T_r", "s", "reaction time: the robot keeps its speed before it brakes", ge=0, le=10,
    typical=(0.0, 0.1), default=0.0, name="reaction_time",
)  # fmt: skip

#: The robot's braking deceleration after the reaction time.
DECELERATION = Param(
    "a_b", "m/s^2", "braking deceleration of the robot", ge=1e-3, le=100, typical=(1.0, 10.0),
    default=10.0, name="deceleration",
)  # fmt: skip

#: Distance between robot and person when the robot detects the person (0: a contact
#: without warning, the robot's speed at contact is its speed limit).
DETECTION_DISTANCE = Param(
    "d_det", "m", "separation at which the robot detects the person (0: no warning)", ge=0,
    le=100, typical=(0.0, 1.0), default=0.0, name="detection_distance",
)  # fmt: skip

#: A robot speed of the braking model: the speed before braking (at most what a speed limit
#: can give, sqrt(20^2 + 2 x 100 m/s^2 x 100 m) = 143 m/s with the largest declared contact
#: speed, deceleration and detection distance).
BRAKING_SPEED = Param(
    "v", "m/s", "robot speed before it brakes", ge=0, le=150, typical=(0.0, 2.0), name="speed"
)

#: The largest robot speed allowed at contact (a speed limit's answer, at most the largest
#: closing velocity of the impact models, 20 m/s).
CONTACT_LIMIT = Param(
    "u", "m/s", "largest robot speed allowed at contact", ge=0, le=20, name="contact_limit"
)

#: Points per axis of a speed-limit map (the map has their product).
MAP_POINTS = Param(
    None, "", "points per axis of the speed-limit map", kind="integer", ge=1, le=400,
    name="map_points",
)  # fmt: skip

#: Monte Carlo samples of an injury probability (each costs one impact-kernel call). The cap
#: bounds a run: crude and importance sampling and a fragility curve draw 3e5-4e5 samples/s
#: on one (shared) core, so 2e6 samples take about 6 s (interruptible between blocks of
#: 262,144 samples); a larger crude reference pools runs of different seeds
#: (benchmarks/codesign.py).
RISK_SAMPLES = Param(
    None, "", "Monte Carlo samples (at the cap about 6 s)", kind="integer", ge=10,
    le=2_000_000, default=100_000, name="samples",
)  # fmt: skip

#: Samples per level of subset simulation: at most 20 levels (MAX_LEVELS) of that many
#: impact-kernel evaluations at about 2e5/s on one (shared) core, so about 10 s a run at the
#: cap (18 levels, 9 s, measured for a probability below 1e-16; interruptible between
#: Markov-chain steps).
SUBSET_SAMPLES = Param(
    None, "", "samples per level of subset simulation (at the cap about 10 s)",
    kind="integer", ge=10, le=100_000, name="samples",
)  # fmt: skip

#: Estimator of an injury probability.
RISK_METHOD = Param(
    None, "", "Monte Carlo estimator", kind="choice",
    choices=("crude", "importance", "subset"),
    default="importance", name="method",
)  # fmt: skip

#: Two-sided confidence level of the probability's interval.
CONFIDENCE = ARG.confidence.but(doc="confidence level of the interval", gt=0.5)

#: Seed of the random samples.
SEED = ARG.seed.but(doc="seed of the random samples")

#: Closing speeds of a fragility curve (each a point of the curve).
CURVE_POINTS = Param(
    None, "", "closing speeds of a fragility curve", kind="integer", ge=1, le=10_000,
    name="speeds",
)  # fmt: skip

#: Saltelli base sample size of the front's Sobol indices (N (D + 2) designs, each a set
#: of navigation runs; a power of two).
SENSITIVITY_SAMPLES = Param(
    None, "", "Saltelli base sample size N of the front's Sobol indices (a power of two)",
    kind="integer", ge=2, le=4096, default=16, name="samples",
)  # fmt: skip
