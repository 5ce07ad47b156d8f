"""docs/performance.md quotes measurements kept in files: benchmarks/results/*.json (what
``python benchmarks/run.py NAME --json ...`` wrote), docs/figures/workprecision_spall.csv, and
constants in code. Each figure here is its file's value rounded as the page prints it, and a
ratio the page derives is the files' ratio within the rounding of its printed digits (a number
in the docs is generated or tested). The page's other tests: test_switch_cost_table.py (the
friction rows), test_cold_start_figure.py (the first-run figures),
test_defect_edges_table.py (the defects' cost), test_versions_workprecision_figures.py (the
default run at equal error). Figures measured without a kept result file (the statistics
ladder, ...) are not here."""

from __future__ import annotations

import ast
import csv
import json
import re
import tomllib
from pathlib import Path
from statistics import median

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "performance.md"
RESULTS = ROOT / "benchmarks" / "results"
#: samples per cage revolution of the default scene (the memory table's sample counts)
PER_REV = 200


def result(name: str) -> dict:
    return json.loads((RESULTS / f"{name}.json").read_text())


def section(title: str) -> str:
    """The raw text under the heading ``title`` (any level) up to the next heading."""
    text = PAGE.read_text(encoding="utf-8")
    m = re.search(rf"^#+ {re.escape(title)}\n", text, re.M)
    assert m, title
    end = re.compile(r"^#+ ", re.M).search(text, m.end())
    return text[m.end():end.start() if end else len(text)]


def flat(text: str) -> str:
    return " ".join(text.split())


def rows(text: str) -> dict[str, list[str]]:
    """The table rows of ``text`` by their first cell (separator lines left out)."""
    out = {}
    for line in text.splitlines():
        if line.startswith("|") and not re.fullmatch(r"[|\-\s]+", line):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            out[cells[0]] = cells
    return out


def row(text: str, start: str) -> list[str]:
    found = [cells for label, cells in rows(text).items() if label.startswith(start)]
    assert len(found) == 1, start
    return found[0]


def grab(pattern: str, text: str) -> tuple[str, ...]:
    m = re.search(pattern, flat(text))
    assert m, f"not on the page: {pattern}"
    return m.groups()


def half_unit(text: str) -> float:
    """Half a unit of the last digit ``text`` prints (1.07: 0.005; 1.7e-5: 5e-7; 177 174: 0.5)."""
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.partition(".")[2])
    return 0.5 * 10.0 ** (int(exponent or 0) - decimals)


def number(text: str) -> float:
    return float(text.replace(" ", "").replace("\u202f", "").replace("\u2212", "-"))


def printed(text: str, value: float, what: str = "", slack: float = 0.0) -> None:
    """``text`` is ``value`` rounded to its printed digits (``slack``: the rounding of printed
    factors a derived figure was computed from)."""
    t = text.replace(" ", "").replace("\u202f", "")
    assert abs(number(t) - value) <= (half_unit(t) + slack) * (1 + 1e-9), \
        f"{what}: the page prints {text}, its source gives {value:.6g}"


def per_repeat(rows_a: list[dict], rows_b: list[dict], key: str = "cpu_s") -> list[float]:
    return [a[key] / b[key] for a, b in zip(rows_a, rows_b)]


def avx512(cpu: str) -> bool:
    return "AVX-512" in cpu and "no AVX-512" not in cpu


def test_default_run_against_926583b():
    """"Default run" and "At a glance": `versions --old 926583b --repeat 3` (versions.json), the
    CPU ranges, the median of the per-repeat ratios, the steps; the CPU of the page's header."""
    cpu = lambda rs: [r["process_cpu_s"] for r in rs]  # noqa: E731
    s = section("Default run")
    # the two machines' measurements, each its file's: the Xeon's first, the AMD EPYC's second
    quoted = re.findall(r"process CPU \*\*([\d.]+)–([\d.]+) s against ([\d.]+)–([\d.]+) s, "
                        r"([\d.]+)×\*\*", flat(s))
    assert len(quoted) == 2, quoted
    for (lo, hi, old_lo, old_hi, ratio), name, machine in zip(
            quoted, ("versions-926583b-xeon", "versions"), ("Intel", "AMD EPYC")):
        got = result(name)
        old, new = got["rows"]["old"], got["rows"]["new"]
        assert len(old) == len(new) == 3 and got["cpu"].startswith(machine), name
        assert avx512(got["cpu"]) == (machine == "Intel"), name
        printed(lo, min(cpu(new)), f"{name}: new CPU, least")
        printed(hi, max(cpu(new)), f"{name}: new CPU, most")
        printed(old_lo, min(cpu(old)), f"{name}: 926583b's CPU, least")
        printed(old_hi, max(cpu(old)), f"{name}: 926583b's CPU, most")
        printed(ratio, median(per_repeat(new, old, "process_cpu_s")), f"{name}: CPU ratio")
        # what the paragraph concludes: the target of 0.20x is not met
        assert "**The target, 0.20×, is not met**" in flat(s) and float(ratio) > 0.20
    got = result("versions")
    old, new = got["rows"]["old"], got["rows"]["new"]
    (wall,) = grab(r"median of the per-repeat ratios; wall ([\d.]+)×", s)
    printed(wall, median(per_repeat(new, old, "process_wall_s")), "wall ratio")

    glance = row(section("At a glance"), "default run")
    cpu_s, lo, hi, steps = grab(r"([\d.]+) s of CPU for the whole process \(([\d.]+)–([\d.]+)\),"
                                r" ([\d ]+) IDA steps", glance[1])
    printed(cpu_s, median(cpu(new)), "default run's CPU")
    printed(lo, min(cpu(new)), "new CPU, least")
    printed(hi, max(cpu(new)), "new CPU, most")
    assert {r["steps"] for r in new} == {number(steps)}


def test_default_run_against_c15baa7():
    """"Default run": with every feature since c15baa7 switched off the default run took the
    median per-repeat ratio of versions-c15baa7.json's CPU, the same steps, 5 repeats, AVX-512."""
    got = result("versions-c15baa7")
    old, new = got["rows"]["old"], got["rows"]["new"]
    ratio, steps, repeat = grab(r"took \*\*([\d.]+)× the CPU\*\* of c15baa7, the code before "
                                r"them, with the same ([\d ]+) steps \(`--repeat (\d+)`, AVX-512",
                                section("Default run"))
    printed(ratio, median(per_repeat(new, old, "process_cpu_s")), "CPU against c15baa7")
    assert {r["steps"] for r in old + new} == {number(steps)}
    assert len(old) == len(new) == int(repeat) and got["same_trajectory"]
    assert avx512(got["cpu"])


def test_at_equal_error_session():
    """"At equal error": the session's CPU, load and repeats as versions-workprecision-926583b.json
    recorded them (its ratios: test_versions_workprecision_figures.py)."""
    got = result("versions-workprecision-926583b")
    repeat, lo, hi = grab(r"--workprecision --repeat (\d+) -o docs/figures`, [\d-]+, Intel Xeon "
                          r"AVX-512, load ([\d.]+)–([\d.]+);", section("Default run"))
    assert got["repeat"] == int(repeat) and avx512(got["cpu"]) and "Xeon" in got["cpu"]
    printed(lo, min(got["load_1min"]), "load, least")
    printed(hi, max(got["load_1min"]), "load, most")


