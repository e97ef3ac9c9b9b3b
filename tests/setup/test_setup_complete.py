"""The set-up list (scripts/packages.txt) is complete, proven from what the build and the tests used.

A green CI on a machine that was set up before proves nothing about a fresh one: a package installed by
hand, or pulled in by something else, hides a missing line. So this test collects every file under /usr
that was used:
  - the compilers' dependency files (*.o.d) and the linker's (link-deps/*.d) of each build tree,
    the absolute paths on the link lines (link.txt), every CMake file the configuration loaded
    (CMakeFiles/Makefile.cmake),
  - every module that the Python tests, the workbench and the examples import (their __file__, and the
    shared libraries the importing process mapped), imported inside FreeCAD as the tests do,
  - the programs the Makefile and the tests run,
maps each to its Debian package (dpkg -S) and fails, naming the file and its package, when that package
is neither in the list nor installed as a dependency of one in it (apt-cache depends --recurse over the
list, installed packages only). The self-check shows it can fail: the list minus any one package fails.

Run by `make test` after every build tree is built (ST_BUILD_DIRS names them, default build).
"""
import ast
import collections
import glob
import json
import os
import re
import shutil
import subprocess
import sys

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PACKAGE_LIST = os.path.join(ROOT, "scripts", "packages.txt")
BUILD_DIRS = [os.path.join(ROOT, d) for d in os.environ.get("ST_BUILD_DIRS", "build").split()]

# The programs the Makefile, CI and the tests run (besides the compilers CMake records).
PROGRAMS = ["cmake", "ctest", "make", "xvfb-run", "Xvfb", "xauth", "freecad", "freecadcmd",
            "pdftotext", "pdftoppm", "rsvg-convert", "/usr/bin/python3", "clang", "clang++", "clang-format"]

# Data files the kernel reads at run time: the labels' font (kernel/occt/src/occt_text.cpp).
RUNTIME_DATA = ["/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"]


def read_package_list(path=PACKAGE_LIST):
    packages = []
    for line in open(path):
        packages += line.split("#", 1)[0].split()
    return packages


# ---- files used ----------------------------------------------------------------------------------

def _depfile_paths(path):
    """The prerequisites of a make-style dependency file (compiler -MD, ld --dependency-file)."""
    text = open(path, errors="replace").read().replace("\\\n", " ")
    paths = []
    for line in text.splitlines():
        if ":" not in line:
            continue
        target, _, prereqs = line.partition(": ")
        paths += [p for p in re.split(r"(?<!\\)\s+", prereqs) if p]
    return paths


def _cmake_loaded_files(build):
    """Every CMake file the configuration read (CMAKE_MAKEFILE_DEPENDS of the Makefile generator)."""
    path = os.path.join(build, "CMakeFiles", "Makefile.cmake")
    text = open(path).read()
    block = text[text.index("set(CMAKE_MAKEFILE_DEPENDS"):]
    block = block[:block.index("\n  )")]
    return re.findall(r'"([^"]+)"', block)


def _link_line_paths(build):
    paths = []
    for link in glob.glob(os.path.join(build, "**", "link.txt"), recursive=True):
        paths += re.findall(r"(?<![\w=])(/usr/[^\s]+)", open(link).read())
    return paths


def _compilers(build):
    cache = open(os.path.join(build, "CMakeCache.txt")).read()
    return re.findall(r"^CMAKE_(?:CXX|C)_COMPILER:\w+=(/\S+)$", cache, re.M)


def build_files(build):
    files = []
    for dep in glob.glob(os.path.join(build, "**", "*.o.d"), recursive=True):
        files += _depfile_paths(dep)
    for dep in glob.glob(os.path.join(build, "link-deps", "*.d")):
        files += _depfile_paths(dep)
    files += _cmake_loaded_files(build) + _link_line_paths(build) + _compilers(build)
    return [f for f in files if os.path.isabs(f)]


