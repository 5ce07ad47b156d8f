"""``bearingdae run`` and ``bearingdae static``: one scene -> NetCDF (+ overview PNG).

Pipeline: the cli layer over the api (simulate, solve_static) and results (save).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from .common import _scene

def _static(args) -> int:
    from .. import solve_static
    from ..util.atomic import check_writable, refuse_aliases
    from .outputs import save_or_keep
    from ..scene import resolve_case
    from ..solvers.static import StaticConvergenceError

    scene = _scene(args)
    source = resolve_case(args.case)
    out = check_writable(args.output or Path(f"{source.stem}_static.nc"))
    refuse_aliases([("output", out)], [("scene file", source)])
    try:
        ds = solve_static(scene)
    except StaticConvergenceError as exc:
        print(f"bearingdae: static solver failure: {exc}; no file written", file=sys.stderr)
        return 1
    written, problems = save_or_keep(ds, out)
    q = ds.contact_force
    print(f"{scene.title}")
    print(f"  Newton iterations      {int(ds.newton_iterations)}")
    print(f"  relative residual      {float(ds.residual_max_relative):.2e}")
    print(f"  ring displacement      {ds.ring_displacement.sel(direction='radial').item() * 1e6:.3f} µm")
    print(f"  ring tilt              {ds.ring_tilt.sel(direction='radial').item() * 1e3:.4f} mrad")
    print(f"  max roller load inner  {q.sel(race='inner').sum('slice').max().item():.2f} N")
    print(f"  max slice pressure     {ds.contact_pressure.max().item() / 1e9:.3f} GPa")
    from ..analysis.engineering import summary_lines

    for line in summary_lines(ds):  # rating life, minimum λ
        print(f"  {line}")
    for line in problems:
        print(f"bearingdae: {line}", file=sys.stderr)
    if problems:
        return 1
    print(f"wrote {written}")
    return 0


def _refuse_aliases(out: Path, source: Path, args) -> None:
    """Before computing: no file ``run`` may write (the result, its checkpoint, overview PNG,
    partial result) is the scene file or another of them."""
    from ..util.atomic import refuse_aliases
    from ..run.checkpoint import checkpoint_path
    from .outputs import partial_path, png_path

    ckpt = checkpoint_path(out)
    outputs = [("output", out), ("checkpoint", ckpt), ("partial result", partial_path(out))]
    if not args.no_plot:
        outputs += [("overview PNG", png_path(out)),
                    ("partial overview PNG", png_path(partial_path(out)))]
    refuse_aliases(outputs, [("scene file", source)])  # (a resumed checkpoint is an output too)


def _where(da) -> tuple[float, str]:
    """The largest value of an extreme and where it is (roller, end or slice and race)."""
    i = np.unravel_index(int(np.nanargmax(da.values)), da.shape)
    at = {dim: da[dim].values[k] for dim, k in zip(da.dims, i)}
    where = ", ".join(f"{dim} {at[dim]}" for dim in da.dims)
    return float(da.values[i]), where


def _peak_lines(ds) -> list[str]:
    """The summary's peaks: the largest pocket force and slice pressure of the recorded
    window, where and when (from every solver step: results/extremes.py)."""
    lines = []
    for name, label, scale, unit, digits in (
            ("cage_force_max", "peak pocket force", 1.0, "N", 3),
            ("contact_pressure_max", "peak slice pressure", 1e-9, "GPa", 3)):
        if name not in ds or ds.sizes.get("time", 0) == 0 or np.all(np.isnan(ds[name])):
            continue
        value, where = _where(ds[name])
        i = np.unravel_index(int(np.nanargmax(ds[name].values)), ds[name].shape)
        when = float(ds[name + "_time"].values[i])
        lines.append(f"  {label:<24} {value * scale:.{digits}f} {unit} ({where}, "
                     f"t = {when:.6f} s)")
    if lines and "extremes_source" in ds.attrs:
        lines.append(f"  (peaks over {ds.attrs['extremes_source']})")
    # the mean peak per roller pass, with its error bar (analysis/statistics.py): what a
    # longer record converges to, unlike the largest value of the window
    from ..analysis.statistics import ATTRIBUTES, with_error

    parts = []
    for key, scale, unit, what in (("roller_pass_peak_cage_force_N", 1.0, "N", "pocket"),
                                   ("roller_pass_peak_contact_pressure_Pa", 1e-9, "GPa",
                                    "slice")):
        value, error = ATTRIBUTES[key]
        if value in ds:
            text = with_error(float(ds[value]) * scale,
                              float(ds[error]) * scale if error in ds else float("nan"))
            parts.append(f"{text} {unit} {what}")
    if parts:
        lines.append(f"  {'peak per roller pass':<24} {', '.join(parts)} (mean over the passes)")
    return lines


def negative_slip_note(slip: float, stderr: float) -> str:
    """What a negative cage slip means, for the summary (docs/user-guide.md, "Reading the
    summary")."""
    if not abs(slip) > 2.0 * stderr:  # (a NaN error bar: not judged either)
        return "(slip below 0 but within 2 standard errors of 0: not resolved from no slip)"
    return ("(negative slip: the cage runs faster than the rigid-body epicyclic speed, as "
            "when deformed contacts, tilt or flange friction change the rolling radii)")


#: a max skew at or above this fraction of the pocket limit c_p / L is "at the limit"
POCKET_LIMIT_FRACTION = 0.95


def pocket_limit_note(skew_rad: float, scene, scale: float, unit: str) -> str:
    """' (at the pocket limit ...)' when the largest skew reaches the angle at which a roller
    end meets the pocket bar, |θ| L/2 = c_p/2; else ''."""
    if not scene.physics.cage or not scene.bearing.roller_length_m > 0:
        return ""
    limit = scene.cage.pocket_clearance_m / scene.bearing.roller_length_m
    if not (limit > 0 and skew_rad >= POCKET_LIMIT_FRACTION * limit):
        return ""
    return (f" (at the pocket limit c_p/L = {limit * scale:.3f} {unit}: a roller end rests on "
            "its pocket bar, which stops the skew)")


def _flange_lines(path, digest) -> list[str]:
    """The summary's flange lines (a bearing with flanges): axial balance, friction power,
    the largest flange force and the catalogue's permissible axial load. The run's digest
    holds no flange series, so they are read from the written file ``path`` (a few numbers
    per roller and sample)."""
    if "flange_type" not in digest.attrs or path is None or not Path(path).is_file():
        return []
    import xarray as xr

    with xr.open_dataset(path, decode_timedelta=False) as ds:
        return _flange_lines_of(ds)


def _flange_lines_of(ds) -> list[str]:
    if "flange_force" not in ds or ds.sizes.get("time", 0) == 0:
        return []
    Fa = (float(ds.applied_axial_load.mean()) if "applied_axial_load" in ds  # a history: mean
          else float(ds["axial_load_N"]) if "axial_load_N" in ds else 0.0)
    lines = []  # each line from the variables it needs (output.variables may keep any)
    if "inner_flange_axial_force" in ds:
        carried = float(ds.inner_flange_axial_force.sum(("roller", "end")).mean())
        lines.append(f"  {'axial load (flanges)':<24} {Fa:.6g} N applied, {carried:.4g} N "
                     f"carried by the inner-ring flanges ({ds.attrs.get('flange_type', '')})")
    if "flange_friction_power" in ds:
        lines.append(f"  {'flange friction (mean)':<24} "
                     f"{float(ds.flange_friction_power.mean()):.4g} W")
    lines.append(f"  {'peak flange force':<24} {float(ds.flange_force.max()):.4g} N")
    if "permissible_axial_load_N" in ds:
        from ..analysis.flange import permissible_axial_load_text
        from ..analysis.result_variables import flat

        lines.append(f"  {'permissible axial load':<24} {permissible_axial_load_text(flat(ds))}")
    return lines


def _thermal_lines(path, scene) -> list[str]:
    """The summary's temperature and viscosity lines of a thermal run (physics.thermal =
    "steady"), read from the written file (a few numbers)."""
    if getattr(scene, "thermal", None) is None or path is None or not Path(path).is_file():
        return []
    import xarray as xr

    from ..results.thermal_variables import thermal_lines

    with xr.open_dataset(path, decode_timedelta=False) as ds:
        return thermal_lines(ds)


def _complete_run(out: Path, scene) -> str:
    """What ``out`` holds, when ``--resume`` finds it with no checkpoint beside it: a complete
    run of ``scene`` (its recorded scene is the same). Anything else is refused (ValueError:
    one line, exit 2): ``--resume`` continues a run, it never replaces a file."""
    import xarray as xr

    try:
        with xr.open_dataset(out, decode_times=False, decode_timedelta=False) as ds:
            recorded = ds.attrs.get("scene_toml")
            read = ds.attrs.get("load_file_sha256")  # the load file's contents it ran on
    except (OSError, ValueError, TypeError) as exc:
        raise ValueError(f"--resume: '{out}' exists and is not a result file ({exc}); nothing "
                         "to resume: drop --resume to replace it, or choose another -o") from None
    if recorded is None:
        raise ValueError(f"--resume: '{out}' is not a bearingdae run file (no 'scene_toml'); "
                         "nothing to resume: drop --resume to replace it, or choose another -o")
    if recorded != scene.to_toml(complete=True):
        raise ValueError(f"--resume: '{out}' holds a complete run of another scene (its "
                         "'scene_toml' differs from this one); nothing to resume: drop "
                         "--resume to replace it with this scene's run, or choose another -o")
    now = scene.operating.load_file_sha256
    if now is not None and read != now:
        raise ValueError(f"--resume: '{out}' is a complete run of this scene, but with other "
                         f"contents of the file '{scene.operating.load_file}' "
                         "('operating.load_file'); nothing to resume: drop --resume to run it "
                         "on the file as it is now")
    return "a complete run of this scene"


def _finish_figure(out: Path) -> int:
    """``--resume`` of a complete run: the overview PNG its run was killed before writing is
    drawn from the file (and a killed write's temporary removed); status 0, or 1 with one line
    if the PNG cannot be written."""
    from ..plots.plotting import overview
    from ..results.streamed_netcdf import open_streamed
    from ..util.atomic import remove_stale, write_failure
    from .outputs import png_path

    png = png_path(out)
    remove_stale(png)
    if png.exists():
        return 0
    try:
        with open_streamed(out) as full:
            if full.sizes.get("time", 0) > 1:
                print(f"wrote {overview(full, png)} (the overview was missing)")
    except OSError as exc:
        print(f"bearingdae: {write_failure(exc, png)} (the NetCDF result {out} is written)",
              file=sys.stderr)
        return 1
    return 0


def _run(args) -> int:
    from ..results.streamed_netcdf import open_streamed
    from ..api import simulate_to_file
    from ..util.atomic import check_writable
    from ..run.checkpoint import Checkpoint, checkpoint_path
    from ..run.integrate import compile_aside
    from .outputs import fallback_path, partial_path, png_path, remove_superseded
    from ..plots.plotting import overview
    from ..run.progress import announce_compiling, start_run
    from ..scene import resolve_case
    from ..solvers import from_name

    scene = _scene(args, {"numerics.until_steady": True} if args.until_steady else None)
    source = resolve_case(args.case)
    out = check_writable(args.output or Path(f"{source.stem}.nc"))
    for other in (checkpoint_path(out),) + (() if args.no_plot else (png_path(out),)):
        check_writable(other)
    _refuse_aliases(out, source, args)
    if args.resume and out.exists() and not checkpoint_path(out).exists():
        print(f"{out}: {_complete_run(out, scene)}; nothing to resume (without --resume the "
              "run starts again and replaces it)")
        return 0 if args.no_plot else _finish_figure(out)
    ckpt = Checkpoint(checkpoint_path(out), resume=args.resume,
                      every_samples=args.checkpoint_every)  # (checks --checkpoint-every)
    accuracy = (f"rtol {scene.dynamics.rtol:g}" if args.solver == "ida" else
                f"Newmark step {scene.dynamics.newmark_step_s:g} s")
    print(f"{scene.title}: {scene.bearing.rollers} rollers x {scene.numerics.slices} slices, "
          f"{accuracy}", flush=True)
    solver = from_name(args.solver)
    compile_aside(solver, scene)  # a cold start: part compiles in a child meanwhile
    status = 0
    from ..run.warmup_checkpoint import warmup_path

    warm = warmup_path(ckpt)  # a warm-up in blocks (until_steady, thermal) keeps its own
    if args.resume and not ckpt.path.exists():
        print(f"bearingdae: resuming the warm-up from {warm} (the record starts after it)"
              if warm.exists() else f"bearingdae: no checkpoint {ckpt.path}; starting from "
              "t = 0", file=sys.stderr)
    start_run()
    cold = announce_compiling()  # once (not again in simulate); None: the kernels are cached
    # the record streams to the file as the run goes (api.simulate_to_file): memory does not grow
    # with the recorded length; a block the target's folder cannot take moves the file to
    # the fallback path with what was written (cli/outputs.py)
    result = simulate_to_file(scene, out, solver=solver, progress=not args.no_progress,
                              checkpoint=ckpt, fallback=fallback_path)
    computed = __import__("time").monotonic()  # the record is written (streamed)
    if not result.success:
        # Ctrl-C ends every command with status 130; the samples are kept all the same
        status = 130 if result.message.startswith("interrupted by the user") else 1
        print(f"bearingdae: {'' if status == 130 else 'solver failure: '}{result.message}",
              file=sys.stderr)
        if ckpt.path.exists():
            print(f"bearingdae: checkpoint {ckpt.path} kept; continue with --resume",
                  file=sys.stderr)
        elif warm.exists():
            print(f"bearingdae: warm-up checkpoint {warm} kept; continue with --resume (the "
                  "record starts again after the warm-up)", file=sys.stderr)
        stop = "the interruption" if status == 130 else "the failure"
        if result.samples == 0:
            print(f"bearingdae: nothing was computed before {stop}; no file written",
                  file=sys.stderr)
            return status
        print(f"bearingdae: keeping the {result.samples} samples computed before {stop}",
              file=sys.stderr)
    if ckpt.write_error is not None:
        print(f"bearingdae: warning: the checkpoint could not be written "
              f"({ckpt.write_error.strerror or ckpt.write_error}): {ckpt.path}", file=sys.stderr)
    written, problems = result.path, list(result.problems)
    intended = out if result.success else partial_path(out)
    if problems:
        problems.append(f"the result is kept in '{written}'; move it where it belongs"
                        if written is not None else "the fallback copy failed as well")
        for line in problems:
            print(f"bearingdae: {line}", file=sys.stderr)
        if ckpt.path.exists() and ckpt.write_error is None:
            print(f"bearingdae: checkpoint {ckpt.path} holds the run: once '{out.parent}' has "
                  "room, the same command with --resume writes it without computing again",
                  file=sys.stderr)
        if written is None:
            return 1
        status = status or 1
        out = written
    elif status == 0:
        ckpt.discard()
        for stale in [*result.superseded, *remove_superseded(out)]:
            print(f"removed {stale} (an earlier incomplete run of {out.name})")
    else:
        out = intended
    from ..analysis.result_variables import flat
    from ..analysis.statistics import with_error

    nan = float("nan")
    s, ds = result.summary, result.digest  # the digest: extremes, cage speed, attributes
    st = __import__("json").loads(ds.attrs["solver_statistics"])
    print(f"  solver                   {st['residual_calls']} residual calls, "
          f"{st['jacobian_calls']} Jacobians, {st['wall_time_s']:.2f} s in the integrator")
    if "mean_cage_speed_rad_s" in s:
        # at zero speed the epicyclic cage speed is 0 and the slip ratio undefined: "n/a"
        # with the standard errors of the time means (analysis/statistics.py: the motion is
        # chaotic, a mean over the window is an estimate)
        epi, slip = s.get("epicyclic_cage_speed_rad_s"), s.get("cage_slip_ratio")
        a = flat(ds)
        cage = with_error(s["mean_cage_speed_rad_s"],
                          a.get("mean_cage_speed_stderr_rad_s", nan))
        slip_se = a.get("cage_slip_ratio_stderr", nan)
        slip_text = "n/a" if slip is None else with_error(100 * slip, 100 * slip_se) + " %"
        print(f"  mean cage speed          {cage} rad/s "
              f"(epicyclic {'n/a' if epi is None else f'{epi:.3f}'}, slip {slip_text})")
        if slip is not None and slip < 0.0:
            print(f"  {'':24} {negative_slip_note(slip, slip_se)}")
    if "steady_state_reached" in ds:
        a = flat(ds)
        print(f"  steady state             {'reached' if a['steady_state_reached'] else 'NOT reached'}"
              f" after {a['warmup_cage_revolutions_used']:.3g} warm-up cage revolutions "
              f"(last block change {a['steady_last_change']:+.2e} of epicyclic)")
    if "max_abs_skew_rad" in s:
        from ..plots.figure_common import SKEW_SCALE, SKEW_UNIT  # one unit in every command

        print(f"  max |skew|               {s['max_abs_skew_rad'] * SKEW_SCALE:.3f} {SKEW_UNIT}"
              + pocket_limit_note(s["max_abs_skew_rad"], scene, SKEW_SCALE, SKEW_UNIT))
        if "skew_rms_rad" in ds:
            a = flat(ds)
            rms = with_error(a["skew_rms_rad"] * SKEW_SCALE,
                             a.get("skew_rms_stderr_rad", nan) * SKEW_SCALE)
            print(f"  skew RMS                 {rms} {SKEW_UNIT}")
    if "max_abs_slip_m_s" in s:
        print(f"  max |slip velocity|      {s['max_abs_slip_m_s']:.4f} m/s")
    for line in _peak_lines(ds) + _flange_lines(out, ds) + _thermal_lines(out, scene):
        print(line)
    for line in result.engineering:  # rating life, minimum λ, power loss
        print(f"  {line}")
    if "ring_vibration_note" in ds.attrs:  # a dynamic ring sampled below its resonance
        print(f"  ring vibration           {ds.attrs['ring_vibration_note']}")
    print(f"wrote {out}")
    if not args.no_plot and ds.sizes.get("time", 0) > 1:
        png = png_path(out)
        try:
            if result.figure is not None:  # a short record: its variables were kept
                print(f"wrote {overview(result.figure, png)}")
            else:
                with open_streamed(out) as full:  # read as it plots, a small cache
                    print(f"wrote {overview(full, png)}")
        except OSError as exc:
            from ..util.atomic import write_failure

            print(f"bearingdae: {write_failure(exc, png)} (the NetCDF result {out} is "
                  "written)", file=sys.stderr)
            print(wall_time_line(cold is not None, computed))
            return status or 1
    print(wall_time_line(cold is not None, computed))
    return status


def wall_time_line(cold: bool, computed: float) -> str:
    """How long the command took, from the process's start (the interpreter and the imports
    included), in phases of one clock that add up to the total: to the run's first sample
    (on a first run, compiling the kernels: numba compiles every kernel the run needs before
    it), integrating and writing the record (streamed as it goes), the summary and the plot.
    ``computed``: the monotonic clock when the record was written."""
    import time

    from ..run.progress import first_sample_clock, process_start_clock

    start, now = process_start_clock(), time.monotonic()
    first = first_sample_clock()
    first = computed if first is None else min(max(first, start), computed)
    what = "compiling the kernels and setting up" if cold else "setting up"
    return (f"wall time {now - start:.1f} s since the command started: {first - start:.1f} s "
            f"{what} to the first sample, {computed - first:.1f} s integrating and writing "
            f"the record, {now - computed:.1f} s the summary and the plot")