def test_the_step_table_adds_up():
    """"What a step costs" is kernels-per-step.json (`kernels --per-step`): each part's calls
    per step, µs per call and µs per step (their product), the kernels' line their sum, the
    process CPU per step of the same run, and the shares the prose and "At a glance" quote."""
    got = result("kernels-per-step")
    ps = got["per_step"]
    assert avx512(got["cpu"]) and "Xeon" in got["cpu"]
    s = section("What a step costs")
    steps, load = grab(r"1 \+ 3 cage revolutions: ([\d ]+) steps; `kernels --per-step --repeats 7`"
                       r", results/kernels-per-step.json, load ([\d.]+)\)", s)
    assert number(steps) == ps["steps"]
    printed(load, got["load_1min_at_end"], "load")
    parts = 0.0
    for part in ps["rows"]:
        cells = row(s, part["part"])
        printed(cells[1], part["calls_per_step"], f"{part['part']}: calls per step")
        printed(cells[2], part["us_per_call"], f"{part['part']}: µs per call")
        printed(cells[3], part["us_per_step"], f"{part['part']}: µs per step")
        # the product of the printed factors, within their rounding
        slack = (half_unit(cells[1]) * number(cells[2]) + half_unit(cells[2]) * number(cells[1]))
        printed(cells[3], number(cells[1]) * number(cells[2]), f"{part['part']}: product",
                slack=slack)
        parts += part["us_per_step"]
    kernels = row(s, "**compiled kernels by these counts**")[3].strip("*")
    printed(kernels, parts, "the kernels: the sum of the parts")
    printed(kernels, ps["kernels_us_per_step"], "the kernels")
    process = row(s, "**`simulate`'s process CPU over the steps")[3].strip("*")
    printed(process, ps["process_us_per_step"], "the run's CPU per step")
    share = ps["kernels_us_per_step"] / ps["process_us_per_step"]
    residual = ps["rows"][0]["us_per_step"] / ps["process_us_per_step"]
    rest, = grab(r"the rest \(([\d.]+) µs\) is IDA's own work", s)
    printed(rest, ps["process_us_per_step"] - ps["kernels_us_per_step"], "the rest of a step")
    # the host against the Xeon of "Default run": the same steps, the CPU of the whole run
    xeon = result("versions-926583b-xeon")["rows"]["new"]
    assert {r["steps"] for r in xeon} == {ps["steps"]}
    host, = grab(r"this run ([\d.]+)× the CPU of\s+results/versions-926583b-xeon.json's whole",
                 s)
    printed(host, ps["process_cpu_s"] / median(r["process_cpu_s"] for r in xeon), "host")
    # perf's split of the same kind of step (profile.json): what the page quotes, and that
    # the compiled code and IDA's own work are what it says they are, of the sampled CPU
    prof = result("profile")
    assert avx512(prof["cpu"]) and "Xeon" in prof["cpu"] and not prof["scikit_sundae"]
    runs, load_p = grab(r"`profile --runs (\d+)`, results/profile.json, load ([\d.]+);", s)
    assert prof["runs"] == int(runs)
    printed(load_p, prof["load_1min_at_end"], "profile's load")
    by = {r["category"].split(":")[0]: r for r in prof["rows"]}
    assert abs(sum(r["share"] for r in prof["rows"]) - 1) < 1e-9
    comp, libm, ida_pct, ida_us, py = grab(
        r"compiled code ([\d.]+) % and its libm ([\d.]+) %, IDA and its vector operations "
        r"([\d.]+) %\s+\(([\d.]+) µs per step\), Python and numpy ([\d.]+) %", s)
    kernels_cat = [r for r in prof["rows"] if r["category"].startswith("numba kernels")]
    printed(comp, 100 * kernels_cat[0]["share"], "perf: compiled code")
    printed(libm, 100 * kernels_cat[1]["share"], "perf: libm")
    printed(ida_pct, 100 * by["IDA itself and N_Vector operations"]["share"], "perf: IDA")
    printed(ida_us, by["IDA itself and N_Vector operations"]["us_per_step"], "perf: IDA µs")
    printed(py, 100 * prof["rows"][-1]["share"], "perf: Python")
    # "not where a step can halve": IDA's own work is under a quarter of a step
    assert by["IDA itself and N_Vector operations"]["share"] < 0.25
    res_pct, ker_pct = grab(r"The residual is (\d+) % of a step, the compiled kernels (\d+) %", s)
    printed(res_pct, 100 * residual, "the residual's share")
    printed(ker_pct, 100 * share, "the kernels' share")
    glance = row(section("At a glance"), "one IDA step")[1]
    printed(grab(r"(\d+) % of it in the compiled kernels", glance)[0], 100 * share,
            "At a glance: the kernels' share")
    ida = section("IDA's settings at equal error")
    calls, = grab(r"fewer residual calls per step \(([\d.]+); 1 at best\)", ida)
    printed(calls, ps["rows"][0]["calls_per_step"], "residual calls per step")
    printed(grab(r"below the compiled kernels' share of a step \((\d+) %\)", ida)[0],
            100 * share, "the kernels' share")
    target, today, per_step = grab(r"At today's steps, ([\d.]+)× the turn-1 core is ([\d.]+)× "
                                   r"today's CPU per step \(\1 / ([\d.]+)\)", ida)
    # the ratio is the Xeon's of "Default run" (the first quoted there)
    assert per_step == grab(r"process CPU \*\*[\d.]+–[\d.]+ s against [\d.]+–[\d.]+ s, "
                            r"([\d.]+)×\*\*", section("Default run"))[0]
    printed(today, float(target) / float(per_step), "the target per step",
            slack=float(target) * half_unit(per_step) / float(per_step) ** 2)
    assert float(today) < share, "the target per step lies below the kernels' share"


def test_the_step_ratio_prose_is_the_results():
    """"IDA's settings at equal error": the earlier growth's steps, Jacobians and CPU."""
    got = result("switches-step-ratios")
    data, default = got["rows"], got["rows"]["default"]
    key = "ida eta_max_fx=1.5"
    st, jac, cpu = grab(r"growth from 1\.5× on: ([\d.]+)× the steps\) changes c_j at each "
                        r"growth, so refreshes the Jacobian ([\d.]+)× as often and costs "
                        r"([\d.]+)× the CPU", section("IDA's settings at equal error"))
    printed(st, data[key][-1]["steps"] / default[-1]["steps"], "steps")
    printed(jac, data[key][-1]["jacobians"] / default[-1]["jacobians"], "Jacobians")
    printed(cpu, median(per_repeat(data[key], default)), "CPU")


def test_where_the_steps_go():
    """"Where the steps go": the steps without pocket contact or without drag, and at rtol 1e-5,
    against the default's, in switches.json."""
    got = result("switches")["rows"]
    share, saved = grab(r"the window takes (\d+) % of the steps; 10× looser rtol saves (\d+) %",
                        section("Where the steps go"))
    default = got["default"][0]["steps"]
    for key in ("no cage (no pocket contact)", "no lubricant drag"):
        printed(share, 100 * got[key][0]["steps"] / default, key)
    printed(saved, 100 * (1 - got["rtol 1e-5"][0]["steps"] / default), "rtol 1e-5")


RR_MIXED = "physics.rolling_resistance=biboulet_houpert,physics.lubrication=mixed"


def _mode_figures(r: dict) -> tuple[float, float, float, float, float]:
    """(median kHz, least, most, median ζ, steps per period) of one switch of ``--modes``."""
    f = [x / 1e3 for x in r["frequency_Hz"]]
    return median(f), min(f), max(f), median(r["damping_ratio"]), r["steps_per_period"]


