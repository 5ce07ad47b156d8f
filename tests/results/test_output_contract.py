"""Output contract: every NetCDF bearingdae writes passes a CF checker and lists
every variable with units.

Files checked: `bearingdae static`, `bearingdae run` (a completed run) and the `_partial.nc` of
an interrupted run, produced through the command line as a user would, and a sweep's file and
one of its run files (bearingdae/studies/sweep/__init__.py).

* CF, the arbiter: the NCAS CF checker ``cfchecks`` (PyPI ``cfchecker``, the CF community's
  reference checker), run as a command on every file: 0 errors, 0 warnings, 0 fatal errors.
  It needs the UDUNITS-2 C library (Debian ``libudunits2-0``; the test is skipped, naming the
  package, where it is missing) and three XML tables: the standard-name table from
  compliance-checker's package data (``-s``), and two stand-ins in tests/results/data for the area-type
  and region tables (``-a``, ``-r``), which no installable package ships; the checker consults
  them only for ``area_type``/``region`` standard names and ``cell_methods``, which our files
  do not have (asserted here). cfchecker 4.1.0, the newest release, knows CF up to 1.8 and
  answers a ``Conventions = "CF-1.10"`` file with one error, "does not appear to contain CF
  Convention data" (2.6.1), before checking it against its newest rules. Where the checker does
  not know the file's version, the test therefore checks a copy whose ``Conventions`` names the
  newest version it knows (every other byte of the file unchanged), with ``-v auto``.
* CF, second opinion: IOOS compliance-checker, standard ``cf:1.10`` (the files'
  ``Conventions``), every check at every priority must pass, and no check may raise. Two
  findings are exempt, stated here rather than hidden:

  - §5.1 asks a dimension named ``time`` for ``standard_name = "time"``, and a CF time
    coordinate needs units "seconds since <epoch>" (IOOS heuristic on the dimension *name*). A
    simulation has no calendar date, and such units would make xarray decode ``time`` to
    datetimes; ``time`` stays an elapsed time in ``s`` (valid UDUNITS, which §3.1 checks), a
    coordinate that CF 4.4 does not identify as a time coordinate (it goes by units). cfchecks
    does not ask for it.
  - §5 (medium priority, a CF *recommendation*): a label variable (``race``, ``end``,
    ``direction``, ``loss_source``, ``frequency_name``: char arrays ``race(race, string5)``) "shares the same name as one of its
    dimensions". CF 6.1 makes labels auxiliary coordinates, named in the data variables'
    ``coordinates`` attribute; cfchecks warns "possible incorrect declaration of a coordinate
    variable" on a label that is not named there, so the files name them. Giving the label
    another name than its dimension would satisfy both, but then xarray reads the file back
    without the ``race`` index (``ds.sel(race="inner")`` fails), breaking the round trip.
  cfchecks, one finding exempt: it warns "(3.1): units attribute should be present" on a
  numeric coordinate variable without units. The integer index coordinates ``roller`` and
  ``slice`` have none on purpose: CF 3.1 "Units are not required for dimensionless quantities.
  A variable with no units attribute is assumed to be dimensionless", and xarray labels a plot
  axis "roller number [1]" from ``units = "1"``. compliance-checker does not ask for them.
  (cfchecks also gives the INFORMATION that ``coordinates`` is a global attribute: xarray
  names ``slice_position_bounds`` there, which makes ``xr.open_dataset`` read it back as a
  coordinate.)
* Units: ``ncdump -h`` (when installed; else the netCDF4 library, the same header) shows a
  non-empty ``units`` and a ``long_name`` on every numeric variable, a ``long_name`` and no
  ``units`` on the index coordinates and label coordinates (``race``: a char array), and no
  attributes needed on a CF 7.1 boundary variable (``slice_position_bounds``).
"""

from __future__ import annotations

import contextlib
import ctypes.util
import importlib.resources
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from bearingdae.cli import main

DATA = Path(__file__).parent / "data"

SHORT = ["numerics.warmup_cage_revolutions=0.0", "numerics.cage_revolutions=0.05",
         "numerics.samples_per_cage_revolution=200", "operating.moment_Nm=0.0"]
