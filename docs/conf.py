"""Sphinx configuration: Markdown pages (MyST) beside an API reference read from
the numpydoc docstrings (autodoc with napoleon). Built with warnings as errors
by .ci/run: ``sphinx-build -W --keep-going -b html docs docs/_build/html``."""

project = "observability"
author = "the observability developers"
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon", "sphinx.ext.mathjax"]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build"]
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3
napoleon_google_docstring = False
napoleon_numpy_docstring = True
autodoc_member_order = "bysource"
autodoc_typehints = "description"
html_theme = "pydata_sphinx_theme"
html_title = "observability"
napoleon_use_ivar = True