def test_where_the_steps_go_modes():
    """"Where the steps go": the fastest lightly damped mode of the default run and of rolling
    resistance with mixed lubrication, their steps per period, the oscillator's, and the step
    ratio, from switches-modes.json; recomputed from its lists (not its printed table)."""
    got = result("switches-modes")
    modes = got["modes"]
    assert got["window"]["numerics.cage_revolutions"] == 1.0
    s = section("Where the steps go")
    n_states, f, lo, hi, zeta, step, per = grab(
        r"at (\d+) states of the default run's recorded revolution has its fastest lightly damped "
        r"mode \(ζ ≤ 0.2\) in a roller's skew rate, at ([\d.]+) kHz median \(([\d.]+)–([\d.]+), "
        r"ζ ([\d.]+)\); the run steps ([\d.]+) µs on average, (\d+) steps per period of it", s)
    d = modes["default"]
    assert len(d["frequency_Hz"]) == int(n_states) and d["moves_most"] == "skew_rate"
    for text, value in zip((f, lo, hi, zeta, per), _mode_figures(d)):
        printed(text, value, "default's mode")
    printed(step, d["mean_step_s"] * 1e6, "default's mean step")
    printed(per, 1.0 / (median(d["frequency_Hz"]) * d["mean_step_s"]), "steps per period")
    lo_o, hi_o = grab(r"IDA alone on an undamped oscillator at rtol 1e-6 takes (\d+)–(\d+)", s)
    osc = modes["oscillator_steps_per_period"]
    assert osc["rtol"] == 1e-6
    each = [v for k, v in osc.items() if k.startswith("atol")]
    printed(lo_o, min(each), "oscillator")
    printed(hi_o, max(each), "oscillator")
    f2, per2, ratio = grab(r"press the bars harder: ([\d.]+) kHz, (\d+) steps per period, "
                           r"([\d.]+)× the steps", s)
    m = modes[RR_MIXED]
    assert m["moves_most"] == "skew_rate"
    printed(f2, _mode_figures(m)[0], "RR + mixed mode")
    printed(per2, m["steps_per_period"], "RR + mixed steps per period")
    printed(ratio, m["steps"] / d["steps"], "RR + mixed steps")


def test_the_inner_spall_rings_its_ring():
    """"A defect": the inner spall's ring mode (frequency, damping) and the steps per period of
    the runs with and without the spall, switches-modes-inner-spall.json."""
    modes = result("switches-modes-inner-spall")["modes"]
    f, zeta, per, step = grab(
        r"the ring's, ([\d.]+) kHz with ζ ([\d.]+) \(its support's damping\), which the defect "
        r"run follows at (\d+) steps per period and the healthy run never excites \(a step every "
        r"(\d+) µs", section("Cost of each switch"))
    spall, healthy = modes["default"], modes["no defects or waviness"]
    for r in (spall, healthy):
        assert r["moves_most"].startswith("ring")
        printed(f, _mode_figures(r)[0], "ring mode")
        printed(zeta, _mode_figures(r)[3], "ring damping")
    printed(per, spall["steps_per_period"], "defect run")
    printed(step, healthy["mean_step_s"] * 1e6, "healthy run's step")
    assert healthy["steps_per_period"] < 1.0


#: "Cost of each switch": the table's row -> its switch in switches.json (the ¹ rows:
#: test_switch_cost_table.py)
SWITCHES = {
    "20 slices instead of 10": "20 slices",
    "5 slices": "5 slices",
    "slide-to-roll traction law": "slide-to-roll traction law",
    "the paper's slip kinematics": "paper slip kinematics",
    "no pocket contact": "no cage (no pocket contact)",
    "no lubricant drag": "no lubricant drag",
    "rtol 1e-5": "rtol 1e-5",
    "rtol 1e-7": "rtol 1e-7",
    "SuperLU_MT linear solver": "SuperLU_MT linear solver",
    "dense linear solver": "dense linear solver",
    "finite-difference Jacobian": "finite-difference Jacobian",
    "`IDASetSuppressAlg`": "IDASetSuppressAlg",
    "scikit-sundae's Python callbacks": "scikit-sundae callbacks",
    "Newmark-β, h = 2 µs": "Newmark-beta, h = 2 µs",
}


def test_mixed_lubrication_in_a_full_film():
    """The friction footnote's full-film sentence: mixed lubrication against the full-film run
    of harris36 (switches-mixed-full-film.json, -before.json): median and range of the
    per-repeat CPU ratios, the same steps in both, and the load the page states."""
    key = "physics.lubrication=mixed"
    now, now_lo, now_hi, old, old_lo, old_hi, load, repeats = grab(
        r"mixed lubrication costs \*\*([\d.]+)×\*\* \(([\d.]+)–([\d.]+)\) the full-film run, "
        r"against ([\d.]+)× \(([\d.]+)–([\d.]+)\) before \(AVX2, load ([\d.]+), (\d+) repeats",
        section("Cost of each switch"))
    for (mid, lo, hi), name in (((now, now_lo, now_hi), "switches-mixed-full-film"),
                                ((old, old_lo, old_hi), "switches-mixed-full-film-before")):
        r = result(name)
        assert not avx512(r["cpu"]) and r["case"] == "paper/harris36_5000rpm"
        ratios = per_repeat(r["rows"][key], r["rows"]["default"])
        assert len(ratios) == int(repeats)
        printed(mid, median(ratios), name)
        printed(lo, min(ratios), name)
        printed(hi, max(ratios), name)
        printed(load, r["load_1min_at_end"], name, slack=0.05)
        assert {row["steps"] for row in r["rows"][key] + r["rows"]["default"]} == \
            {r["rows"]["default"][0]["steps"]}


def test_each_switch_row_is_the_benchmark_result():
    """The median per-repeat CPU ratio, its range, the steps and residual calls of each switch in
    benchmarks/results/switches.json (`switches --repeat 3`, 1 + 1 cage revolutions)."""
    got = result("switches")
    data, default = got["rows"], got["rows"]["default"]
    assert got["window"] == {"numerics.warmup_cage_revolutions": 1.0,
                             "numerics.cage_revolutions": 1.0}
    assert got["cpu"].startswith("AMD EPYC (AVX2, no AVX-512)")
    s = section("Cost of each switch")
    assert "`python benchmarks/run.py switches --repeat 3`" in flat(s)
    (cpu_s,) = grab(r"^1 \(([\d.]+) s\)$", row(s, "default")[2])
    printed(cpu_s, median(r["cpu_s"] for r in default), "the default's CPU")
    printed(row(s, "default")[3], default[0]["steps"], "default: steps")
    printed(row(s, "default")[4], default[0]["residual_calls"], "default: residual calls")
    for label, key in SWITCHES.items():
        cells = rows(s)[label]
        ratio, lo, hi = grab(r"^([\d.]+) \(([\d.]+)–([\d.]+)\)$", cells[2])
        each = per_repeat(data[key], default)
        assert len(each) == 3, key
        printed(ratio, got["cpu_ratio_to_default"][key], key)
        printed(ratio, median(each), key)
        printed(lo, min(each), f"{key}: least")
        printed(hi, max(each), f"{key}: most")
        assert {r["steps"] for r in data[key]} == ({0} if cells[3] == "–" else {number(cells[3])})
        assert {r["residual_calls"] for r in data[key]} == {number(cells[4])}, key


