#pragma once
// A drilling tube of the plan: where the sleeve goes and its sizes, and the one set of rules its
// numbers must keep (the case reader, the plan readers, the sleeve and guide builders all apply it).

#include "st/core/mesh.h"

#include <optional>
#include <string>

namespace st {

/// What a tube guides: a drill (a sleeve, the default) or a fixation pin (a K-wire or a screw).
enum class TubeKind { sleeve, pin };

/// A wider hole for a screw's head, from the sleeve's top down `depth`.
struct Counterbore {
  double radius = 0.0;
  double depth = 0.0;
};

struct TubeSpec {
  std::string name;
  TubeKind kind = TubeKind::sleeve;
  std::optional<Counterbore> counterbore;
  /// No direction was planned (a pin): design_template sets `direction` into the bone from the entry
  /// (pin_direction) before anything is built.
  bool auto_direction = false;
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
/// depth >= 0, a counterbore wider than the bore and 0 < its depth, all finite and under the limits
/// of st/core/tolerances.h), or nothing.
std::optional<TubeProblem> tube_size_problem(const TubeSpec& t);

/// Checks all of a tube's numbers: entry finite, direction finite and non-zero (unless
/// auto_direction), then the sizes. Throws InvalidInput "tube '<name>': <key> <reason>".
void check_tube(const TubeSpec& t);

/// "sleeve" or "pin"; the kind named so, or nothing.
const char* tube_kind_name(TubeKind kind);
std::optional<TubeKind> tube_kind_named(const std::string& name);

} // namespace st
