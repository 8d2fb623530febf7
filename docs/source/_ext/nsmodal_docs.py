"""The `nsmodal-python-api` directive: autodoc of the built module, or a note.

The Python reference comes from the module's own docstrings (pybind11), so it
needs the built module. When `import nsmodal` works, the directive expands to
`automodule`; when it does not, to a note that says how to build the page in
full. scripts/docs.sh decides which is acceptable (it fails when it was given a
module directory that does not import).
"""
import importlib

from docutils import nodes
from docutils.parsers.rst import Directive
from docutils.statemachine import StringList


def _module_or_reason():
    try:
        return importlib.import_module("nsmodal"), None
    except ImportError as error:  # the C++ build is not there: say so on the page
        return None, str(error)


class PythonApi(Directive):
    has_content = False

    def run(self):
        module, reason = _module_or_reason()
        if module is None:
            note = nodes.note()
            note += nodes.paragraph(
                text="This copy of the documentation was built without the Python module "
                f"({reason}). Build the project, then `bash scripts/docs.sh build/python` to "
                "include the reference of every function, taken from the module's docstrings.")
            return [note]
        lines = [
            ".. automodule:: nsmodal",
            "   :members:",
            "   :undoc-members:",
        ]
        container = nodes.container()
        self.state.nested_parse(StringList(lines, source="nsmodal-python-api"), self.content_offset,
                                container)
        return container.children


def _docstring_as_written(app, what, name, obj, options, lines):
    """The module's docstrings are plain text (aligned columns, `x_i`, `*args`),
    not reStructuredText: show each as written, in a literal block, so that
    Sphinx neither misreads nor warns about it."""
    if not (name == "nsmodal" or name.startswith("nsmodal.")) or not lines:
        return
    text = [line.rstrip() for line in lines]
    while text and not text[-1]:
        text.pop()
    lines[:] = ["::", ""] + [("   " + line) if line else "" for line in text] + [""]


def setup(app):
    app.add_directive("nsmodal-python-api", PythonApi)
    app.connect("autodoc-process-docstring", _docstring_as_written)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
