"""Co-design: how fast may the arm move with this foam?

The speed limit of Manipulator 1 with Foam 1 over the thesis's range of heads: the
largest robot speed whose impact meets every criterion, and which criterion limits it
(``docs/codesign.md``); then the same limit for foams of other stiffness.
"""

import matplotlib.pyplot as plt

import designlab as dl

cd, imp = dl.codesign, dl.impact
limit = cd.speed_limit(imp.MANIPULATOR_1, imp.FOAM_1)
print(f"{limit.max_speed:.3f} m/s, limited by {limit.limiting_criterion}")

stiffness = [12e3, 24.25e3, 48e3]
speeds = [
    cd.speed_limit(imp.MANIPULATOR_1, imp.Foam(stiffness=k, damping=71.9, linear_depth=0.02))
    for k in stiffness
]
fig, ax = plt.subplots(layout="constrained")
ax.plot([k / 1e3 for k in stiffness], [s.max_speed for s in speeds], "o-")
ax.set_xlabel("foam stiffness K_c (kN/m)")
ax.set_ylabel("speed limit (m/s)")
ax.set_title("Manipulator 1, 20 mm of foam, damping 71.9 N s/m")
