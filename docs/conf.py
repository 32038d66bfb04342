"""Sphinx configuration of the gnssatt API reference site.

Why Sphinx: gnssatt's docstrings are numpydoc (the house style), which Sphinx renders natively through the
``numpydoc`` extension, and ``sphinx.ext.autosummary`` generates one page per public function and class at
build time from ``__all__``, so the reference cannot drift from the code. The models are the numpy and scipy
references, built the same way. ``myst-parser`` makes the existing Markdown pages in ``docs/*.md`` pages of
the site unchanged.

Build (from the repository root, after ``pip install '.[docs]'``)::

    sphinx-build -W --keep-going -b html docs docs/_build/html
"""

from __future__ import annotations

import gnssatt

project = "gnssatt"
author = "gnssatt contributors"
copyright = "gnssatt contributors, MIT OR Apache-2.0"
version = release = gnssatt.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",  # [source] links beside every documented object
    "numpydoc",
    "myst_parser",
    "matplotlib.sphinxext.plot_directive",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
templates_path = ["_templates"]
# results/ holds the reproduction results, one page per experiment, beside the study files they link to
# (JSON, CSV, PNG: downloads and images of the site, not pages).
exclude_patterns = ["_build", "README*", "Thumbs.db", ".DS_Store"]

# One page per public name, generated at build time into api/generated (ignored by git). A module's page lists
# exactly its __all__, including names it re-exports lazily (PEP 562), as `from gnssatt import *` sees them.
autosummary_generate = True
autosummary_ignore_module_all = False
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_typehints = "none"  # the numpydoc Parameters/Returns sections carry types, shapes and units

# numpydoc renders the sections; autosummary, not numpydoc, lists a class's members (one mechanism, no
# duplicate stub pages).
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# Markdown pages link to each other by file name (`conventions.md`) and to the repository's files; headings
# get anchors so that `page.md#section` links resolve.
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]


# The worked examples' figures (docs/examples/*.py) are drawn IN the build by matplotlib's plot directive,
# `.. plot:: examples/<script>.py` in an eval-rst block on each page (MyST's own directive syntax lacks the
# state machine the plot directive needs; the path is relative to docs/). A script that raises is a warning,
# so `-W` fails the build. Chosen over sphinx-gallery because matplotlib is already a dependency (nothing to
# add to the docs extra), the pages stay hand-written Markdown that explain the physics around the code, and
# the scripts stay plain programs that a user and tests/test_docs_examples.py run as they are. Each script
# runs once per build as `__main__` (its printed output is discarded: the page shows it, and the tests check
# the page's copy against what the script prints).
plot_formats = [("png", 100)]
plot_html_show_formats = False
plot_html_show_source_link = False  # each page shows the script with literalinclude
plot_include_source = False

# furo: a theme of the scientific Python ecosystem; light and dark modes follow the reader's setting. Its content
# column is a fixed 46em; _static/wide.css lets it grow on wide windows so that code lines are not cut.
html_theme = "furo"
html_static_path = ["_static"]
html_css_files = ["wide.css"]
html_title = f"gnssatt {release}"
