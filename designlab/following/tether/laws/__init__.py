"""The tether follower laws: one module per law, one registry (Allan 2015 Sec. 2.3, Ch. 4).

==========================  =================================================================
module                      holds
==========================  =================================================================
``base``                    the face every law shows (:class:`~.base.TetherController`) and
                            the shared declarations (l_d, gains, buffer settings)
``pseudo_joystick``         Pseudo-Joystick (Sec. 2.3.1, mode 10)
``follow_the_leader``       Follow the Leader (Sec. 2.3.2, mode 20)
``constant_distance``       Follow the Leader with Constant Distance (Sec. 2.3.3, mode 21)
``side_joystick``           Side Joystick (Sec. 4.2.2, mode 30)
``side_tracking``           Side Tracking (Sec. 4.2.4, mode 31)
``front_joystick``          Front Joystick (Sec. 4.3.2, mode 40)
``front_vel_joystick``      FrontVelJoystick (App. C mode 42)
``brake``                   Brake mode and its selector (Sec. 4.4)
``registry``                :data:`~.registry.LAWS`: every law by name, one line each
==========================  =================================================================

A new law is one module here plus one line in ``registry``; the engines
(simulation, batches, odometry, stability, linear analysis, tuning, sweeps),
the study kinds and the reports ask the law or the registry, never its name.
The law modules do not import each other and the engines import none of them
(import-linter contracts in ``pyproject.toml``).
"""
