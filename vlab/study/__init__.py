"""Studies over many runs of a scene: content-hash cache, parameter sweeps on Dask, the
accuracy-against-time (cost) study and the per-run accuracy estimate."""
