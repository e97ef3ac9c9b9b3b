#pragma once
// Labels of a guide: text engraved into (or embossed onto) the template's outer surface, so that the
// guide can be told apart in the operating room (case, side, version). The one definition shared by
// the case reader, the guide builder (guide.h), the report and the workbench.
//
// The kernel does not read fonts: a label carries its text's outlines (polygons with holes in the
// label's plane), which st/occt/occt_text.h makes from a real font through OpenCASCADE (FreeType).
// The guide builder lays them on the surface: the label's frame is (right, up, n), n the template's
// outward normal around the label's point, up the planned up direction in the tangent plane and
// right = up x n (the text reads left to right seen from outside). Every vertex of the text, on a
// triangulation no coarser than kLabelSpacing_mm, is carried down n onto the outer surface by a ray;
// an engraving is cut `depth` below it (so the depth holds everywhere, along n, on a curved surface),
// an embossing stands `depth` above it.

#include "st/core/mesh.h"
#include "st/core/polygon_fill.h"
#include "st/guide/tube.h"

#include <optional>
#include <string>
#include <vector>

namespace st {

enum class LabelMode { engrave, emboss };

/// "engrave" or "emboss".
const char* label_mode_name(LabelMode mode);
/// The mode of that name; nothing for another text.
std::optional<LabelMode> label_mode_named(const std::string& name);

/// One filled region of a text's outline in the label's plane (mm, x to the right, y up): loops[0]
/// its boundary (counter-clockwise), the others its holes (clockwise, inside it).
struct LabelPolygon {
  std::vector<std::vector<Point2>> loops;
};

/// Least depth of an engraving (or height of an embossing), mm: legible after printing.
inline constexpr double kMinLabelDepth_mm = 0.5;
/// How close a label may come to a tube's sleeve or bore, or to a slot's housing, mm.
inline constexpr double kLabelClearance_mm = 1.0;
/// Longest edge of the triangulation a label is laid on the surface with, mm.
inline constexpr double kLabelSpacing_mm = 0.8;
/// Most characters in a label.
inline constexpr std::size_t kMaxLabelLength = 64;

struct LabelSpec {
  std::string name;
  std::string text;        ///< UTF-8, one line
  Vec3 at = Vec3::Zero();  ///< on or near the outer surface (or the bone under it): the text's centre
  Vec3 up = Vec3::UnitZ(); ///< the text's up direction (its part in the tangent plane is used)
  double height = 4.0;     ///< the text's cap height (of a capital H), mm
  double depth = 0.6;      ///< engraving depth or embossing height along the normal, mm
  LabelMode mode = LabelMode::engrave;
  std::vector<LabelPolygon> outlines; ///< the text's outlines, centred on the origin (occt_text.h)
};

/// The first rule a label's numbers break (see check_label), as the key relative to the label and why.
std::optional<TubeProblem> label_problem(const LabelSpec& label);

/// Checks a label: text of 1 to kMaxLabelLength characters (UTF-8), at finite, up finite and
/// non-zero, height in [1, 50) mm, depth in [kMinLabelDepth_mm, 5) mm. Throws InvalidInput
/// "label '<name>': <key> <reason>".
void check_label(const LabelSpec& label);

/// Number of characters (code points) in UTF-8 text; nothing when it is not valid UTF-8.
std::optional<std::size_t> utf8_length(const std::string& text);

} // namespace st
