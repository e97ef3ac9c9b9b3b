#pragma once
// Message formatting shared by the kernel's sources.

#include "st/core/mesh.h"

#include <cstdio>
#include <sstream>
#include <string>

namespace st::detail {

/// "(x, y, z)" with two decimals (mm), for messages that say where something is.
inline std::string where(const Vec3& p) {
  std::ostringstream s;
  s.precision(2);
  s << std::fixed << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

/// A number as a person writes it: at most six significant digits, no trailing zeros, an exponent
/// only for very large or small values ("2", "0.25", "1e+09", "nan").
inline std::string number(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", value);
  return buf;
}

/// "1.25 mm": a length for messages.
inline std::string mm(double value) { return number(value) + " mm"; }

} // namespace st::detail
