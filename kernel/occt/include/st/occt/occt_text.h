#pragma once
// The outlines of a label's text from a real font, through OpenCASCADE's font support (FreeType
// underneath): the kernel lays them on the guide (st/guide/label.h).

#include "st/guide/label.h"

#include <string>
#include <vector>

namespace st {

/// The font labels are written in: DejaVu Sans (Debian's fonts-dejavu-core), found through
/// OpenCASCADE's font manager, else at its Debian path.
inline constexpr const char* kLabelFont = "DejaVu Sans";

/// The filled outlines of `text` (UTF-8, one line) with cap height `height` mm (a capital H that tall): one polygon per
/// region of ink (its holes inside it), in the text's plane with x along the text and y up, centred on the middle of
/// the ink's box. Each contour is a polygon within `deflection` mm of the font's curves, none of its edges shorter than
/// 0.15 mm. Throws InvalidInput for text that is empty, not UTF-8 or has nothing to draw, or a height or deflection
/// that is not finite and > 0; GeometryError when the font cannot be found or read.
std::vector<LabelPolygon> text_outlines(const std::string& text, double height, double deflection = 0.01);

/// Fills each label's outlines from its text and height (text_outlines).
void fill_label_outlines(std::vector<LabelSpec>& labels);

} // namespace st
