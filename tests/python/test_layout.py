"""The kernel's house: layers that use only the layers before them, no include circle, files a reader
can hold (README, "Layout")."""
import os
import re

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
KERNEL = os.path.join(ROOT, "kernel")
LAYERS = ["core", "boolean", "validate", "guide", "design", "io"]
MAX_LINES = 600


def kernel_files():
    for base in ("include/st", "src"):
        for folder, _, files in os.walk(os.path.join(KERNEL, base)):
            for f in files:
                if f.endswith((".h", ".cpp")):
                    yield os.path.join(folder, f)


def layer_of(path):
    rel = os.path.relpath(path, KERNEL).split(os.sep)
    rel = rel[2:] if rel[0] == "include" else rel[1:]
    return rel[0] if rel[0] in LAYERS else None


def includes(path):
    """The project files `path` includes, as paths."""
    out = []
    for name in re.findall(r'^#include "([^"]+)"', open(path).read(), re.M):
        for base in (os.path.dirname(path), os.path.join(KERNEL, "include"), os.path.join(KERNEL, "src")):
            candidate = os.path.normpath(os.path.join(base, name))
            if os.path.exists(candidate):
                out.append(candidate)
                break
    return out


def test_every_source_file_is_in_a_layer_folder():
    loose = [os.path.relpath(f, ROOT) for f in kernel_files()
             if layer_of(f) is None and "/src/detail/" not in f]
    assert not loose, loose


def test_layers_use_only_the_layers_before_them():
    wrong = []
    for f in kernel_files():
        mine = layer_of(f)
        for g in includes(f):
            theirs = layer_of(g)
            if mine and theirs and LAYERS.index(theirs) > LAYERS.index(mine):
                wrong.append("%s (%s) includes %s (%s)" % (os.path.relpath(f, ROOT), mine,
                                                           os.path.relpath(g, ROOT), theirs))
    assert not wrong, "\n".join(wrong)


def test_no_include_circle():
    graph = {f: includes(f) for f in kernel_files()}
    state = {}

    def visit(f, stack):
        state[f] = "open"
        for g in graph.get(f, []):
            if state.get(g) == "open":
                raise AssertionError("include circle: " + " -> ".join(os.path.relpath(x, ROOT) for x in stack + [g]))
            if g not in state:
                visit(g, stack + [g])
        state[f] = "done"

    for f in graph:
        if f not in state:
            visit(f, [f])


def test_no_source_file_over_600_lines():
    long = []
    for folder in ("kernel", "tests/kernel", "tests/python", "tests/freecad", "workbench"):
        for dirpath, _, files in os.walk(os.path.join(ROOT, folder)):
            for f in files:
                if f.endswith((".h", ".cpp", ".py")) and "compat" not in dirpath:
                    n = sum(1 for _ in open(os.path.join(dirpath, f)))
                    if n > MAX_LINES:
                        long.append("%s: %d lines" % (os.path.relpath(os.path.join(dirpath, f), ROOT), n))
    assert not long, "\n".join(long)
