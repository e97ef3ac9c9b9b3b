"""The workbench's GUI commands: files (case, bone, plan, STL, drawing) and design (boundary, template,
tubes, guide, validation); toolbar registers them in their order."""
