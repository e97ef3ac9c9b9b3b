"""Strings marked for translation: each command's menu text and tip are QT_TRANSLATE_NOOP literals in the
context FreeCAD translates them in (the command's name), the workbench's in "Workbench", and InitGui.py
puts the translations folder on FreeCAD's language path. Read from the sources (lupdate reads them so)."""
import ast
import glob
import os

from fc_session import ROOT

WORKBENCH = os.path.join(ROOT, "workbench", "SurgicalTemplate")


def noop(node):
    """(context, text) of a QT_TRANSLATE_NOOP call on string literals, else None."""
    if not isinstance(node, ast.Call) or len(node.args) != 2:
        return None
    name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
    if name != "QT_TRANSLATE_NOOP" or not all(isinstance(a, ast.Constant) and isinstance(a.value, str)
                                               for a in node.args):
        return None
    return node.args[0].value, node.args[1].value


def command_classes():
    for path in glob.glob(os.path.join(WORKBENCH, "stcommands", "*.py")):
        tree = ast.parse(open(path, encoding="utf-8").read())
        for cls in [n for n in tree.body if isinstance(n, ast.ClassDef)]:
            values = {}
            for stmt in cls.body:
                if isinstance(stmt, ast.Assign):
                    targets = stmt.targets[0]
                    names = [t.id for t in targets.elts] if isinstance(targets, ast.Tuple) else [targets.id]
                    nodes = stmt.value.elts if isinstance(stmt.value, ast.Tuple) else [stmt.value]
                    values.update(zip(names, nodes))
            if "name" in values:
                yield os.path.basename(path), cls.name, values


def test_every_command_menu_text_and_tip_is_marked_in_its_context():
    seen = 0
    for path, cls, values in command_classes():
        name = values["name"].value
        if not name:
            continue
        for key in ("menu", "tip"):
            marked = noop(values.get(key))
            assert marked is not None, f"{path}: {cls}.{key} is not a QT_TRANSLATE_NOOP literal"
            assert marked[0] == f"SurgicalTemplate_{name}" and marked[1].strip(), (path, cls, key)
        seen += 1
    assert seen >= 14


def test_workbench_texts_marked_and_the_language_path_added():
    source = open(os.path.join(WORKBENCH, "InitGui.py"), encoding="utf-8").read()
    tree = ast.parse(source)
    bench = [n for n in tree.body if isinstance(n, ast.ClassDef)][0]
    texts = {s.targets[0].id: noop(s.value) for s in bench.body if isinstance(s, ast.Assign)}
    assert texts["MenuText"] == ("Workbench", "Surgical Template") and texts["ToolTip"][0] == "Workbench"
    assert "Gui.addLanguagePath(SurgicalTemplate_paths.TRANSLATIONS)" in source
    assert os.path.isdir(os.path.join(WORKBENCH, "Resources", "translations"))
