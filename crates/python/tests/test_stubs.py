"""The type stubs (trueaxis/_native.pyi) against the extension module: every function and method
of the module is in the stubs with the same parameters (names, kinds, defaults), and every name
the stubs declare exists; every public function has a docstring that states its units."""

import ast
import inspect
from pathlib import Path

import trueaxis as ta
from trueaxis import _native

STUBS = Path(ta.__file__).with_name("_native.pyi")


def stub_parameters(node):
    """[(name, kind, default source)] of a stub function, without self."""
    a = node.args
    out = []
    positional = a.posonlyargs + a.args
    defaults = [None] * (len(positional) - len(a.defaults)) + a.defaults
    for arg, d in zip(positional, defaults):
        out.append((arg.arg, "positional", None if d is None else ast.unparse(d)))
    for arg, d in zip(a.kwonlyargs, a.kw_defaults):
        out.append((arg.arg, "keyword", None if d is None else ast.unparse(d)))
    return [p for p in out if p[0] != "self"]


def runtime_parameters(fn):
    out = []
    for p in inspect.signature(fn).parameters.values():
        if p.name == "self":
            continue
        kind = "keyword" if p.kind == p.KEYWORD_ONLY else "positional"
        default = None if p.default is p.empty else repr(p.default)
        out.append((p.name, kind, default))
    return out


def normalised(params):
    # the stubs write tuples where PyO3 shows lists ((9, 9, 9) vs [9, 9, 9]) and single quotes;
    # PyO3 shows a default it cannot write (a path) as `...`
    return [(n, k, None if d is None else d.replace("(", "[").replace(")", "]").replace("'", '"')) for n, k, d in params]


def same(stub, runtime):
    return len(stub) == len(runtime) and all(
        s[:2] == r[:2] and (s[2] == r[2] or (r[2] == "Ellipsis" and s[2] is not None)) for s, r in zip(stub, runtime)
    )


def stub_definitions():
    tree = ast.parse(STUBS.read_text())
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            yield node.name, getattr(_native, node.name), node
        elif isinstance(node, ast.ClassDef):
            cls = getattr(_native, node.name)
            for item in node.body:
                if isinstance(item, ast.FunctionDef) and not any(
                    isinstance(d, ast.Name) and d.id == "property" for d in item.decorator_list
                ):
                    yield f"{node.name}.{item.name}", getattr(cls, item.name), item


def test_every_stub_signature_matches_the_module():
    checked = 0
    for name, obj, node in stub_definitions():
        if name.endswith("__len__") or name.endswith("__init__"):
            continue
        stub, runtime = normalised(stub_parameters(node)), normalised(runtime_parameters(obj))
        assert same(stub, runtime), f"{name}: stubs {stub} != module {runtime}"
        checked += 1
    assert checked > 30


def test_every_module_function_is_in_the_stubs_with_units():
    tree = ast.parse(STUBS.read_text())
    declared = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    functions = [n for n in dir(_native) if inspect.isbuiltin(getattr(_native, n)) and not n.startswith("_")]
    assert set(functions) <= declared, set(functions) - declared
    assert set(functions) <= set(ta.__all__)
    units = ("um", "mm", "deg", "degC", "urad", " s ")
    for f in functions:
        doc = getattr(_native, f).__doc__ or ""
        assert any(u in doc for u in units), f"{f}: the docstring states no unit"
