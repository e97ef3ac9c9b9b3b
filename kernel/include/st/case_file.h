#pragma once
// Case files: the preoperative plan of one template as JSON, format "surgical-template-case/1"
// (the contract is docs/CASE-FORMAT.md). All lengths in mm; paths relative to the case file.

#include "st/mesh.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace st {

struct TubeSpec {
  std::string name;
  Vec3 entry = Vec3::Zero();
  Vec3 direction = Vec3::UnitZ(); ///< unit, pointing into the bone
  double inner_radius = 0.0;
  double outer_radius = 0.0;
  double length = 0.0;
  double offset = 0.0;
  double depth = 0.0;  ///< planned drilling depth into the bone beyond the entry; 0: not planned
};

/// The first rule of the case format that the sizes of `t` break, as (key, reason) with the key
/// relative to the tube ("outer_radius"), or nothing when they are fine.
std::optional<std::pair<std::string, std::string>> tube_size_problem(const TubeSpec& t);

struct CaseFile {
  std::string path;                   ///< the case file itself
  std::string name;
  std::string bone;                   ///< bone mesh path, resolved against the case folder
  std::vector<Vec3> boundary_points;
  std::optional<Vec3> inside;
  double thickness = 0.0;
  double clearance = 0.0;
  std::optional<double> resolution;
  std::optional<int> sampling_step;
  std::vector<TubeSpec> tubes;
  std::optional<std::string> output;  ///< resolved against the case folder
  std::vector<std::string> warnings;  ///< unknown keys and the like
};

inline constexpr const char* kCaseFormat = "surgical-template-case/1";

/// Reads and checks a case file. Throws InvalidInput naming the file and the key for every rule of
/// the format that is broken (missing required key, wrong type, value out of range).
CaseFile read_case(const std::string& path);

/// Parses case JSON text; `path` is used for messages and to resolve relative paths.
CaseFile parse_case(const std::string& text, const std::string& path);

} // namespace st
