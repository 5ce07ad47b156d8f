"""Studies built on many runs: work-precision (error against wall time) and, in time, sweeps."""
