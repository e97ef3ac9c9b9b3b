#pragma once
// Case files: the preoperative plan of one template as JSON, format "surgical-template-case/1"
// (the contract is docs/CASE-FORMAT.md). All lengths in mm; paths relative to the case file.

#include "st/core/mesh.h"
#include "st/design/template_design.h"
#include "st/guide/label.h"
#include "st/guide/slot.h"
#include "st/guide/tube.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace st {

struct CaseFile {
  std::string path; ///< the case file itself
  std::string name;
  std::string bone; ///< bone mesh path, resolved against the case folder
  std::vector<Vec3> boundary_points;
  std::optional<Vec3> inside;
  double thickness = 0.0;
  double clearance = 0.0;
  std::optional<double> resolution;
  std::optional<int> sampling_step;
  std::optional<Vec3> insertion; ///< template.insertion as a unit vector; none for "auto" or absent
  bool insertion_auto = false;   ///< template.insertion is "auto"
  std::vector<TubeSpec> tubes;
  std::vector<SlotSpec> slots;
  std::vector<LabelSpec> labels;     ///< without outlines (st/occt/occt_text.h fills them)
  std::optional<std::string> output; ///< resolved against the case folder
  std::vector<std::string> warnings; ///< unknown keys and the like
};

inline constexpr const char* kCaseFormat = "surgical-template-case/1";

/// Reads and checks a case file. Throws InvalidInput naming the file and the key for every rule of
/// the format that is broken (missing required key, wrong type, value out of range).
CaseFile read_case(const std::string& path);

/// The options a case file asks for: boundary, inside, thickness, clearance, resolution, sampling step
/// tubes, slots and labels (the rest at their defaults; the labels without their outlines).
TemplateOptions template_options(const CaseFile& c);

/// The case as the JSON text of a case file at `path`: the bone relative to that file's folder,
/// optional keys only when set. parse_case(case_json(c, p), p) gives `c` back.
std::string case_json(const CaseFile& c, const std::string& path);

/// Writes the case file at `path` (atomically: a temporary file renamed), after checking what it
/// writes with parse_case (InvalidInput naming the key, nothing written).
void write_case(const CaseFile& c, const std::string& path);

/// Parses case JSON text; `path` is used for messages and to resolve relative paths.
CaseFile parse_case(const std::string& text, const std::string& path);

} // namespace st
