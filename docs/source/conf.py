# Sphinx configuration of the nsmodal documentation (built by scripts/docs.sh).
#
# Pages are MyST markdown (python3-myst-parser) or reStructuredText. The Python
# reference is taken by autodoc from the built module when it imports
# (scripts/docs.sh puts its directory on PYTHONPATH); otherwise that page says
# how to build it, so the site also builds without the C++ build.
import os
import re
import sys

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.abspath(os.path.join(here, "..", ".."))
sys.path.insert(0, os.path.join(here, "_ext"))

project = "nsmodal"
author = "the nsmodal authors"
copyright = "nsmodal authors"


def _project_version():
    # One version for the library, the module and the docs: CMake's project().
    with open(os.path.join(root, "CMakeLists.txt"), encoding="utf-8") as f:
        match = re.search(r"project\(\s*nsmodal\s+VERSION\s+([0-9][0-9.]*)", f.read())
    return match.group(1) if match else "unknown"


version = release = _project_version()

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "nsmodal_docs",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
master_doc = "index"
exclude_patterns = ["_build"]
myst_heading_anchors = 3
myst_enable_extensions = ["deflist"]

html_theme = "sphinx_rtd_theme"
html_title = f"nsmodal {release}"
html_show_sourcelink = False
# The gallery's PNGs live in docs/figures and docs/bench (written by
# `nsmodal figures` and `nsmodal bench`); the pages refer to them there.

autodoc_member_order = "bysource"
autodoc_typehints = "none"   # pybind11 puts the signature in the docstring