#: (check section, message) of compliance-checker exempt from "no findings", with the reason in
#: the module docstring.
EXEMPT = [("§5.1", "Coordinate variable 'time' should have standard_name='time'")] + [
    ("§5 Coordinate Systems", f": {label} shares the same name as one of its dimensions")
    for label in ("race", "end", "direction", "loss_source", "frequency_name")]


KINDS = ["static", "dynamic", "partial", "sweep", "sweep run"]
#: integer index coordinates: dimensionless numbers, no units (module docstring)
INDEX_COORDS = ("roller", "slice")
#: cfchecks finding exempt on the index coordinates, with the reason in the module docstring
CFCHECKS_EXEMPT = "WARN: (3.1): units attribute should be present"


def sets(pairs):
    return [f"--set={p}" for p in pairs]


@pytest.fixture(scope="module")
def produced(tmp_path_factory) -> dict[str, Path]:
    d = tmp_path_factory.mktemp("contract")
    files = {}
    assert main(["static", "yang20_baseline", "-o", str(d / "static.nc")]) == 0
    files["static"] = d / "static.nc"
    assert main(["run", "yang20_baseline", "-o", str(d / "run.nc"), "--no-plot",
                 "--no-progress", *sets(SHORT)]) == 0
    files["dynamic"] = d / "run.nc"
    # A run stopped by Ctrl-C after 4 samples keeps them in run_int_partial.nc (exit status 130).
    from bearingdae.run.checkpoint import Checkpoint

    def ctrl_c_after_4(self, t, y, yp, _sample=Checkpoint.sample):
        _sample(self, t, y, yp)
        if len(self.T) == 4:
            raise KeyboardInterrupt

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(Checkpoint, "sample", ctrl_c_after_4)
        assert main(["run", "yang20_baseline", "-o", str(d / "run_int.nc"), "--no-plot",
                     "--no-progress", *sets(SHORT)]) == 130
    files["partial"] = d / "run_int_partial.nc"
    # A two-run sweep, in this process (the dask path writes the same files: tests/test_faults).
    from bearingdae.studies.sweep import run_sweep, sweep_from_dict

    sweep = sweep_from_dict({
        "title": "contract sweep", "base": "yang20_baseline",
        "overrides": {k: (int(v) if v.isdigit() else float(v))
                      for k, v in (p.split("=") for p in SHORT)},
        "axes": {"operating.radial_load_N": [600.0, 900.0]}})
    run_sweep(sweep, d / "sweep.nc", scheduler="synchronous", progress=False)
    files["sweep"] = d / "sweep.nc"
    files["sweep run"] = next((d / "sweep_runs").glob("*.nc"))
    assert all(p.exists() for p in files.values())
    return files


#: compliance-checker's helpers that read only a file's structure (its variables, dimensions
#: and attributes), which its checks call again and again on the same file (measured on our
#: five files: 3510 calls of is_geophysical, 8512 of get_auxiliary_coordinate_variables, 80 %
#: of the checker's CPU): :func:`structure_answered_once` answers each question once per file
STRUCTURE_HELPERS = ("is_geophysical", "get_geophysical_variables",
                     "get_auxiliary_coordinate_variables", "get_axis_variables",
                     "get_time_variable", "get_time_variables", "get_climatology_variable",
                     "get_z_variables", "get_axis_map", "coordinate_dimension_matrix")


@contextlib.contextmanager
def structure_answered_once(mp: pytest.MonkeyPatch):
    """While checking one file, each helper of :data:`STRUCTURE_HELPERS` computes its answer
    for a question (the file, a variable's name) once and hands out a copy of it after: the
    file does not change while it is checked, so the checks see the answers they would
    compute, and report the same findings, at a tenth of the CPU (measured)."""
    import copy

    import compliance_checker.cf.util as cfutil

    answers: dict = {}

    def once(name, helper):
        def answered(nc, *args):
            if not all(isinstance(a, str) for a in args):
                return helper(nc, *args)
            key = (name, id(nc), *args)
            if key not in answers:
                answers[key] = helper(nc, *args)
            return copy.deepcopy(answers[key])
        return answered

    for name in STRUCTURE_HELPERS:
        mp.setattr(cfutil, name, once(name, getattr(cfutil, name)))
    try:
        yield
    finally:
        answers.clear()


