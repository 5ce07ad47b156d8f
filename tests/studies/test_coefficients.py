"""Stiffness tables over speed x load (bearingdae.coefficients, ``bearingdae coefficients``) and
the bearing as a ROSS element (bearingdae.to_ross): axes, units, and a rotor's critical speeds
against the same rotor on ROSS's closed-form roller bearings."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bearingdae import coefficients, load_scene, stiffness


@pytest.fixture(scope="module")
def table():
    return coefficients(load_scene("yang20_baseline"), [0.0, 6000.0, 12000.0], [400.0, 800.0])


def test_table_holds_each_points_matrix_with_units(table, tmp_path):
    """Each (speed, load) entry is the matrix of the scene at that point; the file keeps the
    coordinates and units."""
    assert table.stiffness.dims == ("speed_rpm", "radial_load_N", "dof", "dof_2")
    point = stiffness(load_scene("yang20_baseline", {"operating.speed_rpm": 6000.0,
                                                     "operating.radial_load_N": 400.0}))
    np.testing.assert_allclose(table.stiffness.sel(speed_rpm=6000.0, radial_load_N=400.0),
                               point.stiffness, rtol=1e-12)
    path = tmp_path / "k.nc"
    coefficients(load_scene("yang20_baseline"), [0.0], [800.0], output=path)
    with xr.open_dataset(path) as ds:
        assert ds.speed_rpm.attrs["units"] == "rpm" and ds.radial_load_N.attrs["units"] == "N"
        assert ds.entry_units.sel(dof="radial", dof_2="radial") == "N/m"
        assert "entry_units" in ds.stiffness.attrs["units"]


def test_bad_grid_is_one_line():
    with pytest.raises(ValueError, match="loads_N.*> 0"):
        coefficients(load_scene("yang20_baseline"), [0.0], [0.0])


def test_cli_writes_the_table(tmp_path, capsys):
    from bearingdae.cli import main

    out = tmp_path / "c.nc"
    assert main(["coefficients", "yang20_baseline", "--speeds", "0", "3000", "--loads", "800",
                 "-o", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        assert ds.stiffness.shape == (2, 1, 4, 4)
    assert "k_rr" in capsys.readouterr().out


def synthetic_table(krr, ktt, krt, ktr, speeds=(0.0, 6000.0)):
    """A table with a known anisotropic, non-symmetric radial block at every speed
    (entries [N/m], each row of speeds scaled by 1 + speed / 6000)."""
    dofs = ["radial", "tangential", "tilt_radial", "tilt_tangential"]
    K = np.zeros((len(speeds), 1, 4, 4))
    for i, n in enumerate(speeds):
        K[i, 0, :2, :2] = np.array([[krr, krt], [ktr, ktt]]) * (1.0 + n / 6000.0)
        K[i, 0, 2:, 2:] = np.eye(2)
    return xr.Dataset({"stiffness": (("speed_rpm", "radial_load_N", "dof", "dof_2"), K)},
                      coords={"speed_rpm": list(speeds), "radial_load_N": [800.0],
                              "dof": dofs, "dof_2": dofs})


def test_ross_axes_of_a_known_anisotropic_case():
    """ROSS's y is the load line, x = -tangential: kxx = k_tt, kyy = k_rr, kxy = -k_tr,
    kyx = -k_rt [N/m], at frequency = the inner ring's speed [rad/s]."""
    ross = pytest.importorskip("ross", reason="ROSS not installed: pip install '.[rotor]'")
    from bearingdae import to_ross

    b = to_ross(synthetic_table(3e8, 1e8, 2e7, -5e6), n=0)
    assert isinstance(b, ross.BearingElement)
    for w, f in ((0.0, 1.0), (6000.0 * np.pi / 30.0, 2.0), (3000.0 * np.pi / 30.0, 1.5)):
        np.testing.assert_allclose(b.K(w)[:2, :2], f * np.array([[1e8, 5e6], [-2e7, 3e8]]),
                                   rtol=1e-9)


def rotor(bearings):
    """A steel shaft (Ø 30 mm, 6 x 50 mm) with two disks (Ø 150 mm, 30 mm wide) at nodes 2
    and 4, on bearings at nodes 0 and 6."""
    import ross as rs

    steel = rs.Material(name="bearingdae_steel", rho=7850.0, E=207e9, G_s=79.6e9)
    shaft = [rs.ShaftElement(L=0.05, idl=0.0, odl=0.03, material=steel, n=i) for i in range(6)]
    disks = [rs.DiskElement.from_geometry(n=k, material=steel, width=0.03, i_d=0.03,
                                          o_d=0.15) for k in (2, 4)]
    return rs.Rotor(shaft, disks, bearings)


