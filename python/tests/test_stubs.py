"""The type stubs (railfem/__init__.pyi, PEP 561) against the package they describe.

The signatures in the stub must be the runtime's (names, order, keyword-only, defaults),
the TypedDicts must name exactly the keys the cases return, and mypy must accept a typed
use of the API and refuse a wrong one.
"""

import ast
import inspect
import pathlib
import subprocess
import sys

import pytest

import railfem

PKG = pathlib.Path(railfem.__file__).parent
STUB = ast.parse((PKG / "__init__.pyi").read_text())


def stub_function(name):
    for node in STUB.body:
        if isinstance(node, ast.FunctionDef) and node.name == name:
            return node
    raise AssertionError(f"no {name} in the stub")


def stub_typeddict_keys(name):
    for node in STUB.body:
        if isinstance(node, ast.ClassDef) and node.name == name:
            return [n.target.id for n in node.body if isinstance(n, ast.AnnAssign)]
    raise AssertionError(f"no {name} in the stub")


def stub_params(fn):
    """(name, keyword-only, default as a Python value or inspect.Parameter.empty)."""
    a = fn.args
    out = []
    pos_defaults = [inspect.Parameter.empty] * (len(a.args) - len(a.defaults)) + [
        ast.literal_eval(d) for d in a.defaults
    ]
    for arg, d in zip(a.args, pos_defaults):
        out.append((arg.arg, False, d))
    for arg, d in zip(a.kwonlyargs, a.kw_defaults):
        out.append((arg.arg, True, inspect.Parameter.empty if d is None else ast.literal_eval(d)))
    return out


def runtime_params(f):
    return [
        (p.name, p.kind == inspect.Parameter.KEYWORD_ONLY, p.default)
        for p in inspect.signature(f).parameters.values()
    ]


@pytest.mark.parametrize(
    "name", ["curve", "train_bridge", "critical_radius", "elements", "load_plugin"]
)
def test_stub_signatures_are_the_runtime_ones(name):
    assert stub_params(stub_function(name)) == runtime_params(getattr(railfem, name))


def test_package_is_marked_typed():
    assert (PKG / "py.typed").exists()


def test_curve_result_keys_are_the_stub_ones():
    r = railfem.curve(quick=True)
    assert sorted(r) == sorted(stub_typeddict_keys("CurveResult"))
    assert sorted(r["wheels"]) == sorted(stub_typeddict_keys("CurveWheels"))
    assert sorted(r["metrics"]) == sorted(stub_typeddict_keys("CurveMetrics"))
    assert sorted(r["stats"]) == sorted(stub_typeddict_keys("CaseStats"))


def test_element_kind_keys_are_the_stub_ones():
    kinds = railfem.elements()
    assert sorted(kinds[0]) == sorted(stub_typeddict_keys("ElementKindDoc"))
    assert sorted(kinds[0]["params"][0]) == sorted(stub_typeddict_keys("ParamDoc"))


GOOD = """
import railfem
r = railfem.curve(quick=True, speed=80.0, geometry="nonlinear")
q: float = float(r["wheels"]["Q_fe"][0, 0])
m: float = r["metrics"]["max_rel_shear"]
tb = railfem.train_bridge(cars=1, spans=2, steps=3)
d = tb["midspan"][1]["deflection"]
res = railfem.Model.from_file("m.toml").run()
n: int = res.stats["steps"]
"""

BAD = """
import railfem
railfem.curve(speed="fast")
railfem.curve(geometry="curly")
x: str = railfem.curve()["metrics"]["max_rel_shear"]
"""


def mypy(tmp_path, text):
    f = tmp_path / "use.py"
    f.write_text(text)
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--no-incremental", "--cache-dir", str(tmp_path / "cache"), str(f)],
        capture_output=True,
        text=True,
    )


def test_mypy_accepts_typed_use_and_refuses_wrong_types(tmp_path):
    pytest.importorskip("mypy")
    ok = mypy(tmp_path, GOOD)
    assert ok.returncode == 0, ok.stdout + ok.stderr
    bad = mypy(tmp_path, BAD)
    errors = [l for l in bad.stdout.splitlines() if ": error:" in l]
    # One error per wrong line: a str for a float, an unknown geometry, a float for a str.
    assert len(errors) == 3, bad.stdout
