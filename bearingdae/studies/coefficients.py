"""The bearing in a rotor model: stiffness tables over speed x radial load, and a ROSS bearing
element from them (docs/theory.md §18, user guide "A bearing in a ROSS rotor").

Stage: api (``stiffness``: one operating point) -> **studies** (many). Each point of the table
is one static solve (milliseconds), so the table is a plain loop in this process: the sweep
engine (studies/sweep) is built for dynamic runs, with workers, a run store and restarts, which
would cost more than the solves themselves.
"""

from __future__ import annotations

import numpy as np

#: ROSS's lateral axes from bearingdae's: y = the load line (ROSS's RollerBearingElement is
#: stiffer in y), z = the bearing axis, x = y × z = -(tangential direction)
ROSS_AXES = {"x": ("tangential", -1.0), "y": ("radial", 1.0)}


def coefficients(scene, speeds_rpm, loads_N, output=None, progress=None):
    """Stiffness matrices over inner-ring speed x radial load, as a Dataset (and a NetCDF file).

    Parameters
    ----------
    scene : Scene
        The bearing and its other operating values (:func:`load_scene`); its speed and radial
        load are replaced by each pair of the grid.
    speeds_rpm, loads_N : sequence of float
        Inner-ring speeds [r/min] (>= 0) and radial loads [N] (> 0).
    output : str or path-like, optional
        Write the Dataset to this NetCDF file (atomically).
    progress : callable, optional
        Called with one line of text per speed.

    Returns
    -------
    xarray.Dataset
        ``stiffness`` (speed_rpm, radial_load_N, dof, dof_2) as :func:`stiffness` gives it,
        its discretisation error ``stiffness_slice_error`` (the change with
        ``numerics.slices`` doubled; one warning for the table when a diagonal entry changes
        by more than 1 %), ``entry_units`` (dof, dof_2).

    Examples
    --------
    >>> from bearingdae import coefficients, load_scene
    >>> table = coefficients(load_scene("yang20_baseline"), [0, 6000], [400, 800])
    >>> k_rr = table.stiffness.sel(dof="radial", dof_2="radial")   # [N/m]
    """
    import warnings

    import xarray as xr

    from ..api import _check_scene
    from ..analysis.stiffness import (RESOLVED_CHANGE, StiffnessResolutionWarning,
                                     resolution_message, rotor_and_tilt, scene_stiffness)
    from ..scene import scene_from_dict

    _check_scene(scene, "coefficients")

    speeds = _grid(speeds_rpm, "speeds_rpm", "speed [r/min]", 0.0)
    loads = _grid(loads_N, "loads_N", "radial load [N]", 0.0, strict=True)
    K = err = None
    worst = 0.0
    for i, n in enumerate(speeds):
        for j, F in enumerate(loads):
            point = scene_from_dict(scene.source, {"operating.speed_rpm": float(n),
                                                   "operating.radial_load_N": float(F)})
            ds = scene_stiffness(point, warn=False)  # one warning for the table, below
            if K is None:
                K = np.empty((len(speeds), len(loads)) + ds.stiffness.shape)
                err = np.empty_like(K)
                first = ds
            K[i, j] = ds.stiffness.values
            err[i, j] = ds.stiffness_slice_error.values
            worst = np.maximum(worst, np.diag(err[i, j]) / np.abs(np.diag(K[i, j])))
        if progress is not None:
            progress(f"{n:g} r/min: {len(loads)} loads")
    if rotor_and_tilt(worst)[0].max() > RESOLVED_CHANGE:  # the entries a rotor model uses
        warnings.warn("over the table: " + resolution_message(scene.numerics.slices, worst),
                      StiffnessResolutionWarning, stacklevel=2)
    table = xr.Dataset(
        {"stiffness": (("speed_rpm", "radial_load_N", "dof", "dof_2"), K,
                       first.stiffness.attrs),
         "stiffness_slice_error": (("speed_rpm", "radial_load_N", "dof", "dof_2"), err,
                                   first.stiffness_slice_error.attrs),
         "entry_units": first.entry_units},
        coords={"speed_rpm": ("speed_rpm", speeds, {"units": "rpm", "long_name":
                                                    "inner-ring speed"}),
                "radial_load_N": ("radial_load_N", loads, {"units": "N", "long_name":
                                                           "radial load"}),
                "dof": first.dof, "dof_2": first.dof_2},
        attrs={"title": f"stiffness table: {scene.title}",
               "scene_toml": scene.to_toml(True),
               "method": "one static solve per point; K by the implicit-function theorem "
                         "(docs/theory.md §18)"})
    if output is not None:
        from ..results import save

        save(table, output)
    return table


