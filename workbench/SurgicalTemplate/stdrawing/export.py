"""PDF and SVG of the drawing's page, written whole or not at all (write_page).

Whole-page export needs FreeCAD's GUI. Without it (freecadcmd, or Python with FreeCAD), the document
is saved to a temporary file and opened by FreeCAD's GUI in a subprocess under Xvfb, which exports the
page (gui_session runs there). GUI modules are imported only where the GUI runs.
"""
import json
import os
import shutil
import signal
import subprocess
import tempfile
import traceback

import FreeCAD as App

import SurgicalTemplate_paths

EXPORT_TIMEOUT = 180  # s, the GUI subprocess


def _style(page):
    """Line widths and text sizes of the page's view providers (GUI only). FreeCAD 0.20.2 as Debian
    builds it draws every edge of a DrawViewPart as a hairline whatever its LineWidth (its line scale
    factor is 0), so the dimensions are thin too, for an even drawing."""
    for v in page.Views:
        vo = getattr(v, "ViewObject", None)
        if vo is None:
            continue
        settings = {}
        if v.isDerivedFrom("TechDraw::DrawViewDimension"):
            settings = {"Fontsize": 3.0, "Arrowsize": 2.5, "LineWidth": 0.13}
            # Short dimensions: arrows outside, pointing in, so that the text stands clear.
            view = v.References2D[0][0] if v.References2D else None
            if view is not None and v.getRawValue() * view.Scale < 5.0 * settings["Fontsize"]:
                settings["FlipArrowheads"] = True
        elif v.isDerivedFrom("TechDraw::DrawViewBalloon"):
            settings = {"Fontsize": 3.5, "LineWidth": 0.18}
        elif v.isDerivedFrom("TechDraw::DrawViewPart"):
            settings = {"LineWidth": 0.35, "HiddenWidth": 0.18, "ExtraWidth": 0.18}
        for key, value in settings.items():
            if key in vo.PropertiesList:
                setattr(vo, key, value)


_GENERAL = "User parameter:BaseApp/Preferences/Mod/TechDraw/General"


def _export_here(page, pdf, svg):
    """Exports the page with FreeCAD's GUI in this process."""
    import FreeCADGui as Gui
    import TechDrawGui

    # TechDraw 0.20 draws hidden lines solid unless a preference says dashed, and reads it when it
    # draws: set it for this export only.
    prefs = App.ParamGet(_GENERAL)
    had = "HiddenLine" in prefs.GetInts()
    old = prefs.GetInt("HiddenLine", 0)
    prefs.SetInt("HiddenLine", 1)
    try:
        page.ViewObject.show()
        Gui.updateGui()
        _style(page)
        for v in page.Views:
            v.touch()
        page.Document.recompute()
        Gui.updateGui()
        if pdf:
            TechDrawGui.exportPageAsPdf(page, pdf)
        if svg:
            TechDrawGui.exportPageAsSvg(page, svg)
    finally:
        if had:
            prefs.SetInt("HiddenLine", old)
        else:
            prefs.RemInt("HiddenLine")


_SESSION = """# Exports one TechDraw page with FreeCAD's GUI: written by stdrawing/export.py, run under Xvfb.
import sys
sys.path.insert(0, {here!r})
from stdrawing import export
export.gui_session()
"""


def gui_session():
    """Runs inside FreeCAD's GUI (see _export_subprocess): opens the document (its objects restore from
    outside a Mod folder too: the session script puts the workbench on sys.path), exports the page,
    writes a status file, quits. Arguments come in environment variables."""
    import FreeCADGui as Gui
    from PySide import QtCore

    env = os.environ

    def work():
        status = {"ok": False}
        try:
            doc = App.openDocument(env["ST_DRAWING_DOC"])
            page = doc.getObject(env["ST_DRAWING_PAGE"])
            if page is None:
                raise RuntimeError(f"no page {env['ST_DRAWING_PAGE']} in {env['ST_DRAWING_DOC']}")
            _export_here(page, env.get("ST_DRAWING_PDF"), env.get("ST_DRAWING_SVG"))
            status["ok"] = True
        except Exception:
            status["error"] = traceback.format_exc()
        finally:
            with open(env["ST_DRAWING_STATUS"], "w") as f:
                json.dump(status, f)
            for name in list(App.listDocuments()):
                App.closeDocument(name)
            QtCore.QTimer.singleShot(0, Gui.getMainWindow().close)

    QtCore.QTimer.singleShot(200, work)