def _imported_names():
    """Top-level names imported anywhere in the tests, the workbench and the examples, less the
    project's own modules."""
    own, names = set(), set()
    sources = []
    for sub in ("tests", "workbench", "examples", "bench"):
        sources += glob.glob(os.path.join(ROOT, sub, "**", "*.py"), recursive=True)
    for path in sources:
        own.add(os.path.splitext(os.path.basename(path))[0])
    for path in sources:
        if "/bench/" in path:
            continue  # the benchmark's references come from `make bench-references`' own extras
        for node in ast.walk(ast.parse(open(path).read(), path)):
            if isinstance(node, ast.Import):
                names.update(a.name.split(".")[0] for a in node.names)
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names.add(node.module.split(".")[0])
    return sorted(names - own - set(sys.builtin_module_names))


PROBE = r"""
import importlib, importlib.util, json, sys

def loaded():
    files = {getattr(m, "__file__", None) for m in list(sys.modules.values())}
    for line in open("/proc/self/maps"):
        parts = line.split()
        if len(parts) >= 6 and parts[5].startswith("/"):
            files.add(parts[5])
    return files - {None}

# What FreeCAD loaded by itself (site hooks, its start-up) belongs to FreeCAD's package; what the
# imports below add is what the project's code needs.
before = loaded()
names = json.loads(sys.argv[-2])
files, failed = set(), []
for name in names:
    try:
        importlib.import_module(name)
    except Exception as e:  # a GUI-only module in the console: its file, without running it
        spec = importlib.util.find_spec(name)
        if spec is None or not spec.origin:
            failed.append(name + ": " + repr(e))
        else:
            files.add(spec.origin)
files |= loaded() - before
with open(sys.argv[-1], "w") as out:
    json.dump({"files": sorted(files), "failed": failed}, out)
"""


def python_files(tmp_dir):
    """Files of the modules the Python code imports, imported inside FreeCAD (as the tests run)."""
    probe = os.path.join(tmp_dir, "probe.py")
    out = os.path.join(tmp_dir, "probe.json")
    open(probe, "w").write(PROBE)
    names = _imported_names()
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [os.path.join(b, "python") for b in BUILD_DIRS] + [os.path.join(ROOT, "workbench", "SurgicalTemplate")]))
    p = subprocess.run(["freecadcmd", probe, json.dumps(names), out], capture_output=True, text=True,
                       timeout=300, env=env)
    assert os.path.exists(out), p.stdout + p.stderr
    result = json.load(open(out))
    assert not result["failed"], "modules the code imports that cannot be found: %s" % result["failed"]
    files = []
    for f in result["files"]:
        m = re.match(r"(.*)/__pycache__/([^.]+)\..*\.pyc$", f)
        files.append(os.path.join(m.group(1), m.group(2) + ".py") if m else f)
    return files


def program_files():
    files = []
    for name in PROGRAMS:
        path = shutil.which(name)
        assert path, "the program '%s' that the tests run is not installed" % name
        files.append(path)
    return files


# ---- files -> packages -----------------------------------------------------------------------------

def _spellings(path):
    """The file as dpkg may know it: Debian's merged /usr gives each file two names."""
    out = [path]
    for a, b in (("/usr/lib/", "/lib/"), ("/usr/bin/", "/bin/"), ("/usr/sbin/", "/sbin/"),
                 ("/lib/", "/usr/lib/"), ("/bin/", "/usr/bin/"), ("/sbin/", "/usr/sbin/")):
        if path.startswith(a):
            out.append(b + path[len(a):])
    return out


def owners(paths):
    """{path: set of packages owning it}; unowned paths (e.g. /etc/alternatives links) map to {}.
    A symbolic link and the file it names are two files the build needs (libtbb.so, a link of
    libtbb-dev, names libtbb.so.12 of libtbb12): pass both."""
    spellings = {p: _spellings(p) for p in paths}
    every = sorted({c for cs in spellings.values() for c in cs})
    owner_of = collections.defaultdict(set)
    for i in range(0, len(every), 500):
        p = subprocess.run(["dpkg-query", "-S", *every[i:i + 500]], capture_output=True, text=True)
        for line in p.stdout.splitlines():
            if line.startswith("diversion by") or ": " not in line:
                continue
            pkgs, _, path = line.partition(": ")
            owner_of[path].update(x.strip().split(":")[0] for x in pkgs.split(","))
    return {p: set().union(*(owner_of.get(c, set()) for c in cs)) for p, cs in spellings.items()}


