"""Command line: ``bearingdae static|run|cases`` (thin layer over the Python API).

Errors in the user's input are printed as one paragraph and exit with status 2; no traceback
reaches the user for bad input.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

DEFAULT_CASE = "yang20_baseline"


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="bearingdae",
        description="Cylindrical roller bearing dynamics (skid, skew, cage) with SUNDIALS IDA.",
    )
    p.add_argument("--version", action="store_true", help="print the version and exit")
    sub = p.add_subparsers(dest="command")

    s = sub.add_parser("static", help="quasi-static equilibrium of a scene -> NetCDF")
    s.add_argument("case", nargs="?", default=DEFAULT_CASE,
                   help=f"scene TOML file or bundled case name (default: {DEFAULT_CASE})")
    s.add_argument("-o", "--output", type=Path, help="NetCDF file to write (default: CASE_static.nc)")
    s.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a scene key, e.g. --set operating.radial_load_N=400")

    k = sub.add_parser("keys", help="list every scene key with default, range and meaning")
    k.add_argument("--markdown", action="store_true", help="as a Markdown table")

    c = sub.add_parser("cases", help="list the bundled scenes")
    c.add_argument("--path", action="store_true", help="print full paths")
    return p


def _overrides(pairs: list[str]) -> dict:
    import tomllib

    out = {}
    for pair in pairs:
        if "=" not in pair:
            raise ValueError(f"--set {pair!r}: expected KEY=VALUE, e.g. operating.speed_rpm=6000")
        key, value = pair.split("=", 1)
        try:
            out[key.strip()] = tomllib.loads(f"v = {value}")["v"]
        except tomllib.TOMLDecodeError:
            out[key.strip()] = value  # a bare string such as a profile name
    return out


def _static(args) -> int:
    from . import load_scene, save, solve_static
    from .scene import resolve_case

    scene = load_scene(args.case, _overrides(args.set))
    ds = solve_static(scene)
    out = args.output or Path(f"{resolve_case(args.case).stem}_static.nc")
    save(ds, out)
    q = ds.contact_force
    print(f"{scene.title}")
    print(f"  Newton iterations      {ds.attrs['newton_iterations']}")
    print(f"  relative residual      {ds.attrs['residual_max_relative']:.2e}")
    print(f"  ring displacement      {ds.ring_displacement.sel(direction='radial').item() * 1e6:.3f} µm")
    print(f"  ring tilt              {ds.ring_tilt.sel(direction='radial').item() * 1e3:.4f} mrad")
    print(f"  max roller load inner  {q.sel(race='inner').sum('slice').max().item():.2f} N")
    print(f"  max slice pressure     {ds.contact_pressure.max().item() / 1e9:.3f} GPa")
    print(f"wrote {out}")
    return 0


def _keys(args) -> int:
    from .scene import key_table

    rows = key_table()
    if args.markdown:
        print("| key | default | allowed | meaning |")
        print("|---|---|---|---|")
        for key, default, rng, desc in rows:
            print(f"| `{key}` | {default} | {rng} | {desc} |")
    else:
        for key, default, rng, desc in rows:
            print(f"{key:34s} {default:>10s} {rng:>18s}  {desc}")
    return 0


def _cases(args) -> int:
    from .scene import bundled_case_dirs

    seen = set()
    for d in bundled_case_dirs():
        for p in sorted(d.rglob("*.toml")):
            rel = p.relative_to(d).with_suffix("")
            if rel in seen:
                continue
            seen.add(rel)
            print(p if args.path else rel)
    return 0


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.version:
        from . import __version__

        print(f"bearingdae {__version__}")
        return 0
    from .scene import SceneError

    handlers = {"static": _static, "cases": _cases, "keys": _keys}
    if args.command is None:
        _parser().print_help()
        return 0
    try:
        return handlers[args.command](args)
    except (SceneError, ValueError) as exc:
        print(f"bearingdae: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("bearingdae: interrupted; no partial output file was left behind", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