def _export_subprocess(doc, page, pdf, svg):
    """Exports the page from a saved copy of the document with FreeCAD's GUI under Xvfb."""
    freecad, xvfb = shutil.which("freecad"), shutil.which("xvfb-run")
    if not freecad or not xvfb:
        missing = " and ".join(n for n, p in (("freecad", freecad), ("xvfb-run", xvfb)) if not p)
        raise RuntimeError(f"{page.Label}: exporting PDF/SVG without FreeCAD's GUI needs {missing} on the PATH "
                           "(Debian packages freecad and xvfb)")
    with tempfile.TemporaryDirectory(prefix="surgical-template-drawing-") as tmp:
        fcstd = os.path.join(tmp, "drawing.FCStd")
        doc.saveCopy(fcstd)
        script = os.path.join(tmp, "export_page.py")
        with open(script, "w") as f:
            f.write(_SESSION.format(here=SurgicalTemplate_paths.HERE))
        status_path = os.path.join(tmp, "status.json")
        os.makedirs(os.path.join(tmp, "tmp"))
        env = dict(os.environ, QTWEBENGINE_DISABLE_SANDBOX="1", ST_DRAWING_DOC=fcstd, ST_DRAWING_PAGE=page.Name,
                   ST_DRAWING_PDF=pdf or "", ST_DRAWING_SVG=svg or "", ST_DRAWING_STATUS=status_path,
                   TMPDIR=os.path.join(tmp, "tmp"))   # FreeCAD's recovery files: never a dialog from old ones
        proc = subprocess.Popen([xvfb, "-a", "-s", "-screen 0 1280x1024x24", freecad, script], env=env,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
        try:
            output, _ = proc.communicate(timeout=EXPORT_TIMEOUT)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            output, _ = proc.communicate()
            raise RuntimeError(f"{page.Label}: FreeCAD's GUI did not export the page within {EXPORT_TIMEOUT} s:\n"
                               f"{output[-2000:]}") from None
        status = {}
        if os.path.exists(status_path):
            with open(status_path) as f:
                status = json.load(f)
        if not status.get("ok"):
            detail = status.get("error") or output[-2000:]
            raise RuntimeError(f"{page.Label}: export with FreeCAD's GUI failed (exit {proc.returncode}):\n{detail}")


_FONTS_CONF = """<?xml version="1.0"?>
<!DOCTYPE fontconfig SYSTEM "fonts.dtd">
<fontconfig>
  <include ignore_missing="yes">/etc/fonts/fonts.conf</include>
  <dir>{fonts}</dir>
</fontconfig>
"""


def _pdf_from_svg(svg, pdf, label):
    """The PDF of the page's SVG by librsvg (cairo): text stays text (the title block and the tables can be
    searched and copied), with TechDraw's osifont found where FreeCAD keeps it. Qt's PDF export writes the
    template's text as outlines and empty sub-paths that poppler reports."""
    rsvg = shutil.which("rsvg-convert")
    with tempfile.TemporaryDirectory(prefix="surgical-template-pdf-") as tmp:
        conf = os.path.join(tmp, "fonts.conf")
        with open(conf, "w") as f:
            f.write(_FONTS_CONF.format(fonts=os.path.join(App.getResourceDir(), "Mod", "TechDraw", "Resources",
                                                           "fonts")))
        env = dict(os.environ, FONTCONFIG_FILE=conf, XDG_CACHE_HOME=tmp)
        p = subprocess.run([rsvg, "--format=pdf", "--output", pdf, svg], env=env, capture_output=True, text=True,
                           timeout=EXPORT_TIMEOUT)
    if p.returncode != 0:
        raise RuntimeError(f"{label}: rsvg-convert could not make the PDF (exit {p.returncode}): {p.stderr[-2000:]}")


def write_page(page, targets):
    """Exports the page to `targets` ({"pdf": path, "svg": path}, either optional): each file written
    to a temporary name next to it and renamed once every export worked. The PDF is made from the SVG
    by rsvg-convert (Debian package librsvg2-bin); without it, by TechDraw's own PDF export, with a
    warning. Returns the paths written."""
    written = {}
    if not targets:
        return written
    folder = os.path.dirname(next(iter(targets.values())))
    via_svg = "pdf" in targets and shutil.which("rsvg-convert") is not None
    if "pdf" in targets and not via_svg:
        App.Console.PrintWarning(f"{page.Label}: rsvg-convert not found (Debian package librsvg2-bin): the PDF "
                                 "comes from TechDraw's export, whose title block text cannot be searched\n")
    kinds = list(targets) + (["svg"] if via_svg and "svg" not in targets else [])
    temps = {k: tempfile.mkstemp(dir=folder, prefix=".drawing-", suffix="." + k) for k in kinds}
    for fd, _ in temps.values():
        os.close(fd)
    try:
        tmp = {k: p for k, (_, p) in temps.items()}
        gui_pdf = None if via_svg else tmp.get("pdf")
        if App.GuiUp:
            _export_here(page, gui_pdf, tmp.get("svg"))
        else:
            _export_subprocess(page.Document, page, gui_pdf, tmp.get("svg"))
        if via_svg:
            _pdf_from_svg(tmp["svg"], tmp["pdf"], page.Label)
        for k, p in tmp.items():
            if os.path.getsize(p) == 0:
                raise RuntimeError(f"{page.Label}: the {k.upper()} export wrote nothing")
        mode = 0o666 & ~_umask()
        for k in targets:
            os.chmod(tmp[k], mode)
            os.replace(tmp[k], targets[k])
            written[k] = targets[k]
    finally:
        for _, p in temps.values():
            if os.path.exists(p):
                os.remove(p)
    return written


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text(path, text):
    """A text file written whole or not at all."""
    tmp = f"{path}.tmp-{os.getpid()}"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)
