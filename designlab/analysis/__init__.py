"""Domain-independent analysis: samples, the chunked sweep engine, executors, sensitivity.

* :mod:`~designlab.analysis.points` - point sources (points drawn a chunk at a time);
* :mod:`~designlab.analysis.sampling` - lists, grids, Latin hypercubes, Sobol and Saltelli samples;
* :mod:`~designlab.analysis.sweep` - evaluating points in chunks through a result store;
* :mod:`~designlab.analysis.executors` - serial, process and Dask executors;
* :mod:`~designlab.analysis.sensitivity` - elasticity, one-at-a-time, range and Sobol tables.

See docs/sweeps.md.
"""
