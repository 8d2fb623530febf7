"""The type stubs (nsmodal/__init__.pyi) against the compiled module: every
public name has a stub and every stub a public name; each function's and
method's parameters (names, kinds, defaults) are those inspect.signature
reports; each property is a property. A stub left behind by a change of the
module fails here."""
import ast
import inspect
import os

import nsmodal

STUB = os.path.join(os.path.dirname(nsmodal.__file__), "__init__.pyi")


def stub_tree():
    with open(STUB, encoding="utf-8") as f:
        return ast.parse(f.read())


REQUIRED = "<required>"  # no default (distinct from a default of None)


def stub_parameters(fn):
    """(name, kind, default) of a stub's def, self dropped."""
    a = fn.args
    out = []
    positional = a.posonlyargs + a.args
    defaults = [None] * (len(positional) - len(a.defaults)) + list(a.defaults)
    for arg, d in zip(positional, defaults):
        out.append((arg.arg, "positional", REQUIRED if d is None else ast.literal_eval(d)))
    if a.vararg:
        out.append((a.vararg.arg, "*args", REQUIRED))
    for arg, d in zip(a.kwonlyargs, a.kw_defaults):
        out.append((arg.arg, "keyword", REQUIRED if d is None else ast.literal_eval(d)))
    if a.kwarg:
        out.append((a.kwarg.arg, "**kwargs", REQUIRED))
    return [p for p in out if p[0] != "self"]


KIND = {
    inspect.Parameter.POSITIONAL_ONLY: "positional",
    inspect.Parameter.POSITIONAL_OR_KEYWORD: "positional",
    inspect.Parameter.KEYWORD_ONLY: "keyword",
    inspect.Parameter.VAR_POSITIONAL: "*args",
    inspect.Parameter.VAR_KEYWORD: "**kwargs",
}


def runtime_parameters(obj):
    out = []
    for p in inspect.signature(obj).parameters.values():
        default = REQUIRED if p.default is inspect.Parameter.empty else p.default
        out.append((p.name, KIND[p.kind], default))
    return [p for p in out if p[0] != "self"]


def test_every_public_name_has_a_stub_and_no_more():
    tree = stub_tree()
    stubbed = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    stubbed |= {t.id for n in tree.body if isinstance(n, ast.AnnAssign) for t in [n.target]}
    public = set(nsmodal.__all__) | {"__version__"}
    assert public == stubbed, public ^ stubbed


def test_the_stubs_parameters_are_the_modules():
    compared = 0
    for node in stub_tree().body:
        if isinstance(node, ast.FunctionDef):
            assert stub_parameters(node) == runtime_parameters(getattr(nsmodal, node.name)), node.name
            compared += 1
        elif isinstance(node, ast.ClassDef):
            cls = getattr(nsmodal, node.name)
            # Every public member of the class has a stub.
            stubbed = {item.name for item in node.body if isinstance(item, ast.FunctionDef)}
            public = {n for n in vars(cls) if not n.startswith("_")}
            assert public <= stubbed, f"{node.name}: no stub for {sorted(public - stubbed)}"
            for item in node.body:
                if not isinstance(item, ast.FunctionDef):
                    continue
                member = inspect.getattr_static(cls, item.name)
                if any(isinstance(d, ast.Name) and d.id == "property" for d in item.decorator_list):
                    assert isinstance(member, property), f"{node.name}.{item.name} is not a property"
                elif item.name not in ("__getstate__", "__setstate__"):  # pybind11 gives these no signature
                    assert stub_parameters(item) == runtime_parameters(getattr(cls, item.name)), (
                        f"{node.name}.{item.name}")
                compared += 1
    assert compared >= 40  # 14 functions, 26 members today


def test_the_package_is_typed_and_pickles_as_nsmodal():
    package = os.path.dirname(nsmodal.__file__)
    assert os.path.isfile(os.path.join(package, "py.typed"))
    assert nsmodal.Model.__module__ == "nsmodal" and nsmodal.simulate.__module__ == "nsmodal"
    import pickle
    m = nsmodal.Model(masses=[1, 1], springs=[0.85, 2], gap=1.0, restitution=1.0)
    assert b"nsmodal._nsmodal" not in pickle.dumps(m)


def test_mypy_checks_code_against_the_stubs(tmp_path):
    """mypy (Debian's, scripts/setup.sh) reads the stubs strictly and catches a
    misspelt keyword and a wrong type in a user's code, and passes good code."""
    import subprocess
    import sys
    good = tmp_path / "good.py"
    good.write_text("import nsmodal\nm = nsmodal.load_scene('paper')\no = nsmodal.orbits(m, period=(1.0, 2.0, 0.5))\n"
                    "d: float = m.gap\ns = nsmodal.simulate(m, [0.0, 0.0], [1.0, 0.0], t_end=1.0)\n")
    bad = tmp_path / "bad.py"
    bad.write_text("import nsmodal\nm = nsmodal.load_scene('paper')\nd: str = m.gap\n"
                   "nsmodal.orbits(m, period=(1.0, 2.0, 0.5), stabilty='x')\n")
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(nsmodal.__file__)))

    def mypy(*paths):
        return subprocess.run([sys.executable, "-m", "mypy", "--strict", "--cache-dir", str(tmp_path / "cache"),
                               *map(str, paths)], capture_output=True, text=True, env=env, cwd=tmp_path)

    ok = mypy(STUB, good)
    assert ok.returncode == 0, ok.stdout + ok.stderr
    wrong = mypy(bad)
    assert wrong.returncode == 1, wrong.stdout + wrong.stderr
    assert 'Unexpected keyword argument "stabilty"' in wrong.stdout
    assert "Incompatible types in assignment" in wrong.stdout
