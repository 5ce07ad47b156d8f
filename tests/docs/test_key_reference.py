"""The scene-key reference is generated from the schema: a key added to the schema appears in the
documentation (and in `bearingdae keys --markdown`) without editing any document."""

from __future__ import annotations

import importlib.util
import re

from pydantic import Field

from bearingdae.cli import main
from bearingdae.scene import schema, valid_keys
from bearingdae.scene.keydoc import key_reference, key_unit
from doc_blocks import DOCUMENTS, ROOT


def _generated_pages_module():
    spec = importlib.util.spec_from_file_location(
        "generated_pages", ROOT / "docs" / "_ext" / "generated_pages.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class _TractionWithNewKey(schema.TractionInput):
    """Traction section with one more key, as a future version might add."""

    film_shear_limit_GPa: float = Field(default=0.03, gt=0.0, le=5.0,
                                        description="limiting shear stress of the film")


def test_every_schema_key_is_in_the_reference():
    text = key_reference()
    for key in valid_keys():
        if "." in key:
            assert f"| `{key}` |" in text, key
    # the six keys the hand-written table once missed
    for key in ("traction.slide_roll_A", "traction.slide_roll_D",
                "traction.rolling_speed_floor_m_s", "cage.spin_friction_force_scale_N"):
        assert f"| `{key}` |" in text


def test_a_key_added_to_the_schema_appears_in_the_built_page(tmp_path, monkeypatch, capsys):
    """The page the documentation build writes (docs/_ext/generated_pages.py, called by
    docs/conf.py) and `bearingdae keys --markdown` list a key added to the schema, with its unit,
    default, range and meaning."""
    monkeypatch.setitem(schema._SECTIONS, "traction", _TractionWithNewKey)
    row = ("| `traction.film_shear_limit_GPa` | GPa | number | `0.03` | (0, 5] "
           "| limiting shear stress of the film |")
    (page, _changelog) = _generated_pages_module().write_pages(tmp_path)
    assert row in page.read_text(encoding="utf-8")
    assert main(["keys", "--markdown"]) == 0
    assert row in capsys.readouterr().out
    monkeypatch.undo()
    assert "film_shear_limit" not in key_reference()


def test_choices_units_and_defaults_come_from_the_fields():
    text = key_reference()
    assert ('| `traction.law` |  | text | `"paper"` | `"paper"`, `"slide-roll"` |' in text)
    assert "| `operating.speed_rpm` | r/min |" in text
    assert "| `numerics.until_steady` |  | true/false | `false` |" in text
    assert key_unit("pocket_stiffness_N_m") == "N/m" and key_unit("moment_Nm") == "N·m"
    assert key_unit("A_s_m") == "s/m" and key_unit("slices") == ""


def test_no_document_keeps_a_hand_written_key_table():
    """The generated page is the one list of keys: no committed document repeats it (a table of a
    few keys on another topic, e.g. the unit-slip checks, is fine)."""
    row = re.compile(r"^\|\s*`(bearing|materials|operating|numerics|physics|traction|cage|"
                     r"lubricant|output)\.\w+`\s*\|", re.M)
    for path in DOCUMENTS:
        rows = row.findall(path.read_text(encoding="utf-8"))
        assert len(rows) < 20, f"{path}: {len(rows)} rows of a key table"
