#pragma once
// A drilling tube of the plan: where the sleeve goes and its sizes, and the one set of rules its
// numbers must keep (the case reader, the plan readers, the sleeve and guide builders all apply it).

#include "st/core/mesh.h"

#include <optional>
#include <string>

namespace st {

struct TubeSpec {
  std::string name;
  Vec3 entry = Vec3::Zero();
  Vec3 direction = Vec3::UnitZ(); ///< unit, pointing into the bone
  double inner_radius = 0.0;
  double outer_radius = 0.0;
  double length = 0.0;
  double offset = 0.0;
  double depth = 0.0; ///< planned drilling depth into the bone beyond the entry; 0: not planned
};

/// A rule of a tube's numbers that is broken: the key relative to the tube ("outer_radius") and why
/// ("must be > inner_radius").
struct TubeProblem {
  std::string key;
  std::string reason;
};

/// The first rule the sizes of `t` break (0 < inner_radius < outer_radius, length > 0, offset >= 0,
/// depth >= 0, all finite and under the limits of st/core/tolerances.h), or nothing.
std::optional<TubeProblem> tube_size_problem(const TubeSpec& t);

/// Checks all of a tube's numbers: entry finite, direction finite and non-zero, then the sizes.
/// Throws InvalidInput "tube '<name>': <key> <reason>".
void check_tube(const TubeSpec& t);

} // namespace st
