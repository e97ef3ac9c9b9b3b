"""The workbench's layout (no FreeCAD needed: the modules are parsed, not run): its modules import one
another in one direction only, counting imports inside functions too, both module by module and
package by package (the layers); the object modules import no GUI code; no file is over 600 lines."""
import ast
import os

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
WORKBENCH = os.path.join(ROOT, "workbench", "SurgicalTemplate")
MAX_LINES = 600
GUI_MODULES = ("FreeCADGui", "PySide", "PySide2", "pivy")
GUI_LAYERS = ("stviewproviders", "sttaskpanels", "stcommands", "stutils", "InitGui")


def _modules():
    """{module name: path} of every Python file of the workbench (Mod/SurgicalTemplate is on sys.path)."""
    found = {}
    for folder, _, files in os.walk(WORKBENCH):
        for f in files:
            if f.endswith(".py"):
                parts = os.path.relpath(os.path.join(folder, f), WORKBENCH)[:-3].split(os.sep)
                if parts[-1] == "__init__":
                    parts = parts[:-1]
                found[".".join(parts)] = os.path.join(folder, f)
    return found


MODULES = _modules()


def _imported(name):
    """Every module an import statement names: the module itself and the packages it runs on the way."""
    parts = name.split(".")
    return {".".join(parts[:i]) for i in range(1, len(parts) + 1)}


def imports_of(module):
    """All names `module` imports anywhere in its code (module level and inside functions)."""
    path = MODULES[module]
    package = module if path.endswith("__init__.py") else module.rpartition(".")[0]
    names = set()
    for node in ast.walk(ast.parse(open(path).read(), path)):
        if isinstance(node, ast.Import):
            for a in node.names:
                names |= _imported(a.name)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([p for p in anchor if p] + ([base] if base else []))
            names |= _imported(base)
            names |= {f"{base}.{a.name}" for a in node.names if f"{base}.{a.name}" in MODULES}
    return names


def graph(layer=lambda m: m):
    edges = {}
    for m in MODULES:
        mine = edges.setdefault(layer(m), set())
        mine |= {layer(n) for n in imports_of(m) if n in MODULES and layer(n) != layer(m)}
    return edges


def cycle(edges):
    """One import cycle as a list of names, or None."""
    state, stack = {}, []

    def visit(n):
        state[n] = "open"
        stack.append(n)
        for m in sorted(edges.get(n, ())):
            if state.get(m) == "open":
                return stack[stack.index(m):] + [m]
            if m not in state:
                found = visit(m)
                if found:
                    return found
        stack.pop()
        state[n] = "done"
        return None

    for n in sorted(edges):
        if n not in state:
            found = visit(n)
            if found:
                return found
    return None


def test_the_workbench_is_split_by_role():
    for package in ("stobjects", "stviewproviders", "stfunctions", "stmake", "stdrawing", "sttaskpanels",
                    "stcommands"):
        assert package in MODULES, f"{package}/__init__.py missing"
    for name in ("boundary", "tube", "validate"):
        assert os.path.exists(os.path.join(WORKBENCH, "Resources", "ui", f"{name}.ui"))


def test_no_import_cycle_among_modules():
    found = cycle(graph())
    assert found is None, "import cycle: " + " -> ".join(found)


def test_no_import_cycle_among_layers():
    found = cycle(graph(lambda m: m.split(".")[0]))
    assert found is None, "the layers import one another in a circle: " + " -> ".join(found)


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m.split(".")[0] == "stobjects"))
def test_objects_import_no_gui(module):
    gui = sorted(n for n in imports_of(module)
                 if n.split(".")[0] in GUI_MODULES + GUI_LAYERS or n.split(".")[0].endswith("Gui"))
    assert not gui, f"{module} imports GUI code: {gui}"


def test_no_file_over_600_lines():
    long = []
    for folder, _, files in os.walk(WORKBENCH):
        for f in files:
            path = os.path.join(folder, f)
            if f.endswith((".py", ".ui", ".xml")):
                with open(path, encoding="utf-8") as fh:
                    n = sum(1 for _ in fh)
                if n > MAX_LINES:
                    long.append(f"{os.path.relpath(path, WORKBENCH)}: {n} lines")
    assert not long, long


def test_saved_proxy_classes_still_resolve():
    """Documents name their proxies st_features.<class>: the alias module must keep every name."""
    tree = ast.parse(open(MODULES["st_features"]).read())
    names = {a.asname or a.name for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) for a in node.names}
    assert {"Boundary", "Template", "Tube", "Guide", "ViewProvider"} <= names