def cf_findings(path: Path, answered_once: bool = True) -> tuple[list[str], dict]:
    """(findings 'priority section: message', exceptions) of compliance-checker cf:1.10;
    ``answered_once``: with :func:`structure_answered_once`."""
    cc = pytest.importorskip("compliance_checker.runner", reason="compliance-checker is in the "
                             "'test' extra (pip install .[test])")
    suite = cc.CheckSuite()
    suite.load_all_available_checkers()
    ds = suite.load_dataset(str(path))
    with pytest.MonkeyPatch.context() as mp, contextlib.ExitStack() as stack:
        if answered_once:
            stack.enter_context(structure_answered_once(mp))
        groups, errors = suite.run_all(ds, ["cf:1.10"], skip_checks=[])["cf:1.10"]
    out = []
    for g in groups:
        if g.value[0] < g.value[1]:
            out += [f"{g.weight} {g.name}: {m}" for m in g.msgs]
    return out, errors


@pytest.mark.parametrize("kind", KINDS)
def test_cf_checker_finds_no_errors(produced, kind):
    found, errors = cf_findings(produced[kind])
    assert errors == {}, f"checks raised: {list(errors)}"
    left = [f for f in found if not any(sec in f and msg in f for sec, msg in EXEMPT)]
    assert left == [], "\n".join(left)


@pytest.mark.parametrize("kind", ["static", pytest.param("dynamic", marks=pytest.mark.slow)])
def test_answering_the_structure_once_changes_no_finding(produced, kind):
    """The checker with each structure question answered once reports what it reports
    answering them every time (findings with their messages, and exceptions): on the static
    file (the smallest, 1 s of CPU) and, in the slow tier, on a run's (15 s; measured equal on
    all five files)."""
    assert cf_findings(produced[kind]) == cf_findings(produced[kind], answered_once=False)


#: a variable's declaration in `ncdump -h`: "double x(slice) ;" or "double t ;"
NCDUMP_DECL = re.compile(r"\s+(\w+) (\w+)(?:\(.*\))? ;$")
#: an attribute: "x:units = "m" ;"; a text attribute that is not plain ASCII (φ, θ, §) is a
#: NetCDF string, which ncdump prefixes with its type: "string x:long_name = "φ" ;". A value
#: ncdump breaks over lines ends with " ;" on its last line only.
NCDUMP_ATTR = re.compile(r"\s+(?:\w+ )?(\w+):(\w+) = (.*)$")


def parse_ncdump_header(text: str) -> dict[str, dict[str, str]]:
    """variable -> attributes (and ``_type``) from the text of `ncdump -h`."""
    body = text.split("variables:", 1)[1].split("// global attributes:", 1)[0]
    out: dict[str, dict[str, str]] = {}
    pending = None  # (variable, attribute, text so far) of a value not yet ended by " ;"
    for line in body.splitlines():
        if pending is not None:
            var, att, value = pending
            pending = None
            value += " " + line.strip()
        else:
            decl, att_m = NCDUMP_DECL.match(line), NCDUMP_ATTR.match(line)
            if decl and not att_m:
                out[decl.group(2)] = {"_type": decl.group(1)}
                continue
            if not att_m or att_m.group(1) not in out:
                continue
            var, att, value = att_m.groups()
        if not value.endswith(" ;"):
            pending = (var, att, value)
            continue
        parts = re.findall(r'"((?:[^"\\]|\\.)*)"', value[:-2])
        out[var][att] = "".join(parts) if parts else value[:-2].strip()
    return out


def header(path: Path) -> dict[str, dict[str, str]]:
    """variable -> attributes, from `ncdump -h` if installed, else from netCDF4."""
    ncdump = shutil.which("ncdump")
    if ncdump:
        return parse_ncdump_header(subprocess.run(
            [ncdump, "-h", str(path)], capture_output=True, text=True, check=True).stdout)
    return netcdf4_header(path)


def netcdf4_header(path: Path) -> dict[str, dict[str, str]]:
    """variable -> attributes, read with the netCDF4 library."""
    import netCDF4

    with netCDF4.Dataset(path) as nc:
        return {name: {"_type": "char" if v.dtype == "S1" else str(v.dtype),
                       **{a: str(v.getncattr(a)) for a in v.ncattrs()}}
                for name, v in nc.variables.items()}


