"""
Bearing stiffness for a rotor model, and a Campbell diagram with ROSS
=====================================================================

The quasi-static stiffness matrix of the paper's bearing (yang20: 20 rollers, 10 µm diametral
clearance) over radial load and inner-ring speed (docs/theory.md §18): k_rr along the load
line, k_tt across it. Then the table as two ROSS bearing elements under a steel shaft with two
disks, against the same rotor on ROSS's closed-form roller bearing (user guide, "A bearing in a
ROSS rotor"). The ROSS part runs when ROSS is installed (``pip install ".[rotor]"``).
"""

import warnings

import matplotlib.pyplot as plt
import numpy as np

from bearingdae import coefficients, load_scene

speeds = np.array([0.0, 4000.0, 8000.0, 12000.0])
loads = np.array([200.0, 400.0, 800.0, 1600.0, 3200.0])
# 40 slices: the paper's 10 leave the stiffness unresolved. The table's warning on the
# discretisation is printed below instead, entry by entry.
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    table = coefficients(load_scene("yang20_baseline", {"numerics.slices": 40}), speeds, loads)
rel = table.stiffness_slice_error / abs(table.stiffness)
for dof in ("radial", "tangential"):
    print(f"k_{dof[0]}{dof[0]}: change with the slices doubled up to "
          f"{float(rel.sel(dof=dof, dof_2=dof).max()):.1%} over the table")
k = table.stiffness
k_rr = k.sel(dof="radial", dof_2="radial")
k_tt = k.sel(dof="tangential", dof_2="tangential")
for n in speeds:
    print(f"{n:6.0f} r/min: k_rr {float(k_rr.sel(speed_rpm=n, radial_load_N=800)):.4g} N/m, "
          f"k_tt {float(k_tt.sel(speed_rpm=n, radial_load_N=800)):.4g} N/m at 800 N")

# %%
# Left: against load at each speed. With clearance the load zone widens as the load grows, so
# k_rr rises faster than the F^0.1 of a zero-clearance line contact (dotted), and k_tt,
# carried by the few rollers off the load line, much faster. Right: against speed at 800 N.

fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4.2), layout="constrained")
for n in speeds:
    line, = ax0.loglog(loads, k_rr.sel(speed_rpm=n), "o-", label=f"k_rr, {n:.0f} r/min")
    ax0.loglog(loads, k_tt.sel(speed_rpm=n), "s--", color=line.get_color(),
               label=f"k_tt, {n:.0f} r/min")
ref = float(k_rr.sel(speed_rpm=0, radial_load_N=loads[0]))
ax0.loglog(loads, ref * (loads / loads[0]) ** 0.1, "k:", label="∝ F^0.1")
ax0.set(xlabel="radial load [N]", ylabel="stiffness [N/m]", title="against load")
ax0.legend(fontsize=7, ncol=2)
for F in (400.0, 800.0, 1600.0):
    ax1.plot(speeds, k_rr.sel(radial_load_N=F) / k_rr.sel(radial_load_N=F, speed_rpm=0),
             "o-", label=f"k_rr, {F:.0f} N")
ax1.set(xlabel="inner-ring speed [r/min]", ylabel="k_rr / k_rr at rest",
        title="against speed (centrifugal force)")
ax1.legend()
plt.show()

# %%
# The two bearings in a rotor: a steel shaft (Ø 30 mm, 6 elements of 50 mm) with two disks
# (Ø 150 mm, 30 mm wide) at nodes 2 and 4, bearings at nodes 0 and 6, each at 800 N. ROSS's
# y axis is the load line, x = -tangential (kxx = k_tt, kyy = k_rr). The closed-form
# element (Friswell's k ∝ Z^0.9 l^0.8 F^0.1, kxx a fixed fraction of kyy) is stiffer across
# the load line, so the mode in x is higher on it.

try:
    with warnings.catch_warnings():  # ROSS's thermodynamics dependency warns on import
        warnings.simplefilter("ignore")
        import ross as rs
except ImportError:
    rs = None
    print("ROSS is not installed (pip install '.[rotor]'): no Campbell diagram")

if rs is not None:
    from bearingdae import to_ross

    steel = rs.Material(name="bearingdae_steel", rho=7850.0, E=207e9, G_s=79.6e9)
    shaft = [rs.ShaftElement(L=0.05, idl=0.0, odl=0.03, material=steel, n=i) for i in range(6)]
    disks = [rs.DiskElement.from_geometry(n=j, material=steel, width=0.03, i_d=0.03,
                                          o_d=0.15) for j in (2, 4)]
    rotors = {
        "bearingdae": rs.Rotor(shaft, disks, [to_ross(table, n=j, radial_load_N=800.0)
                                               for j in (0, 6)]),
        "ROSS closed form": rs.Rotor(shaft, disks, [rs.RollerBearingElement(
            n=j, n_rollers=20, l_rollers=25.5e-3, fs=800.0, alpha=0.0) for j in (0, 6)]),
    }
    w = np.linspace(0.0, 12000.0, 7) * np.pi / 30.0
    fig, ax = plt.subplots(figsize=(7, 4.5), layout="constrained")
    for (name, rotor), style in zip(rotors.items(), ("-", "--")):
        wd = rotor.run_campbell(w, frequencies=4).wd / (2 * np.pi)  # (speed, mode) [Hz]
        for i in range(wd.shape[1]):
            ax.plot(w * 30 / np.pi, wd[:, i], style, color=f"C{i}",
                    label=name if i == 0 else None)
        print(f"{name}: natural frequencies at rest {np.round(wd[0], 1)} Hz")
    ax.plot(w * 30 / np.pi, w / (2 * np.pi), "k:", label="1X")
    ax.set(xlabel="speed [r/min]", ylabel="damped natural frequency [Hz]",
           title="Campbell diagram: two yang20 bearings at 800 N")
    ax.legend()
    plt.show()
