"""The `nsmodal-python-api` directive: autodoc of the built module, or a note.

The Python reference comes from the module's own docstrings (pybind11), so it
needs the built module. When `import nsmodal` works, the directive expands to
`automodule`; when it does not, to a note that says how to build the page in
full. scripts/docs.sh decides which is acceptable (it fails when it was given a
module directory that does not import).
"""
import glob
import importlib
import importlib.util
import json
import os
import subprocess

from docutils import nodes
from sphinx import addnodes
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


def _settings_or_reason():
    """The settings table as `nsmodal settings --json` prints it (NSMODAL_BIN,
    set by scripts/docs.sh to the built command), or why it is not there."""
    binary = os.environ.get("NSMODAL_BIN", "")
    if not binary or not os.access(binary, os.X_OK):
        return None, "no built nsmodal command (NSMODAL_BIN)"
    done = subprocess.run([binary, "settings", "--json"], capture_output=True, text=True, timeout=60, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"{binary} settings --json failed ({done.returncode}): {done.stderr.strip()}")
    return json.loads(done.stdout), None


def _cell(value):
    if value is None:
        return "-"
    return value if isinstance(value, str) else json.dumps(value)


class SettingsTable(Directive):
    """The reference of every setting, made from the one settings table (issue 23)."""
    has_content = False

    def run(self):
        settings, reason = _settings_or_reason()
        if settings is None:
            note = nodes.note()
            note += nodes.paragraph(text=f"This copy was built without the settings table ({reason}): "
                                    "`nsmodal settings` prints it; `bash scripts/docs.sh` includes it here.")
            return [note]
        out = []
        for command in ("simulate", "validate"):
            rows = [s for s in settings if s["scene_key"] is None or s["scene_key"].startswith(command + ".")
                    if command in s["commands"]]
            section = nodes.section(ids=[f"settings-{command}"])
            section += nodes.title(text=f"{command}")
            table = nodes.table()
            group = nodes.tgroup(cols=7)
            table += group
            for width in (12, 18, 14, 12, 12, 8, 40):
                group += nodes.colspec(colwidth=width)
            head = nodes.thead()
            group += head
            header = nodes.row()
            for title in ("name", "scene key", "flag", "Python", "default", "unit", "meaning"):
                header += nodes.entry("", nodes.paragraph(text=title))
            head += header
            body = nodes.tbody()
            group += body
            for s in rows:
                row = nodes.row()
                for value in (s["name"], s["scene_key"], s["flag"], s["python"], s["default"], s["unit"] or None,
                              f"{s['doc']} ({s['kind']})"):
                    row += nodes.entry("", nodes.paragraph(text=_cell(value)))
                body += row
            section += table
            out.append(section)
        return out


_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))


def _doxygen_group_of(header):
    """The Doxygen group that docs/doxygen/comment_filter.py gives a header
    (one definition: the filter's)."""
    spec = importlib.util.spec_from_file_location(
        "comment_filter", os.path.join(_ROOT, "docs", "doxygen", "comment_filter.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.group_of(header)


class CppHeaders(Directive):
    """`nsmodal-cpp-headers:: LIB`: a section per public header of LIB
    (LIB/include/nsmodal/*.h, found when the site is built, so a new header
    is on its page without anyone listing it), each with the header's
    description and its declarations (Breathe, over Doxygen's XML of the
    header's group)."""
    required_arguments = 1
    has_content = False

    def run(self):
        lib = self.arguments[0]
        headers = sorted(glob.glob(os.path.join(_ROOT, lib, "include", "nsmodal", "*.h")))
        if not headers:
            raise self.error(f"nsmodal-cpp-headers: no public header in {lib}/include/nsmodal/")
        env = self.state.document.settings.env
        out = []
        for header in headers:
            env.note_dependency(header)
            group, title = _doxygen_group_of(header)
            section = nodes.section(ids=[nodes.make_id(title)], names=[nodes.fully_normalize_name(title)])
            section += nodes.title(text=title)
            lines = [f".. doxygengroup:: {group}", "   :project: nsmodal", "   :desc-only:", "",
                     f".. doxygengroup:: {group}", "   :project: nsmodal", "   :content-only:", "   :members:",
                     "   :undoc-members:", ""]
            container = nodes.container()
            self.state.nested_parse(StringList(lines, source=f"nsmodal-cpp-headers {lib}"), self.content_offset,
                                    container)
            section.extend(container.children)
            self.state.document.note_implicit_target(section)
            out.append(section)
        return out


def _header_descriptions_without_group_line(app, doctree):
    """The C++ reference shows each header's description with
    `doxygengroup ... :desc-only:` (the header's Doxygen group, made by
    docs/doxygen/comment_filter.py); Breathe signs it "group nsmodal_model_h",
    a name that exists only for Doxygen. Keep the description and the link
    target, drop that signature line."""
    for desc in list(doctree.findall(addnodes.desc)):
        signatures = [c for c in desc.children if isinstance(c, addnodes.desc_signature)]
        if len(signatures) != 1:
            continue
        # The group's own target, "group__nsmodal__model__h"; its members' are
        # "group__nsmodal__model__h_1g..." (Doxygen writes "_" as "__").
        targets = [t for t in signatures[0].findall(nodes.target)
                   if any(i.startswith("group__") and "_1" not in i for i in t.get("ids", []))]
        if not targets or signatures[0].astext().split()[:1] != ["group"]:
            continue
        content = [c for c in desc.children if isinstance(c, addnodes.desc_content)]
        desc.replace_self(targets[:1] + [child for c in content for child in c.children])


def setup(app):
    app.add_directive("nsmodal-python-api", PythonApi)
    app.add_directive("nsmodal-settings", SettingsTable)
    app.add_directive("nsmodal-cpp-headers", CppHeaders)
    app.connect("autodoc-process-docstring", _docstring_as_written)
    app.connect("doctree-read", _header_descriptions_without_group_line)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
