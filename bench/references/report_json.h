#pragma once
// Report helpers shared by the benchmark's reference programs: medians and the solid check as JSON.

#include "st/validate/validate.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <vector>

namespace st::bench {

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

inline nlohmann::json solid_json(const st::SolidReport& s) {
  return {{"valid", s.valid()},
          {"closed", s.closed()},
          {"manifold", s.manifold()},
          {"oriented", s.oriented()},
          {"self_intersection_free", s.self_intersections == 0},
          {"vertices", s.vertices},
          {"triangles", s.triangles},
          {"border_edges", s.border_edges},
          {"nonmanifold_edges", s.nonmanifold_edges},
          {"nonmanifold_vertices", s.nonmanifold_vertices},
          {"misoriented_edges", s.misoriented_edges},
          {"degenerate_triangles", s.degenerate_triangles},
          {"self_intersections", s.self_intersections},
          {"components", s.components},
          {"volume", s.volume},
          {"summary", s.summary()}};
}

} // namespace st::bench