def test_each_effect_row_is_the_benchmark_result():
    """The rows marked ² of "Cost of each switch": `switches --only default --repeat 3 --warmup 1
    --revolutions 1 --try ...` (switches-effects.json), each row's `--set` pairs its `--try`:
    the median per-repeat CPU ratio, its range, the steps and residual calls of the last
    repeat, and the footnote's machine and default CPU."""
    got = result("switches-effects")
    data, default = got["rows"], got["rows"]["default"]
    assert got["window"] == {"numerics.warmup_cage_revolutions": 1.0,
                             "numerics.cage_revolutions": 1.0}
    assert avx512(got["cpu"]) and "Xeon" in got["cpu"]
    s = section("Cost of each switch")
    (cpu_s,) = grab(r"² 2026-12-01, Intel Xeon AVX-512 \(default ([\d.]+) s\)", s)
    printed(cpu_s, median(r["cpu_s"] for r in default), "the default's CPU")
    marked = {label: cells for label, cells in rows(s).items() if label.endswith(" ²")}
    assert len(marked) == len(data) - 1, sorted(marked)
    for label, cells in marked.items():
        key = ",".join(re.findall(r"`--set ([^`]+)`", cells[1]))
        ratio, lo, hi = grab(r"^([\d.]+) \(([\d.]+)–([\d.]+)\)$", cells[2])
        each = per_repeat(data[key], default)
        assert len(each) == 3, key
        printed(ratio, median(each), key)
        printed(lo, min(each), f"{key}: least")
        printed(hi, max(each), f"{key}: most")
        assert data[key][-1]["steps"] == number(cells[3]), key
        assert data[key][-1]["residual_calls"] == number(cells[4]), key
    # the rolling-resistance laws' loops side by side, before and after, on the same steps
    before, after = result("switches-rolling-laws-before"), result("switches-rolling-laws")
    for law, name in (("Goksem & Hargreaves", "goksem_hargreaves"),
                      ("Zhou & Hoeprich", "zhou_hoeprich")):
        key = f"physics.rolling_resistance={name}"
        was, now = grab(rf"{law} ([\d.]+)× → ([\d.]+)×", s)
        printed(was, before["cpu_ratio_to_default"][key], f"{name}, before")
        printed(now, after["cpu_ratio_to_default"][key], f"{name}, after")
        assert {r["steps"] for r in before["rows"][key]} == {r["steps"]
                                                             for r in after["rows"][key]}


def test_the_friction_footnote_is_the_results():
    """The footnote of "Cost of each switch": switches-friction.json (its default's CPU, the
    steps and calls per step of rolling resistance + mixed lubrication), -before/-after.json (the
    thermal run side by side), -limiters.json (the second session's CPU, the step limiters),
    kernels-passes-*.json (the residual's and Jacobian's passes)."""
    key = "physics.rolling_resistance=biboulet_houpert,physics.lubrication=mixed"
    s = section("Cost of each switch")
    fr = result("switches-friction")
    (cpu_s,) = grab(r"load [\d.]+–[\d.]+ \(default ([\d.]+) s\)", s)
    printed(cpu_s, median(r["cpu_s"] for r in fr["rows"]["default"]), "the default's CPU")

    before, after = grab(r"\(([\d.]+)× → ([\d.]+)× side by side, "
                         r"results/switches-friction-after.json, -before.json\)", s)
    for text, name in ((before, "switches-friction-before"), (after, "switches-friction-after")):
        printed(text, result(name)["cpu_ratio_to_default"]["physics.thermal=steady"], name)

    steps_x, per_step_x, second, lo, hi = grab(
        r"together cost \*\*([\d.]+)× the steps and ([\d.]+)× per step\*\* \(([\d.]+)×, "
        r"([\d.]+)–([\d.]+), the CPU in a second session", s)
    both, default = fr["rows"][key][0], fr["rows"]["default"][0]
    printed(steps_x, both["steps"] / default["steps"], "steps with both")
    printed(per_step_x, fr["cpu_ratio_to_default"][key] * default["steps"] / both["steps"],
            "CPU per step with both")
    (again,) = grab(r"At ([\d.]+)× the steps", s)
    printed(again, both["steps"] / default["steps"], "steps with both")
    lim = result("switches-friction-limiters")
    each = per_repeat(lim["rows"][key], lim["rows"]["default"])
    printed(second, median(each), "second session")
    printed(lo, min(each), "second session, least")
    printed(hi, max(each), "second session, most")

    # the same on a quiet AVX-512 Xeon, measured afresh (switches-friction-xeon.json, the
    # kernels' passes of both trees of switches there), and the two CPUs' passes compared
    xe = result("switches-friction-xeon")
    assert avx512(xe["cpu"]) and "Xeon" in xe["cpu"] and not avx512(lim["cpu"])
    load_x, ratio_x, lo_x, hi_x, steps_xe, per_xe = grab(
        r"On a quiet Intel Xeon with AVX-512 \(load ([\d.]+), results/switches-friction-xeon"
        r"\.json; 512-bit vectors, \"Vector width\"\) they cost \*\*([\d.]+)×\*\* "
        r"\(([\d.]+)–([\d.]+)\): ([\d.]+)× the steps, "
        r"([\d.]+)× per step", s)
    printed(load_x, xe["load_1min_at_end"], "Xeon: load")
    each = per_repeat(xe["rows"][key], xe["rows"]["default"])
    printed(ratio_x, median(each), "Xeon: CPU with both")
    printed(lo_x, min(each), "Xeon: least")
    printed(hi_x, max(each), "Xeon: most")
    st_x = xe["rows"][key][-1]["steps"] / xe["rows"]["default"][-1]["steps"]
    printed(steps_xe, st_x, "Xeon: steps")
    printed(per_xe, median(each) / st_x, "Xeon: per step")
    mx, pl = result("kernels-passes-rr-mixed-xeon"), result("kernels-passes-default-xeon")
    assert avx512(mx["cpu"]) and avx512(pl["cpu"]) and mx["overrides"] and not pl["overrides"]
    r_x, r0_x, c_x, cf_x = grab(r"its residual takes ([\d.]+) µs a call against ([\d.]+), the "
                                r"contact pass ([\d.]+) against ([\d.]+) with full-film", s)
    printed(r_x, mx["median_us"]["residual"]["bearingdae"], "Xeon: residual with both")
    printed(r0_x, pl["median_us"]["residual"]["bearingdae"], "Xeon: residual")
    printed(c_x, mx["passes_us"]["contact"], "Xeon: contact pass")
    printed(cf_x, mx["passes_us"]["contact_full_film"], "Xeon: full-film contact pass")
    amd = result("kernels-passes-rr-mixed")
    ff_x, mixed_x = grab(r"runs the full-film contact pass ([\d.]+)× as fast as the AMD EPYC, "
                         r"the mixed one ([\d.]+)×", s)
    printed(ff_x, amd["passes_us"]["contact_full_film"] / mx["passes_us"]["contact_full_film"],
            "full-film pass, AMD over Xeon")
    printed(mixed_x, amd["passes_us"]["contact"] / mx["passes_us"]["contact"],
            "mixed pass, AMD over Xeon")
    calls, jac, calls0, jac0 = grab(r"\(([\d.]+) residual calls and ([\d.]+) Jacobians a step "
                                    r"against ([\d.]+) and ([\d.]+)\)", s)
    printed(calls, both["residual_calls"] / both["steps"], "residual calls per step, both")
    printed(jac, both["jacobians"] / both["steps"], "Jacobians per step, both")
    printed(calls0, default["residual_calls"] / default["steps"], "residual calls per step")
    printed(jac0, default["jacobians"] / default["steps"], "Jacobians per step")

    mixed, plain = result("kernels-passes-rr-mixed"), result("kernels-passes-default")
    assert mixed["overrides"] == {"physics.rolling_resistance": "biboulet_houpert",
                                  "physics.lubrication": "mixed"} and not plain["overrides"]
    passes, us = mixed["passes_us"], lambda d, k: d["median_us"][k]["bearingdae"]  # noqa: E731
    res, res0 = grab(r"The residual takes ([\d.]+) µs a call against ([\d.]+)", s)
    printed(res, us(mixed, "residual"), "residual with both")
    printed(res0, us(plain, "residual"), "residual")
    contact, full_film = grab(r"the contact pass ([\d.]+) µs against ([\d.]+) with the "
                              r"full-film", s)
    printed(contact, passes["contact"], "contact pass")
    printed(full_film, passes["contact_full_film"], "contact pass, full film")
    (rr,) = grab(r"the rolling resistance pass ([\d.]+) µs", s)
    printed(rr, passes["rolling_resistance"], "rolling resistance pass")
    jacobian, jacobian0, slopes, slopes0, rr_block = grab(
        r"the Jacobian ([\d.]+) µs against ([\d.]+) \(contact slopes ([\d.]+) against ([\d.]+), "
        r"the rolling resistance block ([\d.]+)\)", s)
    printed(jacobian, us(mixed, "jacobian"), "Jacobian with both")
    printed(jacobian0, us(plain, "jacobian"), "Jacobian")
    printed(slopes, passes["contact_slopes"], "contact slopes")
    printed(slopes0, passes["contact_slopes_full_film"], "contact slopes, full film")
    printed(rr_block, passes["rolling_resistance_jacobian"], "rolling resistance block")

    share, share_both, step, step_both = grab(
        r"limits (\d+) % of them in the default run and (\d+) % with both, at a median step of "
        r"([\d.]+) against ([\d.]+) µs", s)
    limiters = lim["limiters"]
    printed(share, 100 * limiters["default"]["step_limiters"]["skew_rate"], "skew rate's share")
    printed(share_both, 100 * limiters[key]["step_limiters"]["skew_rate"], "skew rate's share")
    printed(step, 1e6 * limiters["default"]["median_step_s"], "median step")
    printed(step_both, 1e6 * limiters[key]["median_step_s"], "median step with both")


