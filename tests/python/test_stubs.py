# SPDX-License-Identifier: MIT
"""The type stubs (lib/python/ecmxf/__init__.pyi) and the docstrings
follow the module: every public name, every public method and property
of every class is in the stubs, and the stubs name nothing the module
lacks (a binding added without its stub fails here)."""

import ast
import enum
import inspect
import os

import ecmxf

STUBS = os.path.join(os.path.dirname(ecmxf.__file__), "__init__.pyi")


def stub_names():
    tree = ast.parse(open(STUBS).read())
    top, members = set(), {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            top.add(node.name)
            names = set()
            for n in node.body:
                if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    names.add(n.name)
                elif isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name):
                    names.add(n.target.id)
            members[node.name] = names
        elif isinstance(node, ast.FunctionDef):
            top.add(node.name)
    return top, members


def public_members(cls):
    own = set()
    for klass in cls.__mro__:
        if klass.__module__ in ("builtins",) or klass is object:
            continue
        own |= {n for n in vars(klass) if not n.startswith("_")}
    if isinstance(cls, type) and hasattr(cls, "__members__") and not issubclass(cls, BaseException):
        own -= {"name", "value"}                            # pybind11 enums' own
    return own


def test_every_public_name_has_a_stub():
    top, _ = stub_names()
    assert set(ecmxf.__all__) - top == set()
    assert top - set(dir(ecmxf)) == set()


def test_every_method_and_property_has_a_stub():
    _, members = stub_names()
    missing = {}
    for name in ecmxf.__all__:
        obj = getattr(ecmxf, name)
        if not inspect.isclass(obj) or issubclass(obj, BaseException):
            continue
        lack = public_members(obj) - members.get(name, set())
        if lack:
            missing[name] = sorted(lack)
    assert missing == {}


def test_stubs_name_nothing_the_module_lacks():
    _, members = stub_names()
    extra = {}
    for cls, names in members.items():
        obj = getattr(ecmxf, cls, None)
        assert obj is not None, cls
        if issubclass(obj, BaseException):
            continue                                        # their attributes are the instances' (.code...)
        lack = {n for n in names if not n.startswith("_") and not hasattr(obj, n)}
        if lack:
            extra[cls] = sorted(lack)
    assert extra == {}


def test_docstrings():
    for name in ecmxf.__all__:
        obj = getattr(ecmxf, name)
        assert obj.__doc__, name
        if inspect.isclass(obj) and not issubclass(obj, (BaseException, enum.Enum)):
            for m in public_members(obj):
                attr = getattr(obj, m)
                if callable(attr) and not isinstance(attr, type):
                    assert attr.__doc__, f"{name}.{m}"