def test_rotor_on_bearingdae_bearings_against_rosss_closed_form_bearing():
    """Two yang20 bearings at 800 N each: the rotor's first two natural frequencies at rest
    and at 12 000 r/min within 5 % of the same rotor on ROSS's RollerBearingElement (Friswell's
    empirical k ∝ Z^0.9 l^0.8 F^0.1), and equal to a rotor on constant BearingElements typed
    from bearingdae.stiffness at that speed (the mapping, 1e-6)."""
    rs = pytest.importorskip("ross", reason="ROSS not installed: pip install '.[rotor]'")
    from bearingdae import to_ross

    table = coefficients(load_scene("yang20_baseline"), [0.0, 12000.0], [800.0])
    ours = rotor([to_ross(table, n=k) for k in (0, 6)])
    closed = rotor([rs.RollerBearingElement(n=k, n_rollers=20, l_rollers=25.5e-3, fs=800.0,
                                            alpha=0.0) for k in (0, 6)])
    for n in (0.0, 12000.0):
        w = n * np.pi / 30.0
        K = stiffness(load_scene("yang20_baseline", {"operating.speed_rpm": n,
                                                     "operating.radial_load_N": 800.0}))
        k = K.stiffness.sel(dof=["radial", "tangential"], dof_2=["radial", "tangential"])
        typed = rotor([rs.BearingElement(n=j, kxx=float(k[1, 1]), kyy=float(k[0, 0]),
                                         kxy=-float(k[1, 0]), kyx=-float(k[0, 1]), cxx=0.0)
                       for j in (0, 6)])
        f_ours = ours.run_modal(speed=w, num_modes=8).wn[:2]
        f_typed = typed.run_modal(speed=w, num_modes=8).wn[:2]
        f_closed = closed.run_modal(speed=w, num_modes=8).wn[:2]
        np.testing.assert_allclose(f_ours, f_typed, rtol=1e-6)
        np.testing.assert_allclose(f_ours, f_closed, rtol=0.05)
        # the tangential direction (ROSS x) is softer in bearingdae (a clearance's narrow
        # load zone) than the closed form's fixed ratio kxx/kyy: its mode is lower
        assert f_ours[0] < f_closed[0]


def test_import_quietly_holds_back_what_an_import_prints(tmp_path, monkeypatch, capfd):
    """Reference: modules typed here that print as ROSS's ccp does at import, from Python and
    straight to file descriptor 1 (as CoolProp's compiled code prints), and warn about
    REFPROP; a failing one shows its prints on stderr."""
    from bearingdae.studies.coefficients import import_quietly

    (tmp_path / "noisy_import.py").write_text(
        "import os, warnings\n"
        "for k in range(9):\n"
        "    print('Could not load REFPROP (path', k, ')')\n"
        "os.write(1, b'Neither found in current location nor found in system PATH.\\n')\n"
        "warnings.warn('/x/librefprop.so.\\nREFPROP not configured. Switching to HEOS.')\n"
        "VALUE = 42\n")
    (tmp_path / "broken_import.py").write_text("print('why it broke')\nraise ImportError('no')\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = import_quietly("noisy_import")
    out = capfd.readouterr()
    assert module.VALUE == 42 and out.out == "" and not caught, (out, caught)
    with pytest.raises(ImportError):
        import_quietly("broken_import")
    out = capfd.readouterr()
    assert out.out == "" and "why it broke" in out.err


@pytest.mark.parametrize("kwargs, error, words", [
    ({"damping_N_s_m": float("nan")}, ValueError, "damping_N_s_m = nan"),
    ({"damping_N_s_m": -1.0}, ValueError, "damping_N_s_m = -1.0"),
    ({"damping_N_s_m": float("inf")}, ValueError, "finite damping >= 0"),
    ({"damping_N_s_m": "10"}, ValueError, "damping_N_s_m = '10'"),
    ({"colour": "red"}, TypeError, "unknown keyword(s) colour"),
    ({"kxx": 1.0}, TypeError, "unknown keyword(s) kxx"),
    ({"n": -1}, TypeError, "n = -1"),
    ({"n": 1.5}, TypeError, "n = 1.5"),
])
def test_to_ross_refuses_bad_arguments_before_ross_sees_them(monkeypatch, kwargs, error, words):
    """NaN or negative damping and unknown keywords went on to ROSS, which kept them without
    a word. Checked before ROSS is imported (it need not be installed for the refusal)."""
    import builtins

    from bearingdae import to_ross

    real = builtins.__import__

    def no_ross(name, *a, **kw):
        if name == "ross" or name.startswith("ross."):
            raise AssertionError("ROSS reached")
        return real(name, *a, **kw)

    monkeypatch.setattr(builtins, "__import__", no_ross)
    args = {"n": 0, **kwargs}
    with pytest.raises(error) as info:
        to_ross(synthetic_table(3e8, 1e8, 2e7, -5e6), **args)
    assert words in str(info.value) and len(str(info.value).splitlines()) == 1