def test_the_defect_paragraph_rest():
    """"A defect" beyond the ratios of test_defect_edges_table.py: the outer spall's steps, the
    roller spall's healthy scene (steps, CPU), the baseline's CPU over the window, the window and
    repeats of every file, and the inner spall's samples per cage revolution (its case file)."""
    s = section("Cost of each switch")
    defects, base = result("switches-defects"), result("switches-defects-baseline")
    roller = result("switches-roller-spall")
    (steps_x,) = grab(r"of its scene without `\[\[defects\]\]` and ([\d.]+)× the steps", s)
    rs = defects["rows"]
    printed(steps_x, rs["default"][0]["steps"] / rs["no defects or waviness"][0]["steps"],
            "outer spall's steps")
    healthy, spalled, fixed = grab(r"\((\d+) steps against ([\d ]+); ([\d.]+) s of fixed cost\)",
                                   s)
    assert roller["rows"]["no defects or waviness"][0]["steps"] == number(healthy)
    assert roller["rows"]["default"][0]["steps"] == number(spalled)
    printed(fixed, median(r["cpu_s"] for r in roller["rows"]["no defects or waviness"]),
            "the roller spall's scene without it")
    (base_s,) = grab(r"over the same window \(yang20_baseline, ([\d.]+) s\)", s)
    printed(base_s, median(r["cpu_s"] for r in base["rows"]["default"]), "baseline's CPU")
    repeat, warmup, revs = grab(r"--only \"no defects or waviness\" --repeat (\d+) --warmup "
                                r"([\d.]+) --revolutions ([\d.]+)`", s)
    for name in ("switches-defects", "switches-defects-baseline", "switches-roller-spall",
                 "switches-outer-waviness", "switches-inner-spall",
                 "switches-roller-spall-clearance"):
        got = result(name)
        assert got["window"]["numerics.warmup_cage_revolutions"] == float(warmup), name
        assert got["window"]["numerics.cage_revolutions"] == float(revs), name
        assert all(len(r) == int(repeat) for r in got["rows"].values()), name
        assert avx512(got["cpu"]) == (name == "switches-inner-spall"), name
    (clearance,) = grab(r"`--set bearing.radial_clearance_mm=([\d.]+)`, whose healthy run", s)
    assert result("switches-roller-spall-clearance")["window"][
        "bearing.radial_clearance_mm"] == float(clearance)
    (per_rev,) = grab(r"Intel Xeon AVX-512, load [\d.]+, at the case's (\d+) samples per cage "
                      r"revolution; switches-inner-spall.json", s)
    case = tomllib.loads((ROOT / "cases" / "defects" / "inner_spall.toml").read_text())
    assert case["numerics"]["samples_per_cage_revolution"] == int(per_rev)


def test_dense_output_is_the_results():
    """"Dense output" and "At a glance": dense-output.json (`dense-output --repeat 3`, the CPU of
    each repeat, the median peak RSS, the largest pocket force at every step and sampled, the
    median per-repeat CPU ratio and the CPU per extra sample) and dense-output-cli.json."""
    got = result("dense-output")
    assert avx512(got["cpu"])
    s = section("Dense output")
    for label, key in (("200 (the default)", "200"), ("4 000", "4000")):
        cells, runs = rows(s)[label], got["rows"][key]
        assert len(runs) == 3
        assert {r["samples"] for r in runs} == {number(cells[1])}
        assert {r["steps"] for r in runs} == {number(cells[2])}
        cpu = cells[3].split(", ")
        assert len(cpu) == len(runs), cells[3]
        for text, r in zip(cpu, runs):
            printed(text, r["cpu_s"], f"{label}: CPU")
        printed(cells[4].removesuffix(" MB"), median(r["max_rss_MB"] for r in runs), "peak RSS")
        every, sampled = re.fullmatch(r"\*\*([\d.]+) N\*\* / ([\d.]+) N", cells[5]).groups()
        for r in runs:
            printed(every, max(max(pair) for pair in r["cage_force_max_N"]), "largest, every step")
            printed(sampled, r["sampled_peak_cage_force_N"], "largest, sampled")
    ratio, per_sample = grab(r"costs \*\*([\d.]+)× the CPU\*\*, \*\*([\d.]+) ms per extra "
                             r"sample\*\*", s)
    printed(ratio, got["cpu_ratio_to_first"]["4000"], "CPU, 4 000 against 200")
    printed(per_sample, got["cpu_ms_per_extra_sample"]["4000"], "CPU per extra sample")
    cli = result("dense-output-cli")
    assert cli["cli"] and all(len(r) == 3 for r in cli["rows"].values())
    wall, cpu = grab(r"4 000 samples per revolution take ([\d.]+)× the wall time of 200, "
                     r"([\d.]+)× the CPU", s)
    printed(wall, cli["wall_ratio_to_first"]["4000"], "bearingdae run, wall")
    printed(cpu, cli["cpu_ratio_to_first"]["4000"], "bearingdae run, CPU")

    glance = section("At a glance")
    about, ratio = grab(r"≈ ([\d.]+) ms of CPU \(AVX-512, [\d-]+\); 4 000 samples per revolution "
                        r"cost ([\d.]+)× the CPU of 200", row(glance, "one output sample")[1])
    printed(about, got["cpu_ms_per_extra_sample"]["4000"], "CPU per sample")
    printed(ratio, got["cpu_ratio_to_first"]["4000"], "CPU, 4 000 against 200")
    wall, cpu = grab(r"([\d.]+)× the wall time of 200 \(([\d.]+)× the CPU",
                     row(glance, "the same with `bearingdae run`")[1])
    printed(wall, cli["wall_ratio_to_first"]["4000"], "bearingdae run, wall")
    printed(cpu, cli["cpu_ratio_to_first"]["4000"], "bearingdae run, CPU")


