"""``bearingdae plot``: figures drawn from a NetCDF file of run, sweep or paper.

Pipeline: the cli layer over plotting.
"""

from __future__ import annotations

import math
import sys

from ..util.atomic import shown_path


def _plot(args) -> int:
    from ..util.atomic import check_writable, fit_name, refuse_aliases, write_failure
    from ..plots.plotting import PAPER_CAPTIONS, available_figures, figure
    from ..results.readers import KINDS, open_result
    from ..scene.errors import _clip

    if getattr(args, "spectrum", False):
        return _spectrum(args)
    given = [o for o in ("fmin", "fmax", "band") if getattr(args, o, None) is not None] + [
        o for o in ("log", "envelope") if getattr(args, o, False)]
    if given:
        raise ValueError(f"--{given[0]} shapes the spectrum: give it with --spectrum")
    # a run or sweep file, checked before anything draws from it (results/readers.py)
    # (the engineering figure also draws a static file)
    kinds = ("run", "sweep") + (("static",) if "engineering" in (args.figure or []) else ())
    kind, ds = open_result(args.file, kinds)
    ds = _select(ds, kind, args.select, args.file, KINDS)
    wanted = []
    for f in args.figure or [None]:
        if f is None or f == "all":
            wanted += available_figures(ds) if f is None else list(PAPER_CAPTIONS) + ["trends"]
        elif f in ("trends", "engineering", "orbit"):
            wanted.append(f)
        elif f.isdigit() and len(f) <= 3 and int(f) in PAPER_CAPTIONS:
            wanted.append(int(f))
        else:
            raise ValueError(f"--figure {_clip(f)!r}: allowed are 11-24, 'trends', "
                             "'engineering', 'orbit' (cage whirl) and 'all'")
    stem = args.output or args.file
    targets = {}
    for number in wanted:
        tag = number if number in ("trends", "engineering", "orbit") else f"fig{number:02d}"
        if args.output is not None and len(wanted) == 1:
            targets[number] = args.output
        else:
            targets[number] = fit_name(stem.with_name(f"{stem.stem}_{tag}.png"), f"_{tag}.png")
        check_writable(targets[number])  # before drawing anything
    refuse_aliases([(f"figure {n}", t) for n, t in targets.items()], [("input file", args.file)])
    drawn = 0
    for number, target in targets.items():
        try:
            if number == "engineering":  # life, film, power loss (plots/plot_engineering.py)
                from ..plots.plot_engineering import engineering_figure

                print(f"wrote {engineering_figure(ds, target)}")
            else:
                print(f"wrote {figure(ds, number, target)}")
            drawn += 1
        except OSError as exc:  # e.g. the disk filled up while drawing
            print(f"bearingdae: figure {number}: {write_failure(exc, target)}", file=sys.stderr)
            return 1
        except Exception as exc:  # what the file holds cannot make this figure
            if not isinstance(exc, ValueError):  # the checks of open_result missed a defect
                exc = ValueError(f"'{shown_path(args.file)}' cannot make it "
                                 f"({type(exc).__name__}: {str(exc)[:100]})")
            if len(wanted) == 1 or args.figure not in ([], ["all"]):
                raise ValueError(f"figure {number}: {exc}") from None
            print(f"bearingdae: figure {number} skipped: {exc}", file=sys.stderr)
    if not drawn:
        print(f"bearingdae: no figure drawn from {shown_path(args.file)}", file=sys.stderr)
        return 1
    return 0


def _spectrum(args) -> int:
    """``plot RUN.nc --spectrum``: the ring's spectrum PNG (analysis/spectrum.py)."""
    from ..results.readers import open_result
    from ..plots.plot_spectrum import spectrum_figure
    from ..util.atomic import check_writable, fit_name, refuse_aliases, write_failure

    if args.figure or args.select:
        raise ValueError("--spectrum draws one figure of a run file; give it without --figure "
                         "and --select")
    fmin = 0.0 if args.fmin is None else args.fmin
    for option, value in (("--fmin", args.fmin), ("--fmax", args.fmax)):
        if value is not None and not (math.isfinite(value) and value >= 0.0):
            raise ValueError(f"{option} {value!r}: expected a finite frequency >= 0 Hz")
    if args.fmax is not None and args.fmax <= fmin:
        raise ValueError(f"--fmax {args.fmax!r}: expected above --fmin ({fmin!r} Hz)")
    band = _band(args.band, args.envelope)
    _, ds = open_result(args.file, ("run",))
    target = args.output or fit_name(args.file.with_name(f"{args.file.stem}_spectrum.png"),
                                     "_spectrum.png")
    check_writable(target)
    refuse_aliases([("spectrum", target)], [("input file", args.file)])
    try:
        drawn = spectrum_figure(ds, target, fmin, args.fmax, args.log, args.envelope, band)
        print(f"wrote {drawn}")
    except OSError as exc:
        print(f"bearingdae: spectrum: {write_failure(exc, target)}", file=sys.stderr)
        return 1
    return 0


def _band(text: str | None, envelope: bool):
    """``--band LOW,HIGH`` as (low, high) [Hz], or None; ValueError naming what is wrong."""
    from ..scene.errors import _clip

    if text is None:
        return None
    if not envelope:
        raise ValueError("--band is the envelope's band-pass: give it with --envelope")
    try:
        lo, hi = (float(v) for v in text.split(","))
    except ValueError:
        raise ValueError(f"--band {_clip(text)!r}: expected LOW,HIGH in Hz, e.g. "
                         "--band 800,1200") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 <= lo < hi):
        raise ValueError(f"--band {_clip(text)!r}: expected finite 0 <= LOW < HIGH [Hz]")
    return lo, hi


def _select(ds, kind: str, pairs: list[str], path, kinds: dict):
    """``--select DIM=VALUE``: one value of an axis of a sweep file (the only files with runs
    to pick); the value must be one of the axis's."""
    from ..results.readers import sweep_axes
    from ..scene.errors import _clip

    if not pairs:
        return ds
    if kind != "sweep":
        raise ValueError(f"--select {_clip(pairs[0])}: '{shown_path(path)}' is a {kinds[kind]}, "
                         "which has no runs to pick; --select picks runs of a sweep file")
    axes = [a["dim"] for a in sweep_axes(ds)]
    for pair in pairs:
        dim, sep, value = pair.partition("=")
        if not sep or dim not in axes or dim not in ds.dims:
            left = [d for d in axes if d in ds.dims]
            raise ValueError(f"--select {_clip(pair)}: expected AXIS=VALUE with AXIS one of the "
                             f"sweep's axes {left}" if left else
                             f"--select {_clip(pair)}: every axis of the sweep is selected "
                             "already")
        values = list(ds[dim].values)
        try:
            kind_of = type(values[0].item()) if values else str
            v = value.strip().lower() in ("true", "1") if kind_of is bool else kind_of(value)
            ds = ds.sel({dim: v})
        except (KeyError, ValueError, TypeError, OverflowError):
            raise ValueError(f"--select {_clip(pair)}: {dim} has values "
                             f"{[_clip(str(x), 20) for x in values[:20]]}") from None
    return ds
