"""Impact: a foam-covered arm striking a head.

The README's first example, drawn: the head acceleration of Zeng 2011's Manipulator 1
covered with Foam 1 striking the test head at 1.25 m/s (Ch. 3), then the band of foams
(stiffness against damping) that keep that impact below the injury criteria and within
the foam's depth (Ch. 4, ``docs/impact.md``).
"""

import matplotlib.pyplot as plt
import numpy as np

import designlab as dl

imp = dl.impact
response = imp.simulate(imp.MANIPULATOR_1, imp.FOAM_1, imp.TEST_HEAD, impact_velocity=1.25)
print(response)

envelope = imp.foam_envelope(imp.MANIPULATOR_1, 1.25, np.linspace(0.0, 200.0, 21))
print(envelope.summary(max_rows=3))

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
response.plot(left)
left.set_title("head acceleration, Manipulator 1 + Foam 1")
envelope.plot(right)
right.set_title("foams that keep the impact safe")
