#include "st/guide/tube.h"

#include "detail/format.h"
#include "st/core/errors.h"
#include "st/core/tolerances.h"

namespace st {

std::optional<TubeProblem> tube_size_problem(const TubeSpec& t) {
  // The comparisons are written so that NaN fails each of them.
  if (!(t.inner_radius > 0.0)) return TubeProblem{"inner_radius", "must be > 0"};
  if (!(t.outer_radius > t.inner_radius)) return TubeProblem{"outer_radius", "must be > inner_radius"};
  if (!(t.length > 0.0)) return TubeProblem{"length", "must be > 0"};
  if (!(t.offset >= 0.0)) return TubeProblem{"offset", "must be >= 0"};
  if (!(t.depth >= 0.0)) return TubeProblem{"depth", "must be >= 0"};
  const auto under = [](double limit) { return "is absurd (must be under " + detail::mm(limit) + ")"; };
  if (t.outer_radius >= tol::kMaxTubeRadius_mm) return TubeProblem{"outer_radius", under(tol::kMaxTubeRadius_mm)};
  if (t.length >= tol::kMaxTubeLength_mm) return TubeProblem{"length", under(tol::kMaxTubeLength_mm)};
  if (t.offset >= tol::kMaxTubeLength_mm) return TubeProblem{"offset", under(tol::kMaxTubeLength_mm)};
  if (t.depth >= tol::kMaxTubeLength_mm) return TubeProblem{"depth", under(tol::kMaxTubeLength_mm)};
  if (t.counterbore) {
    if (!(t.counterbore->radius > t.inner_radius)) return TubeProblem{"counterbore.radius", "must be > inner_radius"};
    if (!(t.counterbore->depth > 0.0)) return TubeProblem{"counterbore.depth", "must be > 0"};
    if (t.counterbore->radius >= tol::kMaxTubeRadius_mm)
      return TubeProblem{"counterbore.radius", under(tol::kMaxTubeRadius_mm)};
    if (t.counterbore->depth >= tol::kMaxTubeLength_mm)
      return TubeProblem{"counterbore.depth", under(tol::kMaxTubeLength_mm)};
  }
  return std::nullopt;
}

void check_tube(const TubeSpec& t) {
  std::optional<TubeProblem> problem;
  if (!t.entry.allFinite()) problem = TubeProblem{"entry", "must be finite"};
  else if (!t.auto_direction && (!t.direction.allFinite() || !(t.direction.norm() > 1e-12)))
    problem = TubeProblem{"direction", "must be a finite, non-zero vector"};
  else problem = tube_size_problem(t);
  if (problem) throw InvalidInput("tube '" + t.name + "': " + problem->key + " " + problem->reason);
}

const char* tube_kind_name(TubeKind kind) { return kind == TubeKind::pin ? "pin" : "sleeve"; }

std::optional<TubeKind> tube_kind_named(const std::string& name) {
  if (name == "sleeve") return TubeKind::sleeve;
  if (name == "pin") return TubeKind::pin;
  return std::nullopt;
}

} // namespace st