def test_memory_is_the_results():
    """"Memory" and "At a glance": memory.json's peak RSS, CPU and file size at 3 and 30 recorded
    cage revolutions and their peaks' ratio; the block and checkpoint sizes are the code's."""
    got = result("memory")
    assert avx512(got["cpu"])
    by_revs = {round(r["cage_revolutions"]): r for r in got["rows"]}
    s = section("Memory")
    table = rows(s)
    for label, revs in (("3 (the default)", 3), ("30", 30)):
        cells, r = table[label], by_revs[revs]
        assert number(cells[1]) == revs * PER_REV + 1
        (rss,) = re.match(r"\*\*(\d+) MB\*\*", cells[2]).groups()
        printed(rss, r["max_rss_MB"], f"{revs} revolutions: peak RSS")
        printed(cells[3].removesuffix(" s"), r["cpu_s"], f"{revs} revolutions: CPU")
        printed(cells[4].removesuffix(" MB"), r["file_MB"], f"{revs} revolutions: file")
    (ratio,) = grab(r"\(([\d.]+)× the 3-revolution peak\)", table["30"][2])
    printed(ratio, by_revs[30]["max_rss_MB"] / by_revs[3]["max_rss_MB"], "peak, 30 against 3")
    assert number(row(s, "300")[1]) == 300 * PER_REV + 1

    three, thirty, _ = grab(r"(\d+) / (\d+) / (\d+) MB", row(section("At a glance"),
                                                            "peak memory")[1])
    printed(three, by_revs[3]["max_rss_MB"], "peak RSS at 3")
    printed(thirty, by_revs[30]["max_rss_MB"], "peak RSS at 30")

    block, last = grab(r"in blocks of ≤ (\d+) samples .* the checkpoint's last ≤ ([\d ]+),", s)
    code = {"BLOCK_SAMPLES": ROOT / "bearingdae" / "results" / "streamed_netcdf.py",
            "SEGMENT_SAMPLES": ROOT / "bearingdae" / "run" / "segments.py"}
    value = {k: int(re.search(rf"^{k} = (\d+)$", p.read_text(), re.M).group(1))
             for k, p in code.items()}
    assert value == {"BLOCK_SAMPLES": number(block), "SEGMENT_SAMPLES": number(last)}


#: "Cold start": the compile table's entry point -> its name in cold-start.json
ENTRY_POINTS = {
    "residual, from Python": "residual (initial state, from Python)",
    "IDA residual callback": "IDA residual callback",
    "block-arrow linear solver": "block-arrow linear solver (6 ops)",
    "IDA analytic Jacobian callback": "IDA analytic Jacobian callback",
    "IDA per-step extremes hook": "IDA per-step extremes hook",
    "projection of the samples": "projection of the samples",
    "EHL film": "EHL film (post-processing)",
}


def test_cold_start_compile_table_is_the_results():
    """Each entry point's compile CPU before -> now and its specialisations, the sums, in their
    own cells (test_cold_start_figure.py checks the seconds' set); the session's load, rounds and
    date; the cold/warm ratio's two decimals round to the file's one."""
    got = result("cold-start")
    compiled = got["compile_cpu_s"]
    before = compiled[next(k for k in compiled if k != "this checkout")]
    now = compiled["this checkout"]
    s = section("Cold start")
    cells = {}
    for line in rows(s).values():
        for label, value in zip(line[0::2], line[1::2]):
            cells[label] = value
    for label, key in ENTRY_POINTS.items():
        old, new, count = re.fullmatch(r"([\d.]+) → ([\d.]+) \((\d+)\)", cells[label]).groups()
        printed(old, before[key][0], f"{label}: before")
        printed(new, now[key][0], f"{label}: now")
        assert int(count) == now[key][1], label
    old, new = re.fullmatch(r"([\d.]+) → ([\d.]+)", cells["sum"]).groups()
    printed(old, sum(v[0] for v in before.values()), "sum before")
    printed(new, sum(v[0] for v in now.values()), "sum now")
    date, load, ratio = grab(r"\(benchmarks/results/cold-start.json; ([\d-]+), AVX-512, load "
                             r"([\d.]+)\): .*\*\*2×\*\* \(([\d.]+);", s)
    assert date == got["date"] and avx512(got["cpu"])
    printed(load, got["load_1min"], "load")
    assert abs(float(ratio) - got["cold_over_warm"]) <= 0.05 + 1e-9, (ratio, got["cold_over_warm"])
    (repeats,) = grab(r"`cold-start --root <before> --repeats (\d+) --write` times", s)
    assert got["rounds"] == int(repeats)
    (compile_load,) = grab(r"--compile --root <before> --repeats \d+ --write`: one process, "
                           r"empty cache; load ([\d.]+);", s)
    printed(compile_load, got["compile_load_1min"], "compile load")


def test_sweeps_are_the_results():
    """"Sweeps" and "At a glance": paper.json (wall time, CPU per worker, runs) and
    sweep-scaling.json (the sessions' load range, the speed-ups, the repeats)."""
    paper = result("paper")
    s = section("Sweeps")
    workers, runs, wall, cpu = grab(r"\(`paper --workers (\d+)`: (\d+) runs, \d+ figures\) took "
                                    r"\*\*([\d.]+) min of wall time at load [\d.]+–[\d.]+\*\*, "
                                    r"([\d.]+) min of CPU per core", s)
    assert paper["workers"] == int(workers) and paper["runs"] == int(runs)
    printed(wall, paper["wall_s"] / 60, "paper set, wall")
    printed(cpu, paper["cpu_all_s"] / paper["workers"] / 60, "paper set, CPU per core")
    glance = row(section("At a glance"), "paper set")
    runs, workers = grab(r"\((\d+) runs, \d+ figures\), (\d+) workers", glance[0])
    assert paper["workers"] == int(workers) and paper["runs"] == int(runs)
    wall, cpu = grab(r"([\d.]+) min wall at load [\d.]+; ([\d.]+) min of CPU per core", glance[1])
    printed(wall, paper["wall_s"] / 60, "paper set, wall")
    printed(cpu, paper["cpu_all_s"] / paper["workers"] / 60, "paper set, CPU per core")

    scaling = result("sweep-scaling")
    workers, repeat, lo, hi, first, second = grab(
        r"\(`sweep-scaling --workers ([\d ]+) --repeat (\d+)`, load ([\d.]+)–([\d.]+): speed-up "
        r"([\d.]+) and ([\d.]+)\)", s)
    sessions = scaling["sessions"]
    assert all(sorted(x["rows"]) == workers.split() for x in sessions)
    assert all(len(r) == int(repeat) for x in sessions for r in x["rows"].values())
    loads = [r["load"] for x in sessions for rs in x["rows"].values() for r in rs]
    printed(lo, min(loads), "load, least")
    printed(hi, max(loads), "load, most")
    for text, x in zip((first, second), sessions):
        printed(text, x["speedup"][workers.split()[-1]], "speed-up")


