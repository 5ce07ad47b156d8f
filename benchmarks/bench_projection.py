"""Projection of a run's samples onto the algebraic equations: compiled projector vs static Newton.

Run on demand: ``python benchmarks/bench_projection.py`` — integrates 601 samples of the
baseline's first 13 ms, then projects them with ``AlgebraicProjector`` and with
``project_algebraic`` (the numpy static Newton); prints ms per sample, the largest difference
of the projected states (scaled units), Newton iterations, fallbacks and the largest algebraic
residual left. Results: docs/performance.md, "Projection of the samples".
"""
import os, time
os.environ["OMP_NUM_THREADS"]="1"
import numpy as np
from bearingdae import load_scene
from bearingdae.system.model import build_model
from bearingdae.solvers.algebraic import initial_state, project_algebraic, AlgebraicProjector
from bearingdae.solvers.ida import IDA
sc=load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions":0.0,"numerics.cage_revolutions":0.2,"numerics.samples_per_cage_revolution":3000})
m=build_model(sc); y0,yp0=initial_state(m)
t_out=np.linspace(0,0.013,601)
sol=IDA().integrate(m,y0,yp0,t_out)
P=AlgebraicProjector(m)
t=time.perf_counter(); new=[P(tk,y) for tk,y in zip(sol.t,sol.y)]; tn=time.perf_counter()-t
t=time.perf_counter(); old=[project_algebraic(m,tk,y) for tk,y in zip(sol.t,sol.y)]; to=time.perf_counter()-t
d=max(np.abs(a[0]-b[0]).max() for a,b in zip(new,old))
print(f"new {tn/len(new)*1e3:.3f} ms/sample, old {to/len(old)*1e3:.3f}; max scaled diff {d:.2e}; its new {sum(a[1] for a in new)} old {sum(b[1] for b in old)} fallbacks {P.fallbacks}")
alg=P.alg
r=max(np.abs(m.residual(tk,a[0],np.zeros(m.size))[alg]).max() for tk,a in zip(sol.t,new))
r2=max(np.abs(m.residual(tk,a[0],np.zeros(m.size))[alg]).max() for tk,a in zip(sol.t,old))
print(f"max |F_a| new {r:.2e} old {r2:.2e}")