@pytest.mark.parametrize("kind", KINDS)
def test_every_variable_has_units(produced, kind):
    assert len(assert_units_contract(produced[kind])) >= 10


def assert_units_contract(path: Path) -> dict[str, dict[str, str]]:
    """The units contract of the module docstring on the file ``path``; returns its header."""
    h = header(path)
    bounds = {a["bounds"] for a in h.values() if "bounds" in a}
    dims = _dimensions(path)
    for name, attrs in h.items():
        if name in bounds:  # CF 7.1: a boundary variable shares its coordinate's attributes
            continue
        assert "long_name" in attrs, (name, attrs)
        if name in INDEX_COORDS or (attrs["_type"] == "char" and name in dims):
            assert "units" not in attrs, f"{name}: an index or label coordinate has no units"
        elif "flag_values" in attrs:  # a 0/1 flag: CF flag_values and flag_meanings
            assert "units" not in attrs and attrs.get("flag_meanings", "").strip(), (name, attrs)
        elif attrs["_type"] != "char":
            assert attrs.get("units", "").strip(), f"{name} has no units"
        else:
            assert attrs.get("units", "x").strip(), f"{name}: text with empty units"
    return h


def _dimensions(path: Path) -> set[str]:
    import netCDF4

    with netCDF4.Dataset(path) as nc:
        return set(nc.dimensions)


def test_ncdump_header_reads_non_ascii_attributes(tmp_path):
    """A non-ASCII text attribute (a long_name with φ) is a NetCDF string attribute, which
    ncdump prints as "string var:attr = ..."; the header parser reads it like any other, and
    agrees with the netCDF4 library on every attribute."""
    import numpy as np
    import xarray as xr

    path = tmp_path / "phi.nc"
    xr.Dataset({"azimuth": ("roller", np.zeros(3), {
        "units": "rad", "long_name": "roller azimuth φ from the load line",
        "comment": "θ and \"quoted\" text"})},
        coords={"roller": ("roller", [1, 2, 3], {"long_name": "roller number"})}
    ).to_netcdf(path)
    expected = netcdf4_header(path)
    assert expected["azimuth"]["long_name"] == "roller azimuth φ from the load line"
    ncdump = shutil.which("ncdump")
    if ncdump is None:
        pytest.skip("ncdump (Debian netcdf-bin) is not installed")
    text = subprocess.run([ncdump, "-h", str(path)], capture_output=True, text=True,
                          check=True).stdout
    assert "string azimuth:long_name" in text  # the line the parser has to read
    got = parse_ncdump_header(text)
    for var, att in (("azimuth", "units"), ("azimuth", "long_name"), ("azimuth", "comment"),
                     ("roller", "long_name")):
        assert got[var][att].replace('\\"', '"') == expected[var][att], (var, att)


# ---------------------------------------------------------------------------------------------
# The NCAS CF checker (cfchecks), the arbiter
# ---------------------------------------------------------------------------------------------
AREA_TYPES = DATA / "cf-area-type-table-stand-in.xml"
REGION_NAMES = DATA / "cf-standardized-region-list-stand-in.xml"
SUMMARY = re.compile(r"^(FATAL ERRORS|ERRORS detected|WARNINGS given|INFORMATION messages): "
                     r"(\d+)\s*$", re.M)


def cfchecks_ready() -> tuple[list, Path]:
    """(CF versions the installed cfchecks knows, standard-name table); skips with the reason."""
    if ctypes.util.find_library("udunits2") is None:
        pytest.skip("cfchecks (cfchecker) needs the UDUNITS-2 C library: on Debian/Ubuntu "
                    "`apt-get install libudunits2-0` (.ci/run does this when it can)")
    cfchecks = pytest.importorskip("cfchecker.cfchecks", reason="cfchecker is in the 'test' "
                                   "extra (pip install .[test])")
    table = importlib.resources.files("compliance_checker") / "data/cf-standard-name-table.xml"
    if not table.is_file():
        pytest.skip("the CF standard-name table ships with compliance-checker (test extra)")
    return list(cfchecks.cfVersions), Path(str(table))