def test_the_spall_work_precision_is_its_csv():
    """"A defect scene": docs/figures/workprecision_spall.csv, IDA at rtol 1e-6 (time, errors)
    and the longest Newmark step that reaches its cage-speed error, against the reference."""
    with open(ROOT / "docs" / "figures" / "workprecision_spall.csv", newline="") as f:
        table = list(csv.DictReader(f))
    ida = {float(r["rtol"]): r for r in table if r["solver"] == "ida"}
    reference = [r for r in table if r["is_reference"] == "1"]
    ida_s, cage, force, ref_rtol, h_us, nm_s, ratio, nm_force = grab(
        r"\*\*IDA at rtol 1e-6 took ([\d.]+) s\*\* at a cage-speed error of ([\d.]+e-\d+) "
        r"\(contact force ([\d.]+e-\d+), relative RMS against rtol (1e-\d+)\); Newmark-β reached "
        r"that cage-speed error at h = (\d+) µs in ([\d.]+) s \(([\d.]+)×\), contact force "
        r"([\d.]+e-\d+)",
        section("A defect scene"))
    assert len(reference) == 1 and float(reference[0]["rtol"]) == float(ref_rtol)
    r6 = ida[1e-6]
    printed(ida_s, float(r6["wall_s"]), "IDA's time")
    printed(cage, float(r6["cage_speed_rel_rms"]), "IDA's cage-speed error")
    printed(force, float(r6["contact_force_rel_rms"]), "IDA's contact-force error")
    reached = [r for r in table if r["solver"] == "newmark" and r["status"] == "ok"
               and float(r["cage_speed_rel_rms"]) <= float(r6["cage_speed_rel_rms"])]
    nm = max(reached, key=lambda r: float(r["value"]))
    printed(h_us, float(nm["value"]) * 1e6, "Newmark's step")
    printed(nm_s, float(nm["wall_s"]), "Newmark's time")
    printed(ratio, float(nm["wall_s"]) / float(r6["wall_s"]), "Newmark against IDA")
    printed(nm_force, float(nm["contact_force_rel_rms"]), "Newmark's contact-force error")


def test_static_table_is_the_results():
    """"Static solve" and "At a glance": static.json, per scene the median CPU, its quartiles and
    the Newton iterations."""
    got = result("static")
    assert got["cpu"].startswith("AMD EPYC (AVX2, no AVX-512)")
    table = rows(section("Static solve"))
    for r in got["rows"]:
        cells = table[r["scene"]]
        printed(cells[1], r["cpu_median_ms"], f"{r['scene']}: median")
        q25, q75 = cells[2].split("–")
        printed(q25, r["q25_ms"], f"{r['scene']}: q25")
        printed(q75, r["q75_ms"], f"{r['scene']}: q75")
        assert int(cells[3]) == r["newton_iterations"], r["scene"]
    assert len(table) == len(got["rows"]) + 1  # and the header
    (ms,) = grab(r"^([\d.]+) ms of CPU$", row(section("At a glance"), "quasi-static solve")[1])
    printed(ms, got["rows"][0]["cpu_median_ms"], "harris36 static solve")


def test_same_answers_are_the_equivalence_tests_reference():
    """"Same answers": the statistics of commit cbeb403 the slow equivalence test compares a long
    run with (tests/validation/test_statistical_equivalence.py), its revolutions and its bound."""
    source = (ROOT / "tests" / "validation" / "test_statistical_equivalence.py").read_text()
    constants = {}
    for node in ast.parse(source).body:
        if isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Name):
            try:
                constants[node.targets[0].id] = ast.literal_eval(node.value)
            except ValueError:
                pass
    s = section("Same answers")
    warmup, revs, k, commit = grab(r"runs (\d+) \+ (\d+) cage revolutions and requires agreement "
                                   r"within (\d+) combined standard errors with commit (\w+):", s)
    assert (constants["WARMUP_REVS"], constants["REVS"]) == (int(warmup), int(revs))
    assert f"k={float(k)}" in source and f"(commit {commit})" in source
    quoted = grab(r"skew RMS ([\d.]+) ± ([\d.]+) mrad, 3-revolution skew amplitude ([\d.]+) ± "
                  r"([\d.]+) mrad, .* slice loads ([\d.]+) ± ([\d.]+) N and ([\d.]+) ± ([\d.]+) N "
                  r"and the mean cage speed ([\d.]+) ± ([\d.]+) rad/s", s)
    names = ("DOC_SKEW_RMS_MRAD", "DOC_AMPLITUDE_MRAD", "DOC_INNER_SLICE_MAX_N",
             "DOC_OUTER_SLICE_MAX_N", "DOC_CAGE_SPEED_RAD_S")
    for i, name in enumerate(names):
        for text, value in zip(quoted[2 * i:2 * i + 2], constants[name]):
            printed(text, value, name)


def test_the_work_precision_ratios_are_its_times():
    """"Work-precision" and "At a glance": the peers' ratios are the times the paragraph states
    (within the rounding of the three), and the summary row quotes the same ratios. The times
    were measured without a kept result file (not tested against one)."""
    ida, lsoda, lsoda_x, bdf, bdf_x = grab(
        r"\*\*IDA at rtol 1e-6 took ([\d.]+) s\*\* .* \*\*LSODA took ([\d.]+) s \(([\d.]+)×\) and "
        r"BDF ([\d.]+) s \(([\d.]+)×\)\*\*", section("Work-precision"))
    for peer, ratio in ((lsoda, lsoda_x), (bdf, bdf_x)):
        exact = float(peer) / float(ida)
        slack = exact * (half_unit(peer) / float(peer) + half_unit(ida) / float(ida))
        printed(ratio, exact, "peer against IDA", slack=slack)
    quoted = grab(r"LSODA ([\d.]+)×, BDF ([\d.]+)× IDA's time", row(section("At a glance"),
                                                                 "IDA at rtol 1e-6")[1])
    assert quoted == (lsoda_x, bdf_x)


def test_at_a_glance_on_the_xeon():
    """"At a glance": the Xeon's step (the default run's process CPU over its steps,
    versions-926583b-xeon.json) and its residual and Jacobian per call (kernels-xeon.json),
    with the load that file recorded."""
    glance = section("At a glance")
    v = result("versions-926583b-xeon")["rows"]["new"]
    per_step, steps = grab(r"≈ (\d+) µs of CPU on the Intel Xeon \(AVX-512: the process's CPU "
                           r"over its ([\d ]+) steps\)", row(glance, "one IDA step")[1])
    assert {r["steps"] for r in v} == {number(steps)}
    printed(per_step, median(r["process_cpu_s"] for r in v) / v[0]["steps"] * 1e6,
            "CPU per step")
    k = result("kernels-xeon")
    assert avx512(k["cpu"]) and "Xeon" in k["cpu"]
    res, jac, load = grab(r"^([\d.]+) µs / ([\d.]+) µs \(Intel Xeon, AVX-512, load ([\d.]+); "
                          r"results/kernels-xeon.json\)", row(glance, "residual / analytic")[1])
    printed(res, k["median_us"]["residual_flat"]["bearingdae"], "residual per call")
    printed(jac, k["median_us"]["jacobian"]["bearingdae"], "Jacobian per call")
    printed(load, k["load_1min_at_end"], "load")


