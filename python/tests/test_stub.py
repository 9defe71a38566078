"""The type stub (_ffdaabb.pyi) describes the module as built: every public name, class member and
function is in it, and nothing more; the package exports what it says."""

import ast
import inspect
from pathlib import Path

import ffdaabb
import ffdaabb._ffdaabb as ext

STUB = Path(ffdaabb.__file__).with_name("_ffdaabb.pyi")


def stub_names() -> tuple[set, dict]:
    tree = ast.parse(STUB.read_text())
    top, classes = set(), {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            top.add(node.name)
            members = set()
            for item in node.body:
                if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    members.add(item.name)
                elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                    members.add(item.target.id)
            classes[node.name] = members
        elif isinstance(node, ast.FunctionDef):
            top.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            top.add(node.target.id)
    return top, classes


def public(names) -> set:
    return {n for n in names if not n.startswith("_") or n in ("__init__", "__len__", "__version__")}


def test_the_stub_names_every_public_name_of_the_module():
    top, classes = stub_names()
    module = public(n for n in dir(ext) if not (n.startswith("__") and n != "__version__"))
    module |= {n for n in dir(ext) if n == "_detach"}
    assert module <= top, f"missing from the stub: {sorted(module - top)}"
    for name, members in classes.items():
        cls = getattr(ext, name)
        if issubclass(cls, BaseException):
            continue
        built = public(vars(cls)) - {"__init__"} if name in ("BodyId", "PinId", "PlaneId", "Ranges") else public(vars(cls))
        built -= {"__eq__", "__hash__", "__repr__"}
        assert built <= members | {"__init__"}, f"{name}: missing from the stub: {sorted(built - members)}"
        stubbed = members - {"__eq__", "__hash__", "__init__", "__len__"}
        assert stubbed <= public(vars(cls)), f"{name}: in the stub only: {sorted(stubbed - public(vars(cls)))}"


def test_every_stub_function_exists_and_is_documented():
    top, _ = stub_names()
    for name in top:
        assert hasattr(ext, name) or name in ("Vec3Like", "QuatLike", "Vec3", "Points", "CollisionMode", "DynamicsModel", "BodyMotion"), name
    for cls in (ext.World, ext.WorldSettings, ext.BodySettings, ext.PinSettings, ext.LatticeSettings):
        for name, member in inspect.getmembers(cls):
            if name.startswith("_") or name in ("fields", "copy"):
                continue
            lines = [l for l in (getattr(member, "__doc__", None) or "").strip().splitlines() if l.strip()]
            # pybind11 puts the signature first; a documented member has a line after it.
            text = [l for l in lines if not l.startswith(name + "(") and not l.startswith("(")]
            assert text, f"{cls.__name__}.{name} has no documentation"


def test_the_package_exports_what_it_lists():
    assert sorted(ffdaabb.__all__) == sorted(set(ffdaabb.__all__))
    for name in ffdaabb.__all__:
        assert hasattr(ffdaabb, name), name
    exported = {n for n in dir(ext) if not n.startswith("_")}
    assert exported <= set(ffdaabb.__all__), sorted(exported - set(ffdaabb.__all__))
    assert (Path(ffdaabb.__file__).parent / "py.typed").exists()
