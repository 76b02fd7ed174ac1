"""Domain-independent analysis: samples, the sweep engine and its store, executors, sensitivity.

* :mod:`~designlab.analysis.points` - point sources (points drawn a chunk at a time);
* :mod:`~designlab.analysis.sampling` - lists, grids, Latin hypercubes, Sobol and Saltelli samples;
* :mod:`~designlab.analysis.engine` - the sweep engine: points evaluated in chunks through a
  result store (:mod:`~designlab.analysis.keys`: what identifies a chunk;
  :mod:`~designlab.analysis.columns`: points and results as columns);
* :mod:`~designlab.analysis.store` - the SQLite result store, repaired when damaged
  (:mod:`~designlab.analysis.salvage`: rows read from a damaged file's pages);
* :mod:`~designlab.analysis.executors` - serial, process and Dask executors;
* :mod:`~designlab.analysis.sensitivity` - elasticity, one-at-a-time, range and Sobol tables.

See docs/sweeps.md.
"""