def _grid(values, name, what, low, strict=False) -> np.ndarray:
    try:
        a = np.atleast_1d(np.asarray(values, dtype=float))
    except (TypeError, ValueError):
        raise ValueError(f"coefficients: {name}: expected numbers ({what}), got "
                         f"{values!r}") from None
    bad = ~np.isfinite(a) | ((a <= low) if strict else (a < low))
    if a.ndim != 1 or a.size == 0 or bad.any():
        rng = f"> {low:g}" if strict else f">= {low:g}"
        raise ValueError(f"coefficients: {name}: expected one or more finite values {rng} "
                         f"({what}), got {values!r}")
    if np.unique(a).size != a.size:
        raise ValueError(f"coefficients: {name}: every value once, got {values!r}")
    return np.sort(a)


def ross_coefficients(table, radial_load_N=None) -> dict:
    """ROSS's lateral stiffness coefficients [N/m] over frequency [rad/s] (the inner ring's
    speed) from a table of :func:`coefficients`, at ``radial_load_N`` (linear interpolation;
    optional when the table has one load). Axes: :data:`ROSS_AXES`, so kxx = k_tt,
    kyy = k_rr, kxy = -k_tr, kyx = -k_rt."""
    K = table.stiffness
    loads = table.radial_load_N.values
    if radial_load_N is None:
        if loads.size != 1:
            raise ValueError(f"to_ross: radial_load_N: the table has {loads.size} radial loads "
                             f"({loads.min():g}-{loads.max():g} N); give the bearing's load")
        K = K.isel(radial_load_N=0)
    else:
        F = float(radial_load_N)
        if not loads.min() <= F <= loads.max():
            raise ValueError(f"to_ross: radial_load_N: {F:g} N is outside the table's radial "
                             f"loads [{loads.min():g}, {loads.max():g}] N")
        K = K.interp(radial_load_N=F) if loads.size > 1 else K.isel(radial_load_N=0)
    out = {}
    for a, (da, sa) in ROSS_AXES.items():
        for b, (db, sb) in ROSS_AXES.items():
            out[f"k{a}{b}"] = sa * sb * K.sel(dof=da, dof_2=db).values
    if "axial" in K.dof.values:  # flanges: the axial stiffness is ROSS's kzz
        out["kzz"] = K.sel(dof="axial", dof_2="axial").values
    out["frequency"] = table.speed_rpm.values * np.pi / 30.0
    return out


#: the keywords of ``ross.BearingElement`` that to_ross passes on (the coefficients and
#: ``frequency`` it sets itself)
ROSS_KEYWORDS = ("tag", "n_link", "scale_factor", "color")


