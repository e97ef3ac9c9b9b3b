"""The documentation drawing of a surgical guide, by part: the drill protocol (protocol), line drawings
of the guide mesh (lines), the TechDraw page (page) and its PDF/SVG export (export). stmake.drawing
puts them together as make_drawing."""
