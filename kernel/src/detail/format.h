#pragma once
// Message formatting shared by the kernel's sources.

#include "st/mesh.h"

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

/// "1.25 mm": a length for messages.
inline std::string mm(double value) {
  std::ostringstream s;
  s.precision(2);
  s << std::fixed << value << " mm";
  return s.str();
}

} // namespace st::detail
