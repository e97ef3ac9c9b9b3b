// libFuzzer target: the case-file parser on arbitrary text. InvalidInput is the only allowed way to
// refuse a case; a parsed case must keep every rule of docs/CASE-FORMAT.md (checked here again), and
// its tubes must pass check_tube.

#include "st/io/case_file.h"
#include "st/core/errors.h"
#include "st/guide/sleeve.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const st::CaseFile c = st::parse_case(text, "/fuzz/case.json");
    bool ok = c.boundary_points.size() >= 3 && std::isfinite(c.thickness) && c.thickness > 0.0 &&
              std::isfinite(c.clearance) && c.clearance >= 0.0 && !c.bone.empty();
    for (const st::Vec3& p : c.boundary_points) ok = ok && p.allFinite();
    if (c.inside) ok = ok && c.inside->allFinite();
    if (c.resolution) ok = ok && std::isfinite(*c.resolution) && *c.resolution > 0.0;
    if (!ok) std::abort();
    for (const st::TubeSpec& t : c.tubes) st::check_tube(t); // throws InvalidInput: a parser bug
  } catch (const st::InvalidInput& e) {
    if (std::string(e.what()).rfind("tube '", 0) == 0) std::abort(); // check_tube refused what the parser let in
  }
  return 0;
}
