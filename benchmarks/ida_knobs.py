"""IDA's optional step controls on the baseline: steps, residual calls, Jacobians, CPU.

Run on demand (one configuration per process; counts are deterministic, CPU is noisy):
    python benchmarks/ida_knobs.py T_END [IDASetName=value ...]
e.g. ``python benchmarks/ida_knobs.py 0.2634 IDASetDeltaCjLSetup=0.25`` (the whole default run
with SUNDIALS' own refresh threshold) or ``... 0.02 IDASetEtaMax=5``. Each ``IDASet*`` named
is called on the session's IDA memory after IDA's own set-up (a double argument; an int for
IDASetMaxOrd / IDASetMaxNonlinIters; IDASetEtaFixedStepBounds gets (0, value)). Prints one
JSON line: the knobs, success, final time, integration CPU and IDA's statistics.
Results: docs/performance.md, "IDA's Jacobian refresh".
"""
import os, sys, time, json, ctypes as C
os.environ["OMP_NUM_THREADS"]="1"
import numpy as np
from bearingdae import load_scene
from bearingdae.system.model import build_model
from bearingdae.solvers.algebraic import initial_state
from bearingdae.solvers.ida import IDA
from bearingdae.solvers.sundials import session as S
t_end=float(sys.argv[1]); knobs={}
for a in sys.argv[2:]:
    k,v=a.split("="); knobs[k]=float(v)
orig=S.Session._create
def _create(self,*a,**k):
    orig(self,*a,**k)
    ida=self.api.libraries["ida"]
    for name,val in knobs.items():
        f=getattr(ida,name,None)
        if name=="SUNLinSol_SuperLUMTSetOrdering":
            f=getattr(self.api.libraries["sunlinsolsuperlumt"],name)
            f.argtypes=[C.c_void_p,C.c_int]; r=f(self._ptrs["LS"],int(val))
        elif name=="IDASetEtaFixedStepBounds":
            f.argtypes=[C.c_void_p,C.c_double,C.c_double]; r=f(self.mem,0.0,val)
        elif name in ("IDASetMaxOrd","IDASetMaxNonlinIters"):
            f.argtypes=[C.c_void_p,C.c_int]; r=f(self.mem,int(val))
        else:
            f.argtypes=[C.c_void_p,C.c_double]; r=f(self.mem,val)
        assert r==0,(name,r)
S.Session._create=_create
m=build_model(load_scene("yang20_baseline")); y0,yp0=initial_state(m)
t_out=np.linspace(0,t_end,int(t_end/3.3e-4)+2)
c=time.process_time(); sol=IDA().integrate(m,y0,yp0,t_out); cpu=time.process_time()-c
st=sol.stats
print(json.dumps(dict(knobs=knobs,ok=sol.success,t=float(sol.t[-1]),cpu=round(cpu,2),**{k:v for k,v in st.items() if not isinstance(v,(list,dict))},
  cage=float(np.mean(sol.y[-50:, :]) ) )))