def cfchecks(path: Path, workdir: Path) -> dict:
    """Run ``cfchecks -v auto`` on ``path`` (or on a copy naming a CF version the checker knows;
    see the module docstring) and return its summary counts, version lines and findings."""
    import netCDF4

    known, table = cfchecks_ready()
    with netCDF4.Dataset(path) as nc:
        conventions = str(nc.getncattr("Conventions"))
        attrs = [(n, a, str(v.getncattr(a))) for n, v in nc.variables.items()
                 for a in v.ncattrs()]
    # Our files use nothing that would make cfchecks consult the stand-in tables.
    assert not [x for x in attrs if x[1] == "cell_methods"
                or (x[1] == "standard_name" and x[2] in ("area_type", "region"))], attrs
    target = path
    if conventions not in map(str, known):
        target = workdir / path.name
        shutil.copyfile(path, target)
        with netCDF4.Dataset(target, "a") as nc:
            nc.setncattr("Conventions", str(max(known)))
    proc = subprocess.run(
        [sys.executable, "-m", "cfchecker.cfchecks", "-v", "auto", "-s", str(table),
         "-a", str(AREA_TYPES), "-r", str(REGION_NAMES), str(target)],
        capture_output=True, text=True, timeout=600, cwd=workdir)
    out = proc.stdout
    counts: dict[str, int] = {}
    for label, n in SUMMARY.findall(out):
        assert label not in counts, f"two summaries in the cfchecks output:\n{out}"
        counts[label] = int(n)
    # A crash or an aborted check prints no summary (or a FATAL line): never read as a pass.
    assert {"ERRORS detected", "WARNINGS given"} <= set(counts), \
        f"no cfchecks summary (exit {proc.returncode}):\n{out}\n{proc.stderr}"
    versions = re.findall(r"^(Using .*Version .*|Checking against CF Version .*)$", out, re.M)
    findings, exempt = [], []
    for section in re.split(r"^Checking variable: ", out, flags=re.M):
        variable = section.split("\n", 1)[0].strip()
        for line in re.findall(r"^(?:FATAL|ERROR|WARN)\b.*$", section, re.M):
            if variable in INDEX_COORDS and line.strip() == CFCHECKS_EXEMPT:
                exempt.append((variable, line))
            else:
                findings.append(line)
    counts["WARNINGS given"] = counts.get("WARNINGS given", 0) - len(exempt)
    # cfchecks exits with the number of errors, else minus the number of warnings
    returncode = proc.returncode
    if exempt and proc.returncode == (-(counts["WARNINGS given"] + len(exempt))) % 256:
        returncode = (-counts["WARNINGS given"]) % 256
    return {"returncode": returncode, "counts": counts, "versions": versions,
            "findings": findings, "conventions": conventions,
            "checked_as": conventions if target is path else str(max(known)),
            "output": out + proc.stderr}


@pytest.mark.parametrize("kind", KINDS)
def test_cfchecks_reports_no_errors_and_no_warnings(produced, kind, tmp_path):
    r = cfchecks(produced[kind], tmp_path)
    c = r["counts"]
    print(f"\ncfchecks {kind}: {r['conventions']} checked as {r['checked_as']}; "
          f"{'; '.join(r['versions'])}; {c}")
    assert c.get("FATAL ERRORS", 0) == 0 and c["ERRORS detected"] == 0 \
        and c["WARNINGS given"] == 0 and r["returncode"] == 0, r["output"]
    assert r["findings"] == [], r["output"]
    assert any(v.startswith("Using Standard Name Table Version") for v in r["versions"])


# ---------------------------------------------------------------------------------------------
# Results are variables, global attributes are metadata (analysis/result_variables.py)
# ---------------------------------------------------------------------------------------------
#: a name that ends in a unit (what the older files called their numbers: ..._rad_s, ..._N)
UNIT_SUFFIX = re.compile(r"_(s|m|N|Nm|N_m|Pa|W|J|Hz|rad|rad_s|m_s|rpm|Mrev|h|kg|kg_m2|deg|"
                         r"N_s_m|K)$")


