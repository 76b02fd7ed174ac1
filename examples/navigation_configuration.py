"""Navigation: the new virtual force field among walking people.

Zeng 2011's Configuration 1 (Ch. 5-6): the robot crosses a room while a person walks
across its path; the new VFF with the thesis's optimal gains, and the thesis's criteria
of the run (arrival time, smallest distances, ``docs/navigation.md``).
"""

import matplotlib.pyplot as plt

import designlab as dl

nav = dl.navigation
run = nav.simulate(nav.configuration(1), nav.OPTIMAL_GAINS)
print(run)
print(run.summary(max_rows=4))

ax = run.plot()
ax.set_title("Configuration 1: the robot's path and the person's")
plt.gcf().set_layout_engine("constrained")
