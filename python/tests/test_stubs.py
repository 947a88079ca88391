"""The type stubs describe the native module as it is: the same names, the same parameters,
and every public function and class documented."""

import ast
import inspect
import pathlib

import corps
import corps._corps as native

STUBS = pathlib.Path(corps.__file__).with_name("_corps.pyi")


def stub_items():
    tree = ast.parse(STUBS.read_text())
    functions, classes = {}, {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            functions[node.name] = [a.arg for a in node.args.args]
        elif isinstance(node, ast.ClassDef):
            classes[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
    return functions, classes


def test_every_public_name_has_a_stub():
    functions, classes = stub_items()
    stub_text = STUBS.read_text()
    for name in dir(native):
        if name.startswith("_"):
            continue
        obj = getattr(native, name)
        if inspect.isbuiltin(obj) or callable(obj) and not inspect.isclass(obj):
            assert name in functions, f"{name} has no stub"
        elif inspect.isclass(obj):
            assert name in classes, f"class {name} has no stub"
        else:
            assert f"\n{name}:" in stub_text, f"constant {name} has no stub"
    for name in list(functions) + list(classes):
        assert hasattr(native, name), f"stub {name} names nothing in the module"
    for cls, methods in classes.items():
        stubbed = set(methods) | set(re_properties(cls))
        runtime = getattr(native, cls)
        inherited = set(dir(Exception)) | set(dir(object))
        for attr in dir(runtime):
            if not attr.startswith("_") and attr not in inherited:
                assert attr in stubbed, f"{cls}.{attr} has no stub"


def re_properties(cls):
    """Names a class stub declares as attributes (`name: type`) or properties."""
    tree = ast.parse(STUBS.read_text())
    node = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == cls)
    names = [n.target.id for n in node.body if isinstance(n, ast.AnnAssign)]
    names += [n.targets[0].id for n in node.body if isinstance(n, ast.Assign)]
    return names


def test_stub_parameters_match():
    functions, classes = stub_items()
    for name, params in functions.items():
        runtime = inspect.signature(getattr(native, name))
        assert list(runtime.parameters) == params, name
    for cls, methods in classes.items():
        for method in methods - {"__init__", "__mul__", "__getitem__", "__len__"}:
            assert hasattr(getattr(native, cls), method), f"{cls}.{method}"


def test_everything_public_is_documented():
    for name in dir(native):
        obj = getattr(native, name)
        if name.startswith("_") or not callable(obj):
            continue
        assert (obj.__doc__ or "").strip(), f"{name} has no docstring"
