"""Running scripts in FreeCAD for the tests: the workbench installed in a private user folder (as
`make install` does), a script run headless (/usr/bin/python3 with FreeCAD) or in the GUI under Xvfb,
and its result read back."""
import json
import os
import shutil
import subprocess

import pytest

FREECAD_LIB = "/usr/lib/freecad-python3/lib"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HERE = os.path.join(ROOT, "tests", "freecad")


def install_workbench(user_data):
    """The workbench and the kernel module in a private FreeCAD user folder, as `make install` does."""
    target = os.path.join(user_data, "Mod", "SurgicalTemplate")
    shutil.copytree(os.path.join(ROOT, "workbench", "SurgicalTemplate"), target)  # .py, .ui, package.xml
    shutil.copytree(os.path.join(ROOT, "icons"), os.path.join(target, "icons"), dirs_exist_ok=True)
    shutil.copytree(os.path.join(ROOT, "examples"), os.path.join(target, "examples"),
                    ignore=shutil.ignore_patterns("__pycache__"))
    python_dir = os.environ.get("ST_PYTHON_DIR", os.path.join(os.getcwd(), "python"))
    for f in os.listdir(python_dir):
        if f.startswith("stkernel") and f.endswith(".so"):
            shutil.copy(os.path.join(python_dir, f), target)
    return target


def _environment(tmp_path_factory, out, extra):
    home = tmp_path_factory.mktemp("fc")
    install_workbench(str(home))
    return dict(os.environ, FREECAD_USER_HOME=str(home), FREECAD_USER_DATA=str(home), ST_OUT=str(out),
                QTWEBENGINE_DISABLE_SANDBOX="1", ST_EXAMPLES_DIR=os.path.join(ROOT, "examples"), **extra)


def run_headless(tmp_path_factory, script, timeout=900, **extra):
    """Runs tests/freecad/<script> with /usr/bin/python3 and FreeCAD; returns its "RESULT {...}" line's JSON."""
    if not os.path.exists(FREECAD_LIB):
        pytest.skip("FreeCAD is not installed")
    out = tmp_path_factory.mktemp("out")
    env = _environment(tmp_path_factory, out, extra)
    p = subprocess.run(["/usr/bin/python3", os.path.join(HERE, script)], capture_output=True, text=True, env=env,
                       timeout=timeout)
    line = [l for l in p.stdout.splitlines() if l.startswith("RESULT ")]
    assert p.returncode == 0 and line, p.stdout[-3000:] + p.stderr[-3000:]
    return json.loads(line[0][len("RESULT "):])


def run_gui(tmp_path_factory, script, result_name, timeout=600, **extra):
    """Runs tests/freecad/<script> in FreeCAD's window under Xvfb; it writes $ST_OUT/<result_name>, which
    is returned (screenshots stay in the build's test-output/gui folder for CI to keep)."""
    if not shutil.which("freecad") or not shutil.which("xvfb-run"):
        pytest.skip("FreeCAD GUI or Xvfb missing")
    out = os.path.join(os.environ.get("ST_TEST_OUTPUT_DIR", str(tmp_path_factory.mktemp("out"))), "gui")
    os.makedirs(out, exist_ok=True)
    env = _environment(tmp_path_factory, out, extra)
    path = os.path.join(out, result_name)
    if os.path.exists(path):
        os.remove(path)  # a result left by an earlier run must not stand in for this one
    p = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "freecad", os.path.join(HERE, script)],
                       capture_output=True, text=True, env=env, timeout=timeout)
    assert os.path.exists(path), p.stdout[-3000:] + p.stderr[-3000:]
    result = json.load(open(path))
    assert not result["errors"], result["errors"]
    return result
