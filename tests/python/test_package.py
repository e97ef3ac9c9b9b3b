"""The Addon Manager's view of the repository: package.xml at the root (format 1) names what it holds, and
every file it points at exists; the installed copy (workbench/SurgicalTemplate/package.xml) agrees on
name, version and class."""
import os
import xml.etree.ElementTree as ET

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
NS = {"p": "https://wiki.freecad.org/Package_Metadata"}


def read(path):
    root = ET.parse(path).getroot()
    assert root.tag == "{%s}package" % NS["p"] and root.get("format") == "1"
    return root


def text(node, tag):
    found = node.find("p:" + tag, NS)
    return found.text.strip() if found is not None and found.text else None


def test_root_package_names_the_workbench_and_its_files():
    pkg = read(os.path.join(ROOT, "package.xml"))
    for tag in ("name", "description", "version", "date", "maintainer", "license", "icon"):
        assert text(pkg, tag), tag
    assert os.path.exists(os.path.join(ROOT, pkg.find("p:license", NS).get("file")))
    assert os.path.exists(os.path.join(ROOT, text(pkg, "icon")))
    assert {u.get("type") for u in pkg.findall("p:url", NS)} >= {"repository", "readme"}
    assert len(pkg.findall("p:tag", NS)) >= 2
    depends = {d.text for d in pkg.findall("p:depend", NS)}
    assert {"Mesh", "Part", "TechDraw"} <= depends
    wb = pkg.find("p:content/p:workbench", NS)
    folder = os.path.join(ROOT, text(wb, "subdirectory"))
    assert os.path.exists(os.path.join(folder, "InitGui.py")) and os.path.exists(os.path.join(folder, "Init.py"))
    assert "class %s(" % text(wb, "classname") in open(os.path.join(folder, "InitGui.py")).read()
    assert os.path.exists(os.path.normpath(os.path.join(folder, text(wb, "icon"))))


def test_the_installed_package_agrees_with_the_root():
    root = read(os.path.join(ROOT, "package.xml"))
    installed = read(os.path.join(ROOT, "workbench", "SurgicalTemplate", "package.xml"))
    for tag in ("name", "version"):
        assert text(installed, tag) == text(root, tag), tag
    assert text(installed.find("p:content/p:workbench", NS), "classname") == \
        text(root.find("p:content/p:workbench", NS), "classname")
