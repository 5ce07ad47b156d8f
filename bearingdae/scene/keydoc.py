"""The scene-key reference, generated from the schema (pipeline stage 1: what documents a scene).

The pydantic section models of :mod:`bearingdae.scene.schema` are the only source of every key's
type, default, allowed values and meaning. :func:`key_reference` turns them into the Markdown
page that the documentation builds (``docs/conf.py``) and ``bearingdae keys --markdown`` prints,
so a key added to the schema appears in both without editing any document.
"""

from __future__ import annotations

import types
import typing

from pydantic import BaseModel
from pydantic.fields import FieldInfo

from . import schema
from .schema import field_range

#: Unit of a key, read from the end of its name (the longest matching suffix wins).
UNIT_SUFFIXES = {
    "_mm": "mm", "_um": "µm", "_nm": "nm", "_m": "m", "_N": "N", "_Nm": "N·m", "_N_m": "N/m",
    "_GPa": "GPa", "_Pa_s": "Pa·s", "_kg_m3": "kg/m³", "_rpm": "r/min", "_s": "s",
    "_m_s": "m/s", "_s_m": "s/m",
}

PAGE_INTRO = """\
Every key a scene file (TOML) accepts, section by section: its unit (also in the key's name),
type, default, the values allowed and what it means. This page is generated from the scene
schema (`bearingdae/scene/schema.py` and its `sections/`) each time the documentation is built; `bearingdae keys`
prints the same keys on the command line (`--markdown`: this page). Ranges: `[a, b]` closed,
`(a, b)` open. An empty default means "from the bearing preset, or derived" (the meaning says
which). Give a key in its section of the file (`[operating]` / `radial_load_N = 400`), or as
`--set operating.radial_load_N=400` on the command line and
`load_scene(case, overrides={"operating.radial_load_N": 400})` in Python.
"""


def key_unit(name: str) -> str:
    """Unit of a key from its name's suffix (``radial_load_N`` -> ``N``); ``""`` if none."""
    best = ""
    for suffix in UNIT_SUFFIXES:
        if name.endswith(suffix) and len(suffix) > len(best):
            best = suffix
    return UNIT_SUFFIXES.get(best, "")


def _type_name(annotation) -> str:
    """A reader's name of a field type: ``number``, ``integer``, ``'a' | 'b'``, ``list of text``."""
    origin = typing.get_origin(annotation)
    if origin in (typing.Union, types.UnionType):
        parts = [_type_name(a) for a in typing.get_args(annotation) if a is not type(None)]
        return " or ".join(parts)
    if origin is typing.Literal:
        return "text"
    if origin is list:
        (item,) = typing.get_args(annotation) or (str,)
        return f"list of {_type_name(item)}"
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        inner = ", ".join(f"{n} = [...]" for n in annotation.model_fields)
        return f"table {{{inner}}}"
    return {bool: "true/false", int: "integer", float: "number", str: "text"}.get(
        annotation, getattr(annotation, "__name__", str(annotation)))


def _choices(annotation) -> str:
    """The allowed values of a ``Literal`` field (also inside ``| None``), TOML-quoted."""
    if typing.get_origin(annotation) in (typing.Union, types.UnionType):
        return " ".join(_choices(a) for a in typing.get_args(annotation)).strip()
    if typing.get_origin(annotation) is typing.Literal:
        return ", ".join(f'`"{v}"`' for v in typing.get_args(annotation))
    return ""


def _default(field: FieldInfo) -> str:
    if field.default is None or field.is_required():
        return ""
    value = field.default
    if isinstance(value, bool):
        return f"`{str(value).lower()}`"
    if isinstance(value, str):
        return f'`"{value}"`'
    if isinstance(value, float):
        return f"`{value:g}`"
    return f"`{value!r}`"


def _cell(text: str) -> str:
    """Text safe inside a Markdown table cell."""
    return text.replace("|", "\\|").replace("\n", " ")


def key_rows(section: str, model: type[BaseModel]) -> list[tuple[str, ...]]:
    """(key, unit, type, default, allowed, meaning) of every key of one section."""
    rows = []
    for name, field in model.model_fields.items():
        key = f"{section}.{name}"
        allowed = (field_range(field) or _choices(field.annotation)
                   or schema.DEPENDENT_RANGES.get(key)
                   or (f"[0, {_speed_max()}] r/min, or a ramp"
                       if key == "operating.speed_rpm" else ""))
        if key == "bearing.preset":
            from .parameters import preset_names

            allowed = ", ".join(f'`"{p}"`' for p in preset_names())
        rows.append((key, key_unit(name), _type_name(field.annotation), _default(field),
                     allowed, field.description or ""))
    return rows


def _speed_max() -> str:
    return f"{schema.SPEED_MAX_RPM:g}"


def key_reference(sections: dict[str, type[BaseModel]] | None = None,
                  title: str = "Scene keys") -> str:
    """The Markdown page of every scene key, one table per TOML section.

    Parameters
    ----------
    sections : dict of str to pydantic model class, optional
        TOML section name -> its model (default: the scene schema's sections).
    title : str
        Heading of the page.

    Returns
    -------
    str
        MyST/CommonMark Markdown: an introduction, then per section a heading, the section
        model's docstring (if any) and a table of key, unit, type, default, allowed, meaning.
    """
    sections = schema._SECTIONS if sections is None else sections  # read now: tests patch it
    out = [f"# {title}", "", PAGE_INTRO, "`title` (text): the case title, written into every "
           "output file and figure; `{operating}` in it becomes the operating point that runs "
           "(default: the file name and the operating point).", ""]
    for section, model in sections.items():
        out += [f"## [{section}]", ""]
        doc = (model.__doc__ or "").strip()
        if doc:
            out += [" ".join(doc.split()), ""]
        out += ["| key | unit | type | default | allowed | meaning |",
                "|---|---|---|---|---|---|"]
        for key, unit, typ, default, allowed, meaning in key_rows(section, model):
            out.append(f"| `{key}` | {unit} | {_cell(typ)} | {default} | {_cell(allowed)} "
                       f"| {_cell(meaning)} |")
        out.append("")
    if sections is schema._SECTIONS:  # the arrays of tables, after the tables
        for section, model in schema.ARRAY_SECTIONS.items():
            out += [f"## [[{section}]]", "", " ".join((model.__doc__ or "").split()), "",
                    f"An array of tables: one `[[{section}]]` header per entry (none by "
                    "default); `--set` cannot add one.", "",
                    "| key | unit | type | default | allowed | meaning |",
                    "|---|---|---|---|---|---|"]
            for key, unit, typ, default, allowed, meaning in key_rows(section, model):
                key = f"{section}[].{key.partition('.')[2]}"
                out.append(f"| `{key}` | {unit} | {_cell(typ)} | {default} | {_cell(allowed)} "
                           f"| {_cell(meaning)} |")
            out.append("")
        out += output_reference()
    return "\n".join(out)


def output_reference() -> list[str]:
    """The Markdown lines of the table of ``output.variables``' names and the condition under
    which each exists, read off the conditions the variables declare
    (scene/switches.present_when): the same rule that refuses a variable asked for where its
    condition does not hold."""
    from .switches import present_when

    out = ["## Output variables and when they exist", "",
           "The names `output.variables` accepts. A variable asked for where its condition "
           "does not hold is refused in one line naming it and the setting that would make "
           "it exist.", "", "| variable | exists when |", "|---|---|"]
    for name, condition in schema.OUTPUT_VARIABLES.items():
        needs = "always" if condition is None else present_when(condition).needs
        out.append(f"| `{name}` | {_cell(needs)} |")
    return out + [""]
