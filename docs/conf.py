"""Sphinx configuration of vlab's documentation (MyST Markdown, pydata-sphinx-theme, autodoc,
sphinx-gallery). Build with warnings as errors, as CI does:

    python -m sphinx -W --keep-going -b html docs docs/_build/html
"""

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))  # autodoc and the gallery read this checkout's vlab
sys.path.insert(0, str(DOCS / "examples"))  # the gallery scripts' shared helpers
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as the CLI: numpy's BLAS serial (vlab.serial_blas_process)

import vlab  # noqa: E402

project = "vlab"
author = "the vlab authors"
copyright = "the vlab authors"
release = version = vlab.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "examples", "Thumbs.db", ".DS_Store", "**/.ipynb_checkpoints"]
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
suppress_warnings = ["myst.header"]  # a helper's page may start its sections at ###

autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "undoc-members": False}

html_theme = "pydata_sphinx_theme"
html_title = f"vlab {release}"
html_static_path = ["_static"]
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 6,
}
html_sidebars = {"**": ["sidebar-nav-bs"]}

# The gallery: docs/examples/plot_*.py run at build time (every specimen file on a coarse mesh);
# the scripts' matplotlib figures become the pages' images and the thumbnails.
sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",
    "ignore_pattern": r"gallery_helpers\.py",
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("matplotlib",),
    "matplotlib_animations": False,
    "min_reported_time": 1,
}
