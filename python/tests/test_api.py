# SPDX-License-Identifier: GPL-3.0-or-later
"""The package's public surface: the stub declares what the module has, with the same
parameters, and every public function documents itself."""

import ast
import inspect
import os

import flexrod


def stub_functions():
    path = os.path.join(os.path.dirname(flexrod.__file__), "__init__.pyi")
    with open(path) as f:
        tree = ast.parse(f.read())
    out = {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            a = node.args
            out[node.name] = [x.arg for x in a.args + a.kwonlyargs] + (
                [a.kwarg.arg] if a.kwarg else [])
    classes = {n.name for n in tree.body if isinstance(n, ast.ClassDef)}
    return out, classes


def test_stub_matches_the_module():
    functions, classes = stub_functions()
    public = set(flexrod.__all__)
    assert set(functions) | classes == public
    for name, params in functions.items():
        sig = inspect.signature(getattr(flexrod, name))
        assert list(sig.parameters) == params, name


def test_documented_with_units():
    for name in flexrod.__all__:
        doc = inspect.getdoc(getattr(flexrod, name))
        assert doc and len(doc) > 40, name
    for name, unit in [("run", "[s]"), ("modes", "[Hz]"), ("contact", "[kg]"),
                       ("contact", "[m/s]"), ("keys", "unit")]:
        assert unit in inspect.getdoc(getattr(flexrod, name)), (name, unit)


def test_error_classes():
    assert issubclass(flexrod.InputError, ValueError)
    e = flexrod.InputError("rod.height", "-3 mm", "must be > 0")
    assert (e.key, e.value, e.rule) == ("rod.height", "-3 mm", "must be > 0")
    assert str(e) == "rod.height = -3 mm: must be > 0"
    assert issubclass(flexrod.NumericalError, Exception)
    assert not issubclass(flexrod.NumericalError, ValueError)