#: the rows marked ³ of "IDA's settings at equal error" -> their `switches --ida` or `--atol`
#: switches (each in the one result file that holds it)
ATOL_ROWS = {
    "maximum order 4 / 3 (`IDASetMaxOrd`, default 5) ³": ("ida max_order=4", "ida max_order=3"),
    "Newton convergence coefficient 0.2 / 0.5 (`IDASetNonlinConvCoef`, default 0.33) ³":
        ("ida nonlin_conv_coef=0.2", "ida nonlin_conv_coef=0.5"),
    "Newton iterations 3 / 5 (`IDASetMaxNonlinIters`, default 4) ³":
        ("ida max_nonlin_iters=3", "ida max_nonlin_iters=5"),
    "skew angle and rate 10× looser atol ³": ("atol skew_angle=10,skew_rate=10",),
    "rollers' azimuth and orbit speed 10× looser / tighter atol ³":
        ("atol azimuth=10,orbit_speed=10", "atol azimuth=0.1,orbit_speed=0.1"),
    "cage angle and speed 10× looser atol ³": ("atol cage_angle=10,cage_speed=10",),
    "roller spin speed 10× looser atol ³": ("atol spin_speed=10",),
    "Jacobian refresh at 10 % / 25 % change of c_j (`IDASetDeltaCjLSetup`, default 15 %) ³":
        ("ida delta_cj_lsetup=0.1", "ida delta_cj_lsetup=0.25"),
    "step grows from 1.5× / 1.2× on (`IDASetEtaFixedStepBounds`, default 2×) ³":
        ("ida eta_max_fx=1.5", "ida eta_max_fx=1.2"),
    "step growth up to 4× (`IDASetEtaMax`, default 2×) / cut 0.5× on a Newton failure "
    "(`IDASetEtaConvFail`, default 0.25×) ³": ("ida eta_max=4", "ida eta_conv_fail=0.5"),
}


def test_the_error_weight_rows_are_the_benchmark_result():
    """"IDA's settings at equal error", rows ³: switches-atol.json, switches-ida-settings.json
    and switches-step-ratios.json (`switches --atol ... / --ida ... --errors`): each CPU ratio
    and range, the steps, residual calls and Jacobians over the default's, the errors over the
    work-precision window, and the default's errors."""
    files = {name: result(name) for name in ("switches-atol", "switches-ida-settings",
                                             "switches-step-ratios")}
    for got in files.values():
        assert avx512(got["cpu"]) and got["window"] == {
            "numerics.warmup_cage_revolutions": 1.0, "numerics.cage_revolutions": 1.0}
    got = files["switches-atol"]
    data, default, errors = got["rows"], got["rows"]["default"], got["window_errors"]
    # each file's default is the same run's (the same trajectory, steps and errors)
    for other in files.values():
        assert other["rows"]["default"][-1]["steps"] == default[-1]["steps"]
        assert other["window_errors"]["default"] == errors["default"]
    s = section("IDA's settings at equal error")
    table = rows(s)
    assert set(label for label in table if "³" in label) == set(ATOL_ROWS)
    for label, keys in ATOL_ROWS.items():
        cells = table[label]
        ratios = re.findall(r"([\d.]+) \(([\d.]+)–([\d.]+)\)", cells[1])
        counts = [c.split(" / ") for c in cells[2].split("; ")]
        errs = [e.replace("*", "").split(", ") for e in cells[3].split("; ")]
        assert len(ratios) == len(counts) == len(errs) == len(keys), label
        for key, (ratio, lo, hi), (st, rc, jac), (cage, skew) in zip(keys, ratios, counts, errs):
            (got,) = [f for f in files.values() if key in f["rows"]]
            data, default, errors = got["rows"], got["rows"]["default"], got["window_errors"]
            each = per_repeat(data[key], default)
            printed(ratio, median(each), key)
            printed(lo, min(each), f"{key}: least")
            printed(hi, max(each), f"{key}: most")
            last, last0 = data[key][-1], default[-1]
            printed(st, last["steps"] / last0["steps"], f"{key}: steps")
            printed(rc, last["residual_calls"] / last0["residual_calls"], f"{key}: calls")
            printed(jac, last["jacobians"] / last0["jacobians"], f"{key}: Jacobians")
            printed(cage, errors[key]["cage_speed"], f"{key}: cage-speed error")
            printed(skew, errors[key]["skew_angle"], f"{key}: skew error")
    got = files["switches-atol"]
    data, default, errors = got["rows"], got["rows"]["default"], got["window_errors"]
    # the footnote: each file's date and load
    quoted = grab(r"results/switches-ida-settings.json and switches-atol.json \(([\d-]+), load "
                  r"([\d.]+)\), switches-step-ratios.json \([^,]*, ([\d-]+), load ([\d.]+) ", s)
    for (date, load), name in zip((quoted[:2], quoted[2:]), ("switches-atol",
                                                             "switches-step-ratios")):
        assert files[name]["date"] == date, name
        printed(load, files[name]["load_1min_at_end"], f"{name}: load")
    assert files["switches-ida-settings"]["date"] == quoted[0]
    printed(quoted[1], files["switches-ida-settings"]["load_1min_at_end"], "ida settings: load")
    cage0, skew0 = grab(r"the default's errors there ([\d.e-]+), ([\d.e-]+)\)", s)
    printed(cage0, errors["default"]["cage_speed"], "default: cage-speed error")
    printed(skew0, errors["default"]["skew_angle"], "default: skew error")
    key = "atol skew_angle=10,skew_rate=10"
    saved, times = grab(r"the looser skew atol: (\d+) % for ([\d.]+)× the cage-speed error", s)
    printed(saved, 100 * (1 - median(per_repeat(data[key], default))), "skew atol: saved")
    printed(times, errors[key]["cage_speed"] / errors["default"]["cage_speed"], "skew atol: error")


def test_the_vector_width_paragraph_is_the_results():
    """"Vector width": vector-width.json (`versions --old . --old-env
    BEARINGDAE_VECTOR_BITS=256 --cli`), each scene's median per-repeat CPU ratio, the load
    range, the same files to the bit, the same steps; the AVX-512 Xeon it names."""
    got = result("vector-width")["cases"]
    s = section("Vector width")
    loads = [c["load_1min_at_end"] for c in got.values()]
    lo, hi = grab(r"results/vector-width\.json, load ([\d.]+)–([\d.]+)\)", s)
    printed(lo, min(loads), "load, least")
    printed(hi, max(loads), "load, most")
    quoted = dict(zip(("default", "rr-mixed", "many-slices", "outer-spall"), grab(
        r"the default run \*\*([\d.]+)×\*\*, rolling resistance with mixed lubrication "
        r"\*\*([\d.]+)×\*\*, 100 slices \(extreme/many_slices\) \*\*([\d.]+)×\*\*, the "
        r"outer spall with its dynamic ring \*\*([\d.]+)×\*\*", s)))
    assert set(quoted) == set(got)
    for name, text in quoted.items():
        case = got[name]
        assert avx512(case["cpu"]) and "Xeon" in case["cpu"], name
        assert case["cli"] and case["old_env"] == {"BEARINGDAE_VECTOR_BITS": "256"}, name
        assert case["data_variables_identical"] and case["same_trajectory"], name
        new, old = case["rows"]["new"], case["rows"]["old"]
        assert len(new) == len(old) == 3, name
        printed(text, median(per_repeat(new, old, "process_cpu_s")), name)
    assert got["many-slices"]["case"] == "extreme/many_slices"
    assert got["outer-spall"]["case"] == "defects/outer_spall"
    assert got["rr-mixed"]["overrides"] == {"physics.rolling_resistance": "biboulet_houpert",
                                            "physics.lubrication": "mixed"}