def global_attribute_findings(ds) -> list[str]:
    """What breaks "global attributes are metadata": a number that is not one of the solver's
    options (``solver_options``, as recorded) or a count of a sweep's runs; a JSON text whose
    name carries a unit or whose keys name a 0-d variable of the file (a result kept as text
    too); an attribute named like a variable."""
    import json

    import numpy as np

    options = json.loads(ds.attrs.get("solver_options", "{}"))
    out = []
    for key, value in ds.attrs.items():
        if key in ds.variables:
            out.append(f"{key}: also a variable")
        if isinstance(value, (int, float, np.number)) and not isinstance(value, bool):
            sweep_count = key.startswith("runs_") and float(value).is_integer()
            if not (options.get(key) == value or sweep_count):
                out.append(f"{key} = {value!r}: a number that is no solver option")
        elif isinstance(value, str) and value[:1] in "[{":
            try:
                parsed = json.loads(value)
            except ValueError:
                continue
            keys = set(parsed) if isinstance(parsed, dict) else set()
            scalars = {n for n, v in ds.data_vars.items() if v.ndim == 0}
            if UNIT_SUFFIX.search(key) or keys & scalars:
                out.append(f"{key}: JSON of results")
    return out


@pytest.mark.parametrize("kind", KINDS)
def test_global_attributes_are_metadata_and_results_are_variables(produced, kind):
    """No global attribute is a number with units or a JSON text of results; every 0-d
    variable has units and a long name; every ``ancillary_variables`` names variables of the
    file, each an error of its parent (units equal, a long name or standard name saying so)."""
    import xarray as xr

    with xr.open_dataset(produced[kind]) as ds:
        assert global_attribute_findings(ds) == []
        scalars = [n for n, v in ds.data_vars.items() if v.ndim == 0]
        for name in scalars:  # units, or a 0/1 flag's flag_values and flag_meanings
            a = ds[name].attrs
            assert (a.get("units") or a.get("flag_meanings")) and a.get("long_name"), name
        links = {n: v.attrs["ancillary_variables"].split() for n, v in ds.data_vars.items()
                 if "ancillary_variables" in v.attrs}
        for name, partners in links.items():
            for partner in partners:
                assert partner in ds.data_vars, (name, partner)
                p = ds[partner].attrs
                assert p["units"] == ds[name].attrs["units"], (name, partner)
                assert "error" in p["long_name"] or p.get("standard_name", "").endswith(
                    " standard_error"), (name, partner)
        if kind in ("dynamic", "sweep run"):
            assert "mean_cage_speed_rad_s" in scalars and links, kind
            f = ds["characteristic_frequencies_Hz"]
            assert f.dims == ("frequency_name",) and f.attrs["units"] == "Hz"
        if kind == "sweep":  # the runs' variables along the axes
            assert ds["mean_cage_speed_rad_s"].dims == ("radial_load_N",)
            assert "mean_cage_speed_stderr_rad_s" in ds.data_vars


def test_the_rule_finds_results_kept_as_attributes():
    """The rule above catches each way the older files kept their results."""
    import json

    import xarray as xr

    ds = xr.Dataset({"cage_speed": ("time", [1.0, 2.0])}, attrs={
        "solver_options": json.dumps({"rtol": 1e-6}), "rtol": 1e-6, "runs_total": 2,
        "scene_toml": "title = 'x'", "mean_cage_speed_rad_s": 95.0,
        "characteristic_frequencies_Hz": json.dumps({"cage": 15.0}),
        "summary": json.dumps({"cage_slip_ratio": 1.0})}).assign(cage_slip_ratio=0.5)
    found = global_attribute_findings(ds)
    assert [f.split(" ")[0].rstrip(":") for f in found] == [
        "mean_cage_speed_rad_s", "characteristic_frequencies_Hz", "summary"]
    assert "cage_slip_ratio: also a variable" in global_attribute_findings(
        ds.assign_attrs(cage_slip_ratio=0.5))


@pytest.mark.parametrize("kind", KINDS)
def test_text_attributes_share_one_netcdf_type(produced, kind):
    """The title (with "N·m") is stored as the other text attributes are: ncdump prints no
    global attribute as a NetCDF "string" (NC_CHAR throughout)."""
    ncdump = shutil.which("ncdump")
    if ncdump is None:
        pytest.skip("ncdump (Debian netcdf-bin) is not installed")
    text = subprocess.run([ncdump, "-h", str(produced[kind])], capture_output=True,
                          text=True, check=True).stdout
    glob = text.split("// global attributes:", 1)[1]
    assert ":title = " in glob and "string :" not in glob, glob[:400]
