"""The effect declarations (system/effect.py, system/effects.py) against what the package
does: every kernel parameter belongs to one effect, every source says where its heat goes,
every parameter that holds the oil viscosity is declared as such (a thermal run updates it),
and no module but an effect's own names that effect's parameters or keys."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from bearingdae.physics.heat_network import NODES
from bearingdae.system import effects
from bearingdae.system.model import build_model
from bearingdae.system.residual import PARAM_NAMES
from conftest import make_scene

PACKAGE = Path(__file__).resolve().parents[2] / "bearingdae"
#: every switch on (each effect's declaration takes part)
ALL_ON = {"bearing.type": "NUP", "physics.cage_whirl": True, "physics.ring": "dynamic",
          "physics.rolling_resistance": True, "physics.lubrication": "mixed"}


def test_every_kernel_parameter_belongs_to_one_effect_in_one_block():
    owners = [e.name for n in PARAM_NAMES for e in effects.EFFECTS if n in e.params]
    assert len(owners) == len(PARAM_NAMES)  # each name once
    for e in effects.EFFECTS:
        if e.params:
            assert PARAM_NAMES[effects.param_slice(e)] == e.params, e.name


def test_every_source_is_declared_once_and_says_where_its_heat_goes():
    names = [s.name for e in effects.EFFECTS for s in e.sources]
    assert len(names) == len(set(names)) == 11
    for e in effects.EFFECTS:
        for s in e.sources:
            assert len(s.heat) == len(NODES) and min(s.heat) >= 0.0, s.name
            assert sum(s.heat) == pytest.approx(1.0, abs=1e-15), s.name


def test_the_sources_of_a_scene_are_those_of_its_switches():
    assert [s.name for s in effects.sources(make_scene())] == [
        "raceway_inner", "raceway_outer", "pocket_friction", "pocket_impact", "orbit_drag",
        "roller_churning", "cage_churning"]
    every = [s.name for s in effects.sources(make_scene(ALL_ON))]
    assert every[7:] == ["flange_friction", "cage_land", "rolling_resistance",
                         "asperity_friction"]


def test_every_parameter_holding_the_oil_viscosity_is_declared():
    """Built with an oil viscosity no other parameter has, the entries equal to it are
    exactly the declared viscosity parameters: a law that reads the viscosity and is left
    undeclared would keep the inlet viscosity in a thermal run."""
    mu = 0.0123456789
    model = build_model(make_scene({**ALL_ON, "lubricant.viscosity_Pa_s": mu}))
    held = {n for n, v in zip(PARAM_NAMES, model.params) if v == mu}
    assert held == set(effects.viscosity_params()) == {"mu_oil", "wh_visc", "rr_eta0",
                                                        "mx_visc"}
    effects.set_viscosity(model, 0.02)
    assert {n for n, v in zip(PARAM_NAMES, model.params) if v == 0.02} == held
    assert model.scene.lubricant.viscosity_Pa_s == 0.02


def test_an_effect_off_keeps_its_parameters_at_zero_through_the_thermal_update():
    model = build_model(make_scene({"physics.thermal": "steady"}))
    before = model.params.copy()
    effects.set_oil_temperature(model, 80.0)
    changed = {n for n, a, b in zip(PARAM_NAMES, before, model.params) if a != b}
    assert changed == {"mu_oil"}


def test_each_effect_names_its_keys_and_outputs():
    by = {e.name: e for e in effects.EFFECTS}
    assert by["rolling_resistance"].keys() == ("lubricant.temperature_viscosity_K_inv",
                                              "lubricant.thermal_conductivity_W_m_K",
                                              "lubricant.inlet_film_um")
    assert by["mixed_lubrication"].keys() == ("lubricant.boundary_friction",)
    assert "cage.land_friction" in by["cage_whirl"].keys()
    assert "ring.support_stiffness_N_m" in by["dynamic_ring"].keys()
    assert "bearing.flange_friction" in by["flanges"].keys()
    assert "thermal.oil_flow_l_min" in by["thermal"].keys()
    assert "viscosity_ratio_kappa" in by["thermal"].outputs()
    assert "cage_center" in by["cage_whirl"].outputs()
    assert by["core"].keys() == ()


def test_no_module_names_another_effects_parameters_or_keys():
    """grep: an optional effect's parameter names and its keys' names stand, quoted, only in
    its own modules (its system module, its scene checks) and where keys are defined
    (scene/sections/); a string naming them anywhere else is a link the layering check cannot
    see."""
    own = {"flanges": {"system/flange.py", "scene/flanges.py"},
           "cage_whirl": {"system/whirl.py", "scene/whirl.py"},
           "rolling_resistance": {"system/rolling_resistance.py"},
           "mixed_lubrication": {"system/mixed.py"},
           "thermal": {"system/thermal_network.py", "scene/thermal_switch.py"}}
    found = []
    files = {p.relative_to(PACKAGE).as_posix(): p.read_text(encoding="utf-8")
             for p in PACKAGE.rglob("*.py")}
    scanned = 0
    for e in effects.EFFECTS:
        if e.name not in own:
            continue
        names = set(e.params) | {k.partition(".")[2] for k in e.keys()}
        for rel, text in files.items():
            if rel in own[e.name] or rel.startswith("scene/sections/"):
                continue
            scanned += 1
            for n in names:
                if re.search(rf"[\"'](?:\w+\.)?{re.escape(n)}[\"']", text):
                    found.append((e.name, n, rel))
    assert scanned > 5 * 150
    assert found == []


def test_the_passes_compiled_apart_are_told_before_the_model_is_built():
    """What the declarations say of a scene (system/effects.scene_has_optional) is what the
    built model's marker says (system/optional.optional_marker): the optional passes compile
    exactly for the scenes that run them."""
    from bearingdae.system.optional import marker_of, optional_marker

    told = []
    for over in ({}, {"bearing.type": "NJ"}, {"physics.cage_whirl": True},
                 {"physics.rolling_resistance": True}, {"physics.lubrication": "mixed"},
                 {"physics.lubrication": "full-film", "physics.thermal": "steady"}, ALL_ON):
        scene = make_scene(over)
        told.append(effects.apart_pattern(scene))
        assert effects.scene_has_optional(scene) == (told[-1] is not None), over
        assert marker_of(told[-1]) == optional_marker(build_model(scene).params), over
    # one entry per effect compiled apart (flanges, whirl, rolling resistance, mixed), each
    # on only in the scene that switches it on: a scene compiles only its own passes
    T, F = True, False
    assert told == [None, (T, F, F, F), (F, T, F, F), (F, F, T, F), (F, F, F, T), None,
                    (T, T, T, T)]
