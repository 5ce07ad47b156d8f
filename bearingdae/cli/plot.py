"""``bearingdae plot``: figures drawn from a NetCDF file of run, sweep or paper.

Pipeline: the cli layer over plotting.
"""

from __future__ import annotations

import sys

def _plot(args) -> int:
    import xarray as xr

    from ..util.atomic import check_writable, write_failure
    from ..results.plotting import PAPER_CAPTIONS, available_figures, figure

    if args.file.is_dir():
        raise ValueError(f"plot: '{args.file}' is a directory; give a NetCDF file from run, "
                         "sweep or paper (e.g. a .nc file inside it)")
    if not args.file.is_file():
        raise ValueError(f"plot: file '{args.file}' does not exist")
    try:
        with xr.open_dataset(args.file) as ds:
            ds = ds.load()
    except (OSError, ValueError) as exc:
        raise ValueError(f"plot: '{args.file}' is not a readable NetCDF file ({exc})") from None
    for pair in args.select:
        dim, sep, value = pair.partition("=")
        if not sep or dim not in ds.dims:
            raise ValueError(f"--select {pair!r}: expected DIM=VALUE with DIM one of "
                             f"{[d for d in ds.dims if d in ds.coords]}")
        coord = ds[dim]
        try:
            kind = type(coord.values[0].item())
            v = value.strip().lower() in ("true", "1") if kind is bool else kind(value)
            ds = ds.sel({dim: v})
        except (KeyError, ValueError):
            raise ValueError(f"--select {pair!r}: {dim} has values "
                             f"{list(coord.values)}") from None
    wanted = []
    for f in args.figure or [None]:
        if f is None or f == "all":
            wanted += available_figures(ds) if f is None else list(PAPER_CAPTIONS) + ["trends"]
        elif f in ("trends", "engineering"):
            wanted.append(f)
        elif f.isdigit() and int(f) in PAPER_CAPTIONS:
            wanted.append(int(f))
        else:
            raise ValueError(f"--figure {f!r}: allowed are 11-24, 'trends', 'engineering' and "
                             "'all'")
    stem = args.output or args.file
    targets = {}
    for number in wanted:
        tag = number if number in ("trends", "engineering") else f"fig{number:02d}"
        if args.output is not None and len(wanted) == 1:
            targets[number] = args.output
        else:
            targets[number] = stem.with_name(f"{stem.stem}_{tag}.png")
        check_writable(targets[number])  # before drawing anything
    drawn = 0
    for number, target in targets.items():
        try:
            if number == "engineering":  # life, film, power loss (results/plot_engineering.py)
                from ..results.plot_engineering import engineering_figure

                print(f"wrote {engineering_figure(ds, target)}")
            else:
                print(f"wrote {figure(ds, number, target)}")
            drawn += 1
        except OSError as exc:  # e.g. the disk filled up while drawing
            print(f"bearingdae: figure {number}: {write_failure(exc, target)}", file=sys.stderr)
            return 1
        except ValueError as exc:
            if len(wanted) == 1 or args.figure not in ([], ["all"]):
                raise ValueError(f"figure {number}: {exc}") from None
            print(f"bearingdae: figure {number} skipped: {exc}", file=sys.stderr)
    if not drawn:
        print(f"bearingdae: no figure drawn from {args.file}", file=sys.stderr)
        return 1
    return 0
