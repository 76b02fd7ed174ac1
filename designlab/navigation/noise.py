"""A seeded sensor-noise model: what the field sees is measured, not true (Zeng 2011, Sec. 6.2).

The thesis's robots see themselves and the human through a 16.7 Hz camera with a maximum
position error of 0.025 m (Sec. 6.2.1), and the thesis explains with such noise why its
optimised gains do worse than the experiment gains in Configurations 2 and 4. With
``simulate(..., noise=SensorNoise(...))`` every navigation sample draws, from a generator
seeded with ``seed``:

* the robot's measured position error (normal, ``position_sd`` per axis);
* each obstacle's measured position error (the same distribution; static obstacles too:
  the field sees them relative to the noisy robot);
* each moving obstacle's measured velocity error (``velocity_sd`` per axis).

The field and the critical-region rule use the measurements; the robot moves, collides and
is scored with the true state. The robot's own velocity comes from its wheel encoders and
is taken as exact. The nominal (obstacle-free) run of the criteria is noise-free.

Examples
--------
>>> import designlab as dl
>>> nav = dl.navigation
>>> quiet = nav.simulate(nav.configuration(1), nav.EXPERIMENT_GAINS, stabilising="off")
>>> noisy = nav.simulate(nav.configuration(1), nav.EXPERIMENT_GAINS, stabilising="off",
...                      noise=SensorNoise(position_sd=0.0125, seed=3))
>>> noisy.arrived, noisy.arrival_time != quiet.arrival_time
(True, True)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from designlab.params import ARG, declared, param
from designlab.validation import ParamsMixin

__all__ = ["SensorNoise"]


@declared
@dataclass(frozen=True)
class SensorNoise(ParamsMixin):
    """Seeded measurement noise of the robot's and the obstacles' positions and velocities.

    Examples
    --------
    >>> SensorNoise().position_sd
    0.0125
    """

    position_sd: float = param(
        "sigma_p", "m", doc="standard deviation of a measured position, per axis", ge=0,
        le=1.0, default=0.0125, typical=(0.0, 0.025),
    )  # fmt: skip
    velocity_sd: float = param(
        "sigma_v", "m/s", doc="standard deviation of a moving obstacle's measured velocity, "
        "per axis", ge=0, le=5.0, default=0.1, typical=(0.0, 0.3),
    )  # fmt: skip
    seed: int = ARG.seed.field(doc="seed of the generator")

    def generator(self) -> np.random.Generator:
        """A fresh generator for one run."""
        return np.random.default_rng(self.seed)

    def measure(
        self, rng: np.random.Generator, obs: NDArray[np.float64], goal: NDArray[np.float64],
        moving: NDArray[np.bool_],
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # fmt: skip
        """The measured obstacle inputs (6 per obstacle) and goal seen from the noisy robot.

        The robot's position error e_r enters as a shift of everything it sees by -e_r
        (the field depends on relative positions only).

        Parameters
        ----------
        rng
            The run's generator.
        obs
            True positions, velocities and accelerations (6 per obstacle).
        goal
            The goal.
        moving
            Which obstacles move (only their velocities are measured with noise).
        """
        n = moving.size
        e_r = rng.normal(0.0, self.position_sd, 2)
        e_o = rng.normal(0.0, self.position_sd, (n, 2))
        e_v = rng.normal(0.0, self.velocity_sd, (n, 2)) * moving[:, None]
        out = obs.reshape(n, 6).copy() if n else obs.reshape(0, 6).copy()
        out[:, 0:2] += e_o - e_r
        out[:, 2:4] += e_v
        return out.reshape(-1), np.asarray(goal, dtype=float) - e_r
