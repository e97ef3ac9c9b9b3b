// libFuzzer target: the plan readers (3D Slicer markups JSON, CSV of axes or planes) and the sleeve catalogue
// on arbitrary text. The first byte picks the reader and the bone's frame. InvalidInput is the only
// allowed way to refuse; what is read must be finite, axes and normals unit, catalogue sleeves valid.

#include "st/core/errors.h"
#include "st/io/plan.h"
#include "st/guide/sleeve.h"
#include "st/guide/slot.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  const st::Space space = (data[0] & 4) ? st::Space::RAS : st::Space::LPS;
  try {
    if ((data[0] & 3) == 2) {
      for (const st::SleevePreset& p : st::parse_sleeve_presets(text, "/fuzz/sleeves.json"))
        if (!(p.inner_radius > 0 && p.outer_radius > p.inner_radius && p.length > 0 && p.offset >= 0)) std::abort();
      return 0;
    }
    const st::Plan plan = (data[0] & 3) == 0 ? st::parse_markups(text, "/fuzz/plan.mrk.json", space)
                                             : st::parse_plan_csv(text, "/fuzz/plan.csv", space);
    for (const st::Vec3& p : plan.boundary_points)
      if (!p.allFinite()) std::abort();
    if (plan.inside && !plan.inside->allFinite()) std::abort();
    st::SlotSizes sizes;
    sizes.blade = st::default_blade_presets().front();
    sizes.length = 10.0;
    for (const st::PlanPlane& p : plan.planes) {
      if (!p.origin.allFinite() || std::abs(p.normal.norm() - 1.0) > 1e-9) std::abort();
      if (p.direction && std::abs(p.direction->norm() - 1.0) > 1e-9) std::abort();
      try {
        st::check_slot(st::slot_from_plane(p, sizes));
      } catch (const st::InvalidInput& e) {
        if (std::string(e.what()).rfind("slot '", 0) == 0) std::abort(); // check_slot refused an accepted plane
      }
    }
    for (const st::PlanAxis& a : plan.axes) {
      if (!a.entry.allFinite() || std::abs(a.direction.norm() - 1.0) > 1e-9) std::abort();
      try {
        st::check_tube(st::tube_from_axis(a, st::default_sleeve_presets().front()));
      } catch (const st::InvalidInput& e) {
        if (std::string(e.what()).rfind("tube '", 0) == 0) std::abort(); // check_tube refused an accepted axis
      }
    }
  } catch (const st::InvalidInput&) {
  }
  return 0;
}
