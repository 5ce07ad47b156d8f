"""Sphinx configuration of the bearingdae documentation.

Build (warnings are errors, the example gallery is executed):

    pip install ".[docs]" && python -m sphinx -W --keep-going -b html docs docs/_build/html

Generated at build time, never edited by hand (and kept out of git): the scene-key page from
the scene schema and the changelog page (docs/_ext/generated_pages.py), the API pages from the
docstrings (autosummary, docs/api/), the CLI reference from the argument parser
(sphinx-argparse) and the gallery from docs/examples/ (sphinx-gallery, docs/auto_examples/).
"""

import os
import sys
from pathlib import Path

import bearingdae

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "_ext"))

import generated_pages  # noqa: E402  (docs/_ext, put on the path just above)

generated_pages.write_pages(DOCS)

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

project = "bearingdae"
author = "bearingdae developers"
copyright = "2026, bearingdae developers"
version = release = bearingdae.__version__  # the one version (bearingdae/__init__.py)

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",
    "sphinxarg.ext",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "examples/README.txt", "**/*.ipynb",
                    "data"]  # data/: CSVs and Markdown parts the pages include (tools/)
templates_path = []

# Markdown pages stay Markdown (MyST)
myst_enable_extensions = ["colon_fence", "deflist"]
myst_heading_anchors = 3

# API reference from the docstrings (numpydoc style)
autosummary_generate = True
autodoc_default_options = {"members": False}
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# Example gallery: every script in docs/examples/ runs at build time (each <= 60 s on 2 cores)
sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"plot_",
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
    "capture_repr": (),
    "matplotlib_animations": False,
    "image_scrapers": ("matplotlib",),
    "reset_modules": ("matplotlib",),
    # the examples run one after another: in sphinx-gallery's parallel mode (joblib's loky
    # processes) the dask example cannot start its process cluster
}

html_theme = "pydata_sphinx_theme"
html_title = f"bearingdae {release}"
html_theme_options = {
    "navbar_align": "left",
    "show_toc_level": 2,
    "header_links_before_dropdown": 5,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
    "secondary_sidebar_items": ["page-toc"],
}
html_static_path = ["_static"]
html_css_files = ["custom.css"]
# pages without sub-pages: no left sidebar, the width goes to the text and wide tables
html_sidebars = {page: [] for page in (
    "index", "user-guide", "_generated/scene-keys", "_generated/changelog", "cli", "theory",
    "validation", "skidmaps", "stability", "performance", "adding-an-effect",
    "robustness")}
html_show_sourcelink = False
