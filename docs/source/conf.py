# Sphinx configuration of the nsmodal documentation (built by scripts/docs.sh).
#
# Pages are MyST markdown (python3-myst-parser) or reStructuredText. The Python
# reference is taken by autodoc from the built module when it imports
# (scripts/docs.sh puts its directory on PYTHONPATH); otherwise that page says
# how to build it, so the site also builds without the C++ build. The
# tutorials are Jupyter notebooks (nbsphinx), stored without outputs and
# executed at every build when the module imports (NSMODAL_DOCS_EXECUTE,
# set by scripts/docs.sh). The C++ reference is Breathe over Doxygen's XML of
# the public headers (docs/doxygen/Doxyfile, run by scripts/docs.sh).
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
    "sphinx.ext.mathjax",
    "nbsphinx",
    "breathe",
    "nsmodal_docs",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
master_doc = "index"
exclude_patterns = ["_build", "**.ipynb_checkpoints"]
myst_heading_anchors = 3
# $...$ and $$...$$ (label) in MyST pages: the theory page's equations (MathJax).
myst_enable_extensions = ["deflist", "dollarmath", "amsmath"]

# The tutorials: executed at each build ("always") when scripts/docs.sh found
# the module ("never" otherwise: the pages then show the code without output).
# A cell that raises fails the build, and so does one running longer than
# nbsphinx_timeout seconds (each notebook takes a few seconds).
nbsphinx_execute = os.environ.get("NSMODAL_DOCS_EXECUTE", "never")
nbsphinx_allow_errors = False
nbsphinx_timeout = int(os.environ.get("NSMODAL_DOCS_CELL_TIMEOUT", "60"))
nbsphinx_kernel_name = "python3"
nbsphinx_execute_arguments = [
    "--InlineBackend.figure_formats={'png'}",
    "--InlineBackend.rc=figure.dpi=96",
]
# Each tutorial's page says where its notebook is and how to run it.
nbsphinx_prolog = r"""
{% set path = env.doc2path(env.docname, base=None) %}
.. note::

   This page is the notebook ``docs/source/{{ path }}``
   {%- if env.config.nbsphinx_execute == "always" %}, executed when this site was built
   {%- else %}, shown without its outputs (this copy of the site was built without the
   Python module){% endif %}. To run it, open it in Jupyter from the clone with the module
   on ``PYTHONPATH`` and Debian's ``/usr/bin/python3`` as the kernel
   (:doc:`/installation`, "Building this documentation").

"""

# The C++ reference: Doxygen's XML (scripts/docs.sh writes it to
# $NSMODAL_DOXYGEN_OUT/xml, default build/docs/doxygen/xml).
breathe_projects = {
    "nsmodal": os.environ.get("NSMODAL_DOXYGEN_XML", os.path.join(root, "build", "docs", "doxygen", "xml")),
}
breathe_default_project = "nsmodal"
breathe_domain_by_extension = {"h": "cpp"}
breathe_show_include = True

# Literal blocks without a language are plain text (the headers' comments in
# the C++ reference, the docstrings, the formulas of indented blocks): not
# highlighted as code.
highlight_language = "none"

html_theme = "sphinx_rtd_theme"
html_title = f"nsmodal {release}"
html_show_sourcelink = False
# The gallery's PNGs live in docs/figures and docs/bench (written by
# `nsmodal figures` and `nsmodal bench`); the pages refer to them there.

autodoc_member_order = "bysource"
autodoc_typehints = "none"   # pybind11 puts the signature in the docstring