def _check_ross_arguments(n, damping_N_s_m, kwargs: dict) -> None:
    """ValueError or TypeError naming the argument, before ROSS sees any: ``n`` a node number
    >= 0, ``damping_N_s_m`` finite and >= 0, ``kwargs`` among :data:`ROSS_KEYWORDS` (ROSS
    would take a NaN or negative damping, and keep an unknown keyword, without a word)."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
        raise TypeError(f"to_ross: n = {n!r:.60}: expected the rotor node number, an integer "
                        ">= 0")
    number = isinstance(damping_N_s_m, (int, float, np.integer, np.floating)) \
        and not isinstance(damping_N_s_m, bool)
    if not (number and np.isfinite(damping_N_s_m) and damping_N_s_m >= 0.0):
        raise ValueError(f"to_ross: damping_N_s_m = {damping_N_s_m!r:.60}: expected a finite "
                         "damping >= 0 N s/m")
    unknown = sorted(set(kwargs) - set(ROSS_KEYWORDS))
    if unknown:
        raise TypeError(f"to_ross: unknown keyword(s) {', '.join(unknown)}; allowed: "
                        f"{', '.join(ROSS_KEYWORDS)} (the coefficients and frequency come "
                        "from the table)")


def to_ross(table, n, radial_load_N=None, damping_N_s_m=0.0, **kwargs):
    """A ``ross.BearingElement`` with the table's stiffness as functions of speed.

    Parameters
    ----------
    table : xarray.Dataset
        From :func:`coefficients` (or a file it wrote, opened with ``xarray.open_dataset``).
    n : int
        The rotor node of the bearing (ROSS's ``n``).
    radial_load_N : float, optional
        The bearing's radial load (interpolated linearly in the table); needed when the table
        has more than one load.
    damping_N_s_m : float, default 0
        Direct damping cxx = cyy [N s/m] (the quasi-static model has none).
    **kwargs
        Passed to ``ross.BearingElement``: ``tag``, ``n_link``, ``scale_factor``, ``color``
        (:data:`ROSS_KEYWORDS`; another is a TypeError).

    Returns
    -------
    ross.BearingElement
        kxx, kyy, kxy, kyx [N/m] at ``frequency`` = the table's speeds [rad/s]. ROSS's y is
        bearingdae's load line (``radial``), z the bearing axis, x = -tangential; the tilt
        stiffness has no place in ROSS's bearing element and is left out.
    """
    _check_ross_arguments(n, damping_N_s_m, kwargs)
    try:
        ross = import_quietly("ross")
    except ImportError:
        raise ImportError("to_ross needs ROSS: pip install 'bearingdae[rotor]' "
                          "(ross-rotordynamics)") from None
    k = ross_coefficients(table, radial_load_N)
    freq = k.pop("frequency")
    c = np.full(freq.shape, float(damping_N_s_m))
    zero = np.zeros(freq.shape)
    if freq.size == 1:  # one speed: constant coefficients
        k = {key: float(v[0]) for key, v in k.items()}
        c, zero, freq = float(c[0]), 0.0, None
    if "kzz" in k:
        kwargs = {"kzz": k["kzz"], "czz": zero, **kwargs}
    return ross.BearingElement(n=n, kxx=k["kxx"], kyy=k["kyy"], kxy=k["kxy"], kyx=k["kyx"],
                               cxx=c, cyy=c, cxy=zero, cyx=zero, frequency=freq, **kwargs)


def import_quietly(name: str):
    """``importlib.import_module(name)`` without what the import prints to stdout, from
    Python and from compiled code alike (file descriptor 1 is a temporary file meanwhile), and
    without its warnings that name REFPROP. ROSS 2.3 imports ccp, whose CoolProp prints a
    paragraph on REFPROP (an optional commercial library; CoolProp serves without it) to
    stdout, 16 lines, and warns that it switched to CoolProp: the bearing element needs none
    of it. When the import fails, what it printed goes to stderr with the error."""
    import contextlib
    import ctypes
    import importlib
    import io
    import os
    import sys
    import tempfile
    import warnings

    sys.stdout.flush()
    with tempfile.TemporaryFile() as tmp:
        saved = os.dup(1)
        py = io.StringIO()
        try:
            os.dup2(tmp.fileno(), 1)
            with contextlib.redirect_stdout(py), warnings.catch_warnings():
                warnings.filterwarnings("ignore", message=r"(?s).*REFPROP")
                return importlib.import_module(name)
        except BaseException:
            tmp.seek(0)
            sys.stderr.write(py.getvalue() + tmp.read().decode(errors="replace"))
            raise
        finally:
            try:
                ctypes.CDLL(None).fflush(None)  # the C library's buffer, before fd 1 returns
            except (OSError, AttributeError):
                pass
            os.dup2(saved, 1)
            os.close(saved)
