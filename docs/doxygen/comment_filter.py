"""Doxygen INPUT_FILTER for nsmodal's headers: their plain // comments as
documentation.

The headers document every declaration in ordinary // comments (plain text,
aligned formulas, no Doxygen markup), which Doxygen would skip. This filter
rewrites them, on the fly and only for Doxygen, as documentation blocks whose
text is kept verbatim (so `x_c <= d`, `*args`, `\\` or `#` are never read as
markup and the alignment of the formulas survives):

- the first comment block of the file (after `#pragma once`) -> the
  header's description;
- a block of comment-only lines -> the description of the declaration after it;
- a comment after code on the same line (and the comment-only lines below it
  that start in the same column) -> the description of that member (`/**<`);
- each namespace block and each macro -> the Doxygen group of the header
  (`nsmodal_model_h` for nsmodal/model.h, `\\defgroup`'d with the file's
  description), which the reference pages show with `doxygengroup`;
- a member's C++20 designated initializer, which Sphinx's C++ parser does not
  read, -> moved into its description ("Default: {.a = ...}").

Usage (Doxygen appends the path): python3 comment_filter.py HEADER
"""
import os
import re
import sys

COMMENT_ONLY = re.compile(r"^(\s*)//(?!/)(.*)$")
# The headers open and close their namespaces at column 0.
NAMESPACE_OPEN = re.compile(r"^namespace [\w:]+ \{\s*$")
NAMESPACE_CLOSE = re.compile(r"^\}\s*// namespace")
# A member with a designated initializer: `SweepOptions sweep{.a = 1, ...};`
DESIGNATED_INIT = re.compile(r"^(\s*[^/{}]*\w)(\{\..*\});\s*$")


def code_comment_split(line):
    """(code, comment) of a line whose // starts a comment after code, or None."""
    quote = None
    i = 0
    while i < len(line) - 1:
        ch = line[i]
        if quote:
            if ch == "\\":
                i += 2
                continue
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
        elif line.startswith("//", i):
            code = line[:i]
            if code.strip():
                return code, line[i + 2:], i
            return None
        i += 1
    return None


def verbatim(text_lines, opener):
    """The comment's lines (less the one space after "//") in a verbatim block,
    at column 0: a verbatim block keeps every leading space."""
    body = [t[1:] if t.startswith(" ") else t for t in text_lines]
    while body and not body[-1].strip():
        body.pop()
    return [f"{opener} \\verbatim"] + [t.rstrip() for t in body] + ["\\endverbatim */"]


def rewrite(lines, group):
    """The header's lines rewritten; what each namespace block declares, and
    each macro, in one Doxygen group named `group` (titled by the header's
    include path), whose description is the file's first comment block."""
    name, title = group
    opened = False
    out = []
    i = 0
    n = len(lines)
    while i < n:
        line = lines[i]
        m = COMMENT_ONLY.match(line)
        if m:
            indent = m.group(1)
            block = []
            while i < n:
                mm = COMMENT_ONLY.match(lines[i])
                if not mm or mm.group(1) != indent:
                    break
                block.append(mm.group(2))
                i += 1
            if not opened:
                out += verbatim(block, f"/** \\defgroup {name} {title}\n")
                opened = True  # the first block describes the header
            else:
                out += verbatim(block, "/**")
            continue
        split = code_comment_split(line)
        # (not after a preprocessor line or a closing brace: "}  // namespace")
        if split and not line.lstrip().startswith("#") and split[0].strip() not in ("}", "};"):
            code, text, column = split
            block = [text]
            i += 1
            # Comment-only lines starting in the same column continue it.
            while i < n:
                mm = COMMENT_ONLY.match(lines[i])
                if not mm or len(mm.group(1)) != column:
                    break
                block.append(mm.group(2))
                i += 1
            out.append(code.rstrip())
            out += verbatim(block, "/**<")
            continue
        designated = DESIGNATED_INIT.match(line)
        if designated:
            # Sphinx's C++ parser does not know C++20 designated initializers:
            # the member declared without it, the initializer in its text.
            out += verbatim([" Default: " + designated.group(2)], "/**")
            line = designated.group(1) + ";"
        stripped = line.strip()
        if stripped and not stripped.startswith("#pragma") and not opened:
            out.append(f"/** \\defgroup {name} {title} */")
            opened = True
        if NAMESPACE_CLOSE.match(line):
            out.append("/** @} */")
        if line.startswith("#define"):  # a macro: outside the namespaces
            out.append(f"/** \\ingroup {name} */")
        out.append(line)
        if NAMESPACE_OPEN.match(line):
            out.append(f"/** \\addtogroup {name}\n@{{ */")
        i += 1
    return out


def group_of(path):
    """("nsmodal_model_h", "nsmodal/model.h") for .../include/nsmodal/model.h."""
    title = "nsmodal/" + os.path.basename(path)
    return re.sub(r"[^A-Za-z0-9]", "_", title), title


def main():
    with open(sys.argv[1], encoding="utf-8") as f:
        lines = f.read().splitlines()
    sys.stdout.write("\n".join(rewrite(lines, group_of(sys.argv[1]))) + "\n")


if __name__ == "__main__":
    main()
