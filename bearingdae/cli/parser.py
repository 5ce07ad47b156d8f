"""The argument parser of the ``bearingdae`` program: every command and its options.

Pipeline: the cli layer (above studies). Built on first use only (argparse is imported inside
:func:`_parser`), so that ``import bearingdae.cli`` stays cheap.
"""

from __future__ import annotations

from pathlib import Path

DEFAULT_CASE = "yang20_baseline"


def _case_arguments(p: argparse.ArgumentParser, default_output: str) -> None:
    """CASE, -o/--output and --set, shared by the commands that run one scene."""
    p.add_argument("case", nargs="?", default=DEFAULT_CASE,
                   help=f"scene TOML file or bundled case name (default: {DEFAULT_CASE})")
    p.add_argument("-o", "--output", type=Path,
                   help=f"NetCDF file to write (default: {default_output})")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a scene key, e.g. --set operating.radial_load_N=400")


def _parser() -> argparse.ArgumentParser:
    import argparse  # here, not at the top: `import bearingdae.cli` stays cheap (see main)

    p = argparse.ArgumentParser(
        prog="bearingdae",
        description="Cylindrical roller bearing dynamics (skid, skew, cage) with SUNDIALS IDA.",
    )
    p.add_argument("--version", action="store_true", help="print the version and exit")
    sub = p.add_subparsers(dest="command")

    r = sub.add_parser("run", help="dynamic simulation (IDA or Newmark) of a scene -> NetCDF + PNG")
    _case_arguments(r, "CASE.nc")
    r.add_argument("--solver", choices=("ida", "newmark"), default="ida",
                   help="integrator: SUNDIALS IDA (default) or fixed-step Newmark-beta "
                        "(numerics.newmark_step_s)")
    r.add_argument("--no-plot", action="store_true", help="do not write the overview PNG")
    r.add_argument("--no-progress", action="store_true", help="no progress bar")
    r.add_argument("--resume", action="store_true",
                   help="continue from OUTPUT.checkpoint.npz, left by an interrupted run")
    r.add_argument("--checkpoint-every", type=int, default=None, metavar="N",
                   help="write the checkpoint every N output samples (and every 10 s); "
                        "default: every 50 samples, at most once a second")
    r.add_argument("--until-steady", action="store_true",
                   help="warm up until the cage speed is steady (numerics.until_steady; "
                        "criterion in bearingdae/run/steady.py), then record the window")

    s = sub.add_parser("static", help="quasi-static equilibrium of a scene -> NetCDF")
    _case_arguments(s, "CASE_static.nc")

    w = sub.add_parser("sweep", help="parameter sweep (dask) -> one NetCDF with the axes as dims")
    w.add_argument("sweep", help="sweep TOML file or bundled sweep (paper/yang20_speed_sweep)")
    w.add_argument("-o", "--output", type=Path, help="NetCDF file to write (default: SWEEP.nc); "
                   "the runs are kept in OUTPUT_runs/ and reused on restart")
    _cluster_arguments(w)

    pp = sub.add_parser("paper", help="the whole paper set: every sweep of cases/paper + Figs "
                        "11-24")
    pp.add_argument("-o", "--output", type=Path, default=Path("paper"),
                    help="output folder (default: paper/)")
    pp.add_argument("--no-figures", action="store_true", help="do not draw the PNGs")
    pp.add_argument("--trends", action="store_true",
                    help="instead: the trend claims with error bars (32-revolution windows, "
                         "bearingdae/studies/trends.py) -> OUTPUT/trends.csv, .nc, verdicts, "
                         "figures; resumes from or reads OUTPUT/runs")
    _cluster_arguments(pp)

    f = sub.add_parser("plot", help="the paper's figures (11-24) from a run or sweep file")
    f.add_argument("file", type=Path, help="NetCDF file from run, sweep or paper")
    f.add_argument("--figure", action="append", default=[], metavar="N",
                   help="figure number 11-24, 'trends', 'engineering' (power loss, oil film, "
                   "life by slice), 'orbit' (cage whirl: the cage centre) or 'all' (default: the "
                   "file's figures); repeatable")
    f.add_argument("-o", "--output", type=Path, help="PNG to write (with several figures: the "
                   "stem of OUTPUT_figNN.png; default: FILE_figNN.png)")
    f.add_argument("--select", action="append", default=[], metavar="DIM=VALUE",
                   help="pick runs of a sweep, e.g. --select speed_rpm=6000")
    f.add_argument("--spectrum", action="store_true",
                   help="the inner ring's vibration spectrum of a run file (ring_acceleration "
                   "of a dynamic ring, else ring_displacement) with the bearing's characteristic "
                   "frequencies marked -> OUTPUT or FILE_spectrum.png")
    f.add_argument("--fmin", type=float, default=None, metavar="HZ",
                   help="with --spectrum: lowest frequency drawn [Hz] (default 0)")
    f.add_argument("--fmax", type=float, default=None, metavar="HZ",
                   help="with --spectrum: highest frequency drawn [Hz] (default 4 x the "
                   "inner-race roller pass, at most the Nyquist frequency)")
    f.add_argument("--log", action="store_true",
                   help="with --spectrum: logarithmic amplitude axis")
    f.add_argument("--envelope", action="store_true",
                   help="with --spectrum: add the envelope spectrum (band-pass around a ring "
                   "resonance, Hilbert envelope)")
    f.add_argument("--band", default=None, metavar="LOW,HIGH",
                   help="with --envelope: the band-pass [Hz] (default: around the highest ring "
                   "natural frequency the record resolves)")

    sp = sub.add_parser("spectrum", help="the strongest peaks of a run's (envelope) spectrum, "
                        "each matched to a characteristic order (BPFO, BPFI ± fs, 2×BSF ± FTF, "
                        "...), as a table")
    sp.add_argument("file", type=Path, help="NetCDF file of a run")
    sp.add_argument("--envelope", action="store_true",
                    help="the envelope spectrum (band-pass around a ring resonance, Hilbert "
                    "envelope) instead of the amplitude spectrum")
    sp.add_argument("--peaks", default="10", metavar="N",
                    help="how many peaks, strongest first (default 10)")
    sp.add_argument("--band", default=None, metavar="LOW,HIGH",
                    help="with --envelope: the band-pass [Hz] (default: around the highest ring "
                    "natural frequency the record resolves)")
    sp.add_argument("--fmax", type=float, default=None, metavar="HZ",
                    help="highest frequency searched [Hz] (default 4 x the inner-race roller "
                    "pass, at most the Nyquist frequency)")

    k = sub.add_parser("keys", help="list every scene key with default, range and meaning")
    k.add_argument("--markdown", action="store_true", help="as Markdown: the documentation's "
                   "scene-key page, one table per section")

    wp = sub.add_parser("workprecision", help="error against wall time of IDA and the scipy "
                       "peers -> NetCDF + CSV table and PNG in DIR")
    wp.add_argument("case", nargs="?", default=DEFAULT_CASE,
                   help=f"scene TOML file or bundled case name (default: {DEFAULT_CASE})")
    wp.add_argument("-o", "--output", type=Path, default=Path("."), metavar="DIR",
                   help="output directory (default: .)")
    wp.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="override a scene key, e.g. --set operating.speed_rpm=10000")
    wp.add_argument("--revolutions", type=float, default=None, metavar="R",
                    help="errors over the first R cage revolutions from t = 0 (default 0.2: "
                         "on the baseline, runs at different tolerances diverge exponentially "
                         "after ~0.3 revolution; see docs/performance.md); with --statistics "
                         "the recorded cage revolutions after the scene's warm-up (default 4 x "
                         "the scene's numerics.cage_revolutions)")
    wp.add_argument("--statistics", action="store_true",
                    help="statistical study instead: IDA at rtol 1e-4 ... 1e-8, each run's "
                         "mean cage speed, slip, skew RMS and RMS pocket force with their "
                         "standard errors against the tightest run's, and the default rtol "
                         "they support")
    wp.add_argument("--repeat", type=int, default=3, help="timed runs per rung (median; >= 1)")
    wp.add_argument("--quick", action="store_true", help="short ladders (a smoke test)")
    wp.add_argument("--solvers", default=None,
                   help="comma-separated subset of the peers (IDA always runs)")
    wp.add_argument("--time-limit-factor", type=float, default=20.0, metavar="F",
                   help="stop a peer after F x the wall time of IDA at rtol 1e-6 (default 20)")
    wp.add_argument("--no-progress", action="store_true", help="no progress bar")

    cv = sub.add_parser("converge", help="the headline outputs under refinement of slices, "
                        "rtol and samples per revolution, against their standard errors, with "
                        "the CPU time of each setting -> NetCDF + PNG (+ Markdown table)")
    _case_arguments(cv, "CASE_converge.nc; the figure beside it, OUTPUT.png")
    cv.add_argument("--refine", default="slices,rtol,samples", metavar="LIST",
                    help="comma-separated refinements to run, one at a time: slices "
                         "(numerics.slices), rtol (numerics.rtol and atol), samples "
                         "(numerics.samples_per_cage_revolution); default all three")
    cv.add_argument("--slices-factor", type=float, default=None, metavar="F",
                    help="slices times F (default 2)")
    cv.add_argument("--rtol-factor", type=float, default=None, metavar="F",
                    help="rtol and atol divided by F (default 10)")
    cv.add_argument("--tolerance", type=float, default=None, metavar="REL",
                    help="practical tolerance: a change within REL times the base value is "
                         "converged however significant (default 1e-3, 0.1 %%)")
    cv.add_argument("--samples-factor", type=float, default=None, metavar="F",
                    help="samples per cage revolution times F (default 2)")
    cv.add_argument("--quick", action="store_true", help="a short record (0.2 + 0.5 cage "
                    "revolutions per run unless --set gives them; a smoke test: wide error "
                    "bars)")
    cv.add_argument("--table", type=Path, metavar="FILE.md", help="also write the table as "
                    "Markdown (with a caption saying how it was made) and FILE.csv")
    cv.add_argument("--no-plot", action="store_true", help="do not write the PNG")
    cv.add_argument("--no-progress", action="store_true", help="no progress lines")

    co = sub.add_parser("coefficients", help="the bearing's quasi-static stiffness matrix "
                        "over speed x radial load (for a rotor model, e.g. ROSS) -> NetCDF")
    _case_arguments(co, "CASE_coefficients.nc")
    co.add_argument("--speeds", type=float, nargs="+", required=True, metavar="RPM",
                    help="inner-ring speeds [r/min]")
    co.add_argument("--loads", type=float, nargs="+", required=True, metavar="N",
                    help="radial loads [N]")

    ca = sub.add_parser("calibrate", help="the inlet film (lubricant.inlet_film_um) at which "
                        "a scene's mean friction torque, drag excluded, equals a measured or "
                        "catalogue value -> the calibrated scene as TOML")
    _case_arguments(ca, "CASE_calibrated.toml")
    ca.add_argument("--friction-torque-Nmm", type=float, required=True, metavar="T",
                    dest="friction_torque_Nmm",
                    help="the target mean friction torque [N mm], drag excluded")

    sm = sub.add_parser("skidmap", help="steady cage slip over speed x radial load (dask, "
                        "until_steady) -> NetCDF + contour PNG with the skid boundary")
    sm.add_argument("case", help="scene TOML file or bundled case name")
    sm.add_argument("--speeds", type=float, nargs="+", required=True, metavar="RPM",
                    help="inner-ring speeds [r/min], at least 2")
    sm.add_argument("--loads", type=float, nargs="+", required=True, metavar="N",
                    help="radial loads [N], at least 2")
    sm.add_argument("-o", "--output", type=Path, help="NetCDF map (default: CASE_skidmap.nc; "
                    "beside it the PNG, and OUTPUT_sweep.nc: the sweep's summaries of every "
                    "point and one-orbit curves, for `bearingdae plot`; the runs in "
                    "OUTPUT_sweep_runs/, reused on restart)")
    sm.add_argument("--boundary", type=float, default=0.01, metavar="SLIP",
                    help="cage slip ratio of the skid boundary line (default 0.01 = 1 %%)")
    _cluster_arguments(sm)  # with --set: a scene key of every run

    c = sub.add_parser("cases", help="list the bundled scenes; --copy one to start a case of "
                       "your own")
    c.add_argument("--path", action="store_true", help="print full paths")
    c.add_argument("--copy", nargs=2, metavar=("CASE", "FILE"),
                   help="copy the bundled CASE to FILE (a new file) to edit, e.g. "
                        "--copy yang20_baseline my_case.toml")
    return p


def _cluster_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="dask scheduler address to attach to (default: a local cluster of "
                   "pinned single-thread processes); 'synchronous' runs in this process")
    p.add_argument("--workers", type=int, metavar="N", help="processes of the local cluster "
                   "(default: [sweep] workers, else the CPU count)")
    p.add_argument("--retry-failed", action="store_true", help="run again the runs recorded "
                   "as failed (default: keep their error)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--scheduler-timeout", type=float, default=30.0, metavar="S",
                   help="seconds to wait for the --scheduler address (default 30)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a scene key in every run, e.g. --set numerics.slices=6")
