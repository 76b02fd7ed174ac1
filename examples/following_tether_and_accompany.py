"""Following: a robot led on a tether, and a robot walking beside its user.

Allan 2015's Follow the Leader with Constant Distance on a figure eight, with the normal
path deviation of App. A; then Wu et al. 2021's accompanying robot keeping its pose in
the user's frame while the user walks a circle (``docs/following.md``,
``docs/accompanying.md``).
"""

import matplotlib.pyplot as plt

import designlab as dl

fol = dl.following
run = fol.simulate(fol.FollowTheLeaderConstDistance(desired_length=1.0),
                   fol.figure_eight(a=4.0), speed=0.5)  # fmt: skip
deviation = fol.normal_path_deviation(run.leader_xy, run.robot_xy)
print(f"mean normal path deviation {deviation.mean:.3f} m")

beside = fol.accompany(fol.walking_task("circle_cw"))
print(f"accompanying robot: settled error {beside.settled_error * 1e3:.1f} mm")

ax = run.plot()
ax.set_title("FTL-CD on a figure eight (Allan 2015)")
plt.gcf().set_layout_engine("constrained")