def _installed():
    p = subprocess.run(["dpkg-query", "-W", "-f", "${Package} ${Status} ${Essential}\\n"],
                       capture_output=True, text=True, check=True)
    installed, essential = set(), set()
    for line in p.stdout.splitlines():
        name, *rest = line.split()
        if "installed" in rest[:3] and rest[:2] == ["install", "ok"]:
            installed.add(name)
            if rest[-1] == "yes":
                essential.add(name)
    return installed, essential


_INSTALLED, _ESSENTIAL = _installed()
_DEPENDS = {}


def _depends(packages):
    """{package: installed packages it depends on} (Depends, Pre-Depends; a virtual package's
    installed providers), cached."""
    todo = [p for p in packages if p not in _DEPENDS]
    if todo:
        out = subprocess.run(["apt-cache", "depends", "--installed", "--no-recommends", "--no-suggests",
                              "--no-conflicts", "--no-breaks", "--no-replaces", "--no-enhances", *todo],
                             capture_output=True, text=True, check=True).stdout
        current = None
        for line in out.splitlines():
            if not line[:1].isspace():
                current = line.strip().split(":")[0]
                _DEPENDS.setdefault(current, set())
                continue
            m = re.match(r"\s*\|?(?:Pre)?Depends: <?([^>\s:]+)", line)
            name = m.group(1) if m else (line.strip().split(":")[0] if line.startswith("    ") else None)
            if current and name in _INSTALLED:
                _DEPENDS[current].add(name)
    return {p: _DEPENDS.get(p, set()) for p in packages}


def closure(packages, without=()):
    """The packages, every installed package they depend on, recursively, and Debian's essential
    packages (present on every Debian system) with theirs; `without`: packages taken as absent."""
    seen = (set(packages) | _ESSENTIAL) - set(without)
    frontier = list(seen)
    while frontier:
        new = set().union(*_depends(frontier).values()) - seen - set(without)
        seen |= new
        frontier = sorted(new)
    return seen


def uncovered(used, packages, without=()):
    """[(file, owners)] of the used files whose packages the list does not bring."""
    covered = closure(packages, without)
    return sorted((f, sorted(o)) for f, o in used.items() if o and not (o & covered))


# ---- the test --------------------------------------------------------------------------------------

def _is_system(path):
    return (path.startswith(("/usr/", "/lib/", "/bin/", "/sbin/", "/lib64/"))
            and not path.startswith("/usr/local/"))


@pytest.fixture(scope="module")
def used(tmp_path_factory):
    for build in BUILD_DIRS:
        assert os.path.exists(os.path.join(build, "CMakeCache.txt")), "build tree %s is not built" % build
    files = program_files() + python_files(str(tmp_path_factory.mktemp("probe"))) + RUNTIME_DATA
    for build in BUILD_DIRS:
        files += build_files(build)
    files = {os.path.normpath(f) for f in files}
    files |= {os.path.realpath(f) for f in files}
    return owners(sorted(f for f in files if _is_system(f) and os.path.exists(f)))


def test_every_used_file_comes_from_the_setup_list(used):
    packages = read_package_list()
    missing = uncovered(used, packages)
    assert not missing, "files used by the build or the tests whose packages scripts/packages.txt misses:\n" + \
        "\n".join("  %s  (%s)" % (f, ", ".join(o)) for f, o in missing[:40])
    owned = sum(1 for o in used.values() if o)
    assert owned > 1000  # the collection itself worked: headers, libraries, CMake files, modules


def test_every_listed_package_is_needed(used):
    # The self-check: with any one package of the list absent (taken out of the list and out of the
    # dependencies of the others), the check fails, naming a file of it. So the check can fail, and
    # the list holds nothing the build and the tests do not use.
    packages = read_package_list()
    unneeded = [p for p in packages if not uncovered(used, [q for q in packages if q != p], without=[p])]
    assert not unneeded, "the check passes without these packages (remove them, or a file they bring " \
                         "is not collected): %s" % unneeded
    missing_tbb = uncovered(used, [q for q in packages if q != "libtbb-dev"], without=["libtbb-dev"])
    assert any(f.endswith("/libtbb.so") for f, _ in missing_tbb)  # the fresh-machine failure, caught
