"""The kernel's parameter vector P: its entries' names in order and the offsets the compiled
code reads them at (system layer). system/model.py fills P in this order; each optional
effect's entries follow the core's, from its own module's name list.
"""

from __future__ import annotations

from .flange import FLANGE_PARAM_NAMES, P_FLANGE_OFFSET
from .mixed import MIXED_PARAM_NAMES
from .rolling_resistance import RR_PARAM_NAMES
from .whirl import WHIRL_PARAM_NAMES

PARAM_NAMES = (
    "Z", "Rm", "Ri", "Ro", "r", "L", "mass", "Ix", "It", "Ic", "clearance", "K_w", "eps_c",
    "w", "Rp_in", "Rp_out", "eta",
    "tr_law", "tr_A", "tr_B", "tr_C", "tr_D", "tr_alt", "tr_v",
    "sr_A", "sr_B", "sr_C", "sr_D", "sr_u0",
    "slip_paper", "orbit_paper", "gyro", "has_cage", "has_drag",
    "cp", "Kp", "cdamp", "mu_c", "eps_p", "f_p", "spin_scale", "spin_f",
    "rho_e", "mu_oil", "cage_ri", "cage_ro",
    "unb", "unb_phase", "ring_dyn", "ring_m", "ring_I", "sup_k", "sup_c",
) + FLANGE_PARAM_NAMES + WHIRL_PARAM_NAMES + RR_PARAM_NAMES + MIXED_PARAM_NAMES
(P_Z, P_RM, P_RI, P_RO, P_R, P_L, P_MASS, P_IX, P_IT, P_IC, P_CL, P_KW, P_EPS, P_W, P_RPI,
 P_RPO, P_ETA, P_TLAW, P_TA, P_TB, P_TC, P_TD, P_TALT, P_TV, P_SRA, P_SRB, P_SRC, P_SRD,
 P_SRU0, P_SLIP, P_ORBIT, P_GYRO, P_CAGE, P_DRAG, P_CP, P_KP, P_CD, P_MUC, P_EPSP, P_FP,
 P_SPIN, P_SPINF, P_RHO, P_MUO, P_CRI, P_CRO, P_UNB, P_UNBPH, P_RDYN, P_RMASS, P_RINER, P_SUPK,
 P_SUPC) = range(len(PARAM_NAMES) - len(FLANGE_PARAM_NAMES) - len(WHIRL_PARAM_NAMES)
                 - len(RR_PARAM_NAMES) - len(MIXED_PARAM_NAMES))
P_FL = P_SUPC + 1  #: the flange parameters P[P_FL:] (system/flange.py), P[P_FL] > 0.5: flanges
assert P_FL == P_FLANGE_OFFSET
#: the cage-whirl parameters P[P_WH:] (system/whirl.py), P[P_WH] > 0.5: the cage centre moves
P_WH = P_FL + len(FLANGE_PARAM_NAMES)
#: the rolling-resistance parameters P[P_RR:] (system/rolling_resistance.py), P[P_RR] > 0.5: on
P_RR = P_WH + len(WHIRL_PARAM_NAMES)
#: the mixed-lubrication parameters P[P_MX:] (system/mixed.py), P[P_MX] > 0.5: mixed
P_MX = P_RR + len(RR_PARAM_NAMES)
