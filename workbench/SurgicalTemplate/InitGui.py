# Surgical Template workbench: registered at FreeCAD's start; commands load when it is activated.
import os

import FreeCAD as App
import FreeCADGui as Gui


class SurgicalTemplateWorkbench(Gui.Workbench):
    MenuText = App.Qt.QT_TRANSLATE_NOOP("Workbench", "Surgical Template")
    ToolTip = App.Qt.QT_TRANSLATE_NOOP("Workbench", "Patient-specific surgical guides on bone scans: boundary, "
                                                     "template, drilling sleeves, saw slots, labels")

    def __init__(self):
        import SurgicalTemplate_paths  # noqa: F401  (the folder of this file, for the icon below)
        self.__class__.Icon = os.path.join(SurgicalTemplate_paths.ICONS, "SurgicalTemplate_Workbench.svg")

    def Initialize(self):
        from stcommands import toolbar

        toolbars, menu = toolbar.register()
        for title, names in toolbars:
            self.appendToolbar(title, names)
        self.appendMenu("Surgical Template", menu)

    def ContextMenu(self, recipient):
        from stcommands import toolbar

        names = toolbar.context_menu(Gui.Selection.getSelection())
        if names:
            self.appendContextMenu("", ["Separator"] + names)

    def GetClassName(self):
        return "Gui::PythonWorkbench"


Gui.addWorkbench(SurgicalTemplateWorkbench())


def _add_preferences():
    import SurgicalTemplate_paths

    # The group's icon in Edit > Preferences: FreeCAD looks for preferences-<group, lower case, "_" for
    # spaces>.svg in its icon paths.
    Gui.addIconPath(SurgicalTemplate_paths.ICONS)
    # Translations (SurgicalTemplate_<language>.qm, see Resources/translations/README.md).
    Gui.addLanguagePath(SurgicalTemplate_paths.TRANSLATIONS)
    Gui.updateLocale()
    Gui.addPreferencePage(os.path.join(SurgicalTemplate_paths.UI, "preferences.ui"), "Surgical Template")


_add_preferences()


def _restore_views_of_opened_documents():
    """Documents made without the GUI open with the workbench's view providers (stviewproviders)."""
    import SurgicalTemplate_paths  # noqa: F401  (puts this folder's packages on the path)
    from stobjects.base import RESTORE_HOOKS
    from stviewproviders.view_feature import restore_view

    RESTORE_HOOKS.append(restore_view)


_restore_views_of_opened_documents()
