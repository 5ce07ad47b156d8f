"""IDA on the default run with each linear solver: CPU, steps, residual calls, Jacobians.

Run on demand: ``python benchmarks/bench_linsolvers.py T_END [CASE.toml] [LINSOLVER ...]``
(default: the baseline, sparse then blockarrow; T_END 0.2634 is the whole default run, 1 + 3
cage revolutions; e.g. ``... 0.1 cases/paper/harris36_5000rpm.toml blockarrow sparse`` for
Z = 36, after an untimed warm-up call of each). One process runs the
solvers in the order given (alternate the order between processes: the machine is shared).
Results: docs/performance.md, "Linear algebra".
"""
import os, sys, time
os.environ["OMP_NUM_THREADS"]="1"
import numpy as np
from bearingdae import load_scene
from bearingdae.system.model import build_model
from bearingdae.solvers.algebraic import initial_state
from bearingdae.solvers.ida import IDA
t_end=float(sys.argv[1]); args=sys.argv[2:]
case="yang20_baseline"
if args and args[0].endswith(".toml"):
    case=args.pop(0)
ls=args or ["sparse","blockarrow"]
m=build_model(load_scene(case)); y0,yp0=initial_state(m)
for l in set(ls):  # warm-up: load (or compile) each solver's callbacks, untimed
    IDA(linsolver=l).integrate(m,y0,yp0,np.linspace(0,1e-4,3))
t=np.linspace(0,t_end,int(t_end/3.3e-4)+2)
out={}
for l in ls:
    c=time.process_time(); s=IDA(linsolver=l).integrate(m,y0,yp0,t); c=time.process_time()-c
    out[l]=s
    print(l, s.success, s.message[:80], f"cpu {c:.2f}", s.stats["steps"], s.stats["residual_calls"], s.stats["jacobian_calls"], s.stats["nonlinear_convergence_failures"])
if len(ls)==2:
    a,b=out[ls[0]],out[ls[1]]
    k=min(len(a.y),len(b.y))
    print("max rel diff first 5 samples", (np.abs(a.y[:5]-b.y[:5])/(1e-6+np.abs(a.y[:5]))).max())
