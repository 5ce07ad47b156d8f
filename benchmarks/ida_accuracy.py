"""Accuracy of IDA settings on the first quarter cage revolution against IDA at rtol 1e-9.

Run on demand: ``python benchmarks/ida_accuracy.py``. Prints the spread of two rtol-1e-9 runs
(SuperLU_MT vs the block-arrow solver) and, for both linear solvers and Jacobian-refresh
thresholds 0.25 / 0.15 / 0.2 / 0.12 at rtol 1e-6, the relative RMS errors of cage speed, orbit
speeds and skew angles. Results: docs/performance.md, "IDA's Jacobian refresh".
"""
import os
os.environ["OMP_NUM_THREADS"]="1"
import numpy as np
from bearingdae import load_scene
from bearingdae.system.model import build_model
from bearingdae.solvers.algebraic import initial_state
from bearingdae.solvers.ida import IDA
def run(rtol, **kw):
    sc=load_scene("yang20_baseline", {"numerics.rtol":rtol, "numerics.atol":rtol*1e-2})
    m=build_model(sc); y0,yp0=initial_state(m)
    T=2*np.pi/m.final_cage_speed(); t=np.linspace(0,T*0.25,26)
    s=IDA(**kw).integrate(m,y0,yp0,t)
    F=[m.layout.unpack(y*m.scale) for y in s.y]
    return dict(cage=np.array([f[1][1] for f in F]), orbit=np.array([f[0][:,1] for f in F]), skew=np.array([f[0][:,3] for f in F]))
ref=run(1e-9, linsolver="sparse", delta_cj_lsetup=0.25)
ref2=run(1e-9, linsolver="blockarrow")
def rr(a,b): return np.sqrt(np.mean((a-b)**2)/np.mean(b**2))
print("ref vs ref2", {q:"%.1e"%rr(ref2[q],ref[q]) for q in ref})
for ls in ("sparse","blockarrow"):
  for d in (0.25,0.15,0.2,0.12):
    r=run(1e-6, linsolver=ls, delta_cj_lsetup=d)
    print(ls,d,{q:"%.1e"%rr(r[q],ref[q]) for q in ref})
