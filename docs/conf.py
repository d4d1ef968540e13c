"""Sphinx configuration of the lorentz-gas documentation site (`scripts/docs.sh` builds it).

Sphinx, not mdBook: the Python API reference is generated from the package's docstrings
(autodoc + napoleon, numpy style), which mdBook cannot do; MyST reads the Markdown pages. The
source root is the repository itself (`sphinx-build -c docs . OUT`), restricted to `docs/` and
`proofs-notes/`, so that every relative link between the pages and the verification dossier is
the same path on GitHub and in the site.
"""

project = "lorentz-gas"
author = "the lorentz-gas developers"
copyright = "2026, the lorentz-gas developers"

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon"]
root_doc = "docs/index"
include_patterns = ["docs/**", "proofs-notes/**", "ARCHITECTURE.md"]
exclude_patterns = ["target", "fuzz", "python", "results", "src", "tests", "benches", ".git", "docs/conf.py"]
source_suffix = {".md": "markdown"}

myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3
# The notes' headings begin where a note's argument begins, not always at level 1.
suppress_warnings = ["myst.header"]

napoleon_numpy_docstring = True
napoleon_google_docstring = False
autodoc_member_order = "bysource"
autodoc_typehints = "description"

html_theme = "alabaster"
html_title = "lorentz-gas"
html_theme_options = {"page_width": "1100px", "body_max_width": "none", "sidebar_includehidden": False}
