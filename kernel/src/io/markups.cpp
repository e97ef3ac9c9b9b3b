// 3D Slicer markups (.mrk.json) read into a Plan (st/io/plan.h).

#include "st/io/plan.h"

#include "detail/json_reader.h"
#include "detail/text.h"
#include "st/core/errors.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>

namespace st {

namespace {

using detail::json;
using detail::lower;
using detail::without_blanks;

// ---- 3D Slicer markups ---------------------------------------------------------------------------

struct ControlPoint {
  Vec3 position;
  std::string label;
};

Space markup_space(const detail::JsonReader& r, const json& m, const std::string& key) {
  if (!m.contains("coordinateSystem")) return Space::LPS; // Slicer's default
  const std::string s = lower(r.string(m["coordinateSystem"], key + ".coordinateSystem"));
  if (s == "lps") return Space::LPS;
  if (s == "ras") return Space::RAS;
  r.fail(key + ".coordinateSystem", "must be \"LPS\" or \"RAS\", got \"" + s + "\"");
}

/// mm per unit of the markup's coordinates.
double markup_scale(const detail::JsonReader& r, const json& m, const std::string& key) {
  if (!m.contains("coordinateUnits")) return 1.0;
  const json& u = m["coordinateUnits"];
  // A plain string, or a coded entry (UCUM): [CodeValue, CodingSchemeDesignator, CodeMeaning] as Slicer
  // writes it, or an object with a CodeValue.
  std::string unit;
  if (u.is_array()) {
    if (u.empty()) r.fail(key + ".coordinateUnits", "is an empty coded entry");
    unit = r.string(u[0], key + ".coordinateUnits[0]");
  } else if (u.is_object()) {
    unit = r.string(r.required(u, "CodeValue", key + ".coordinateUnits.CodeValue"), key + ".coordinateUnits.CodeValue");
  } else {
    unit = r.string(u, key + ".coordinateUnits");
  }
  if (unit == "mm") return 1.0;
  if (unit == "um") return 1e-3;
  r.fail(key + ".coordinateUnits", "must be \"mm\" or \"um\", got \"" + unit + "\"");
}

std::vector<ControlPoint> control_points(const detail::JsonReader& r, const json& m, const std::string& key,
                                         Space target, std::vector<std::string>& warnings) {
  std::vector<ControlPoint> out;
  if (!m.contains("controlPoints")) return out;
  const json& cps = m["controlPoints"];
  if (!cps.is_array()) r.fail(key + ".controlPoints", "must be an array");
  const Space space = markup_space(r, m, key);
  const double scale = markup_scale(r, m, key);
  for (std::size_t i = 0; i < cps.size(); ++i) {
    const std::string ck = key + ".controlPoints[" + std::to_string(i) + "]";
    const json& cp = cps[i];
    if (!cp.is_object()) r.fail(ck, "must be an object");
    if (cp.contains("positionStatus")) {
      const std::string status = r.string(cp["positionStatus"], ck + ".positionStatus");
      if (status != "defined") {
        warnings.push_back(r.file() + ": " + ck + ": skipped (positionStatus \"" + status + "\")");
        continue;
      }
    }
    ControlPoint p;
    p.position =
        convert_space(r.point(r.required(cp, "position", ck + ".position"), ck + ".position") * scale, space, target);
    if (cp.contains("label")) p.label = r.string(cp["label"], ck + ".label");
    out.push_back(std::move(p));
  }
  return out;
}

/// A cut plane from a Plane markup: "center" and "normal" as Slicer 5 writes them, else the first
/// control point with the normal of "orientation" (its third column), else of the first three points.
PlanPlane plane_markup(const detail::JsonReader& r, const json& m, const std::string& what,
                       const std::vector<ControlPoint>& points, Space target) {
  const Space space = markup_space(r, m, what);
  const double scale = markup_scale(r, m, what);
  PlanPlane plane;
  Vec3 normal = Vec3::Zero();
  if (m.contains("center") && m.contains("normal")) {
    plane.origin = convert_space(r.point(m["center"], what + ".center") * scale, space, target);
    normal = convert_space(r.point(m["normal"], what + ".normal"), space, target);
  } else if (!points.empty() && m.contains("orientation")) {
    const json& o = m["orientation"];
    if (!o.is_array() || o.size() != 9) r.fail(what + ".orientation", "must hold 9 numbers (a 3 x 3 matrix)");
    Vec3 z;
    for (int i = 0; i < 3; ++i) z[i] = r.number(o[static_cast<std::size_t>(3 * i + 2)], what + ".orientation");
    plane.origin = points[0].position;
    normal = convert_space(z, space, target);
  } else if (points.size() >= 3) {
    plane.origin = points[0].position;
    normal = (points[1].position - points[0].position).cross(points[2].position - points[0].position);
  } else {
    r.fail(what, "a plane needs \"center\" and \"normal\", or a control point and \"orientation\", or 3 "
                 "control points");
  }
  const double length = normal.norm();
  if (!(length > 1e-12) || !std::isfinite(length)) r.fail(what, "its normal is zero or not finite: no plane");
  if (!plane.origin.allFinite()) r.fail(what, "its centre is not finite");
  plane.normal = normal / length;
  return plane;
}

std::vector<Vec3> positions(const std::vector<ControlPoint>& points) {
  std::vector<Vec3> out;
  for (const ControlPoint& p : points) out.push_back(p.position);
  return out;
}

} // namespace

Plan parse_markups(const std::string& text, const std::string& path, Space target) {
  const detail::JsonReader r(path);
  const json doc = r.parse(text);
  if (!doc.is_object()) r.fail("(top level)", "must be a JSON object (a 3D Slicer markups file)");
  Plan plan;
  plan.path = path;
  plan.kind = "markups";
  if (!doc.contains("@schema")) plan.warnings.push_back(path + ": no \"@schema\"; read as a 3D Slicer markups file");
  const json& markups = r.required(doc, "markups", "markups");
  if (!markups.is_array()) r.fail("markups", "must be an array");
  bool closed_curve = false;
  std::vector<Vec3> point_list_boundary;
  for (std::size_t i = 0; i < markups.size(); ++i) {
    const std::string key = "markups[" + std::to_string(i) + "]";
    const json& m = markups[i];
    if (!m.is_object()) r.fail(key, "must be an object");
    const std::string type = r.string(r.required(m, "type", key + ".type"), key + ".type");
    const std::string name = m.contains("name") ? r.string(m["name"], key + ".name") : "";
    const std::vector<ControlPoint> points = control_points(r, m, key, target, plan.warnings);
    const std::string what = key + " (" + type + (name.empty() ? "" : " \"" + name + "\"") + ")";
    if (type == "ClosedCurve") {
      if (closed_curve) {
        plan.warnings.push_back(path + ": " + what + ": a second ClosedCurve, ignored");
        continue;
      }
      if (points.size() < 3)
        r.fail(what, "a boundary needs at least 3 defined control points, got " + std::to_string(points.size()));
      plan.boundary_points = positions(points);
      closed_curve = true;
    } else if (type == "Line") {
      if (points.size() != 2)
        r.fail(what, "a drilling axis needs exactly 2 defined control points (entry, then a point inside the "
                     "bone), got " +
                         std::to_string(points.size()));
      PlanAxis axis;
      axis.entry = points[0].position;
      const Vec3 along = points[1].position - points[0].position;
      const double depth = along.norm();
      if (!(depth > 1e-9)) r.fail(what, "its two control points coincide: no direction");
      axis.direction = along / depth;
      axis.depth = depth;
      axis.name = !name.empty()              ? name
                  : !points[0].label.empty() ? points[0].label
                                             : "Line " + std::to_string(plan.axes.size() + 1);
      axis.source = path + ": " + key;
      plan.axes.push_back(std::move(axis));
    } else if (type == "Plane") {
      PlanPlane plane = plane_markup(r, m, key, points, target);
      plane.name = !name.empty() ? name : "Plane " + std::to_string(plan.planes.size() + 1);
      plane.source = path + ": " + key;
      plan.planes.push_back(std::move(plane));
    } else if (type == "Fiducial") {
      if (points.size() == 1) {
        if (plan.inside) plan.warnings.push_back(path + ": " + what + ": a second inside point, ignored");
        else plan.inside = points[0].position;
      } else if (points.size() >= 3 && point_list_boundary.empty()) {
        point_list_boundary = positions(points);
      } else {
        plan.warnings.push_back(path + ": " + what + ": a point list of " + std::to_string(points.size()) +
                                " points, ignored (1 point: inside the region; 3 or more: the boundary)");
      }
    } else {
      plan.warnings.push_back(path + ": " + what + ": this markups type is not part of a plan, ignored");
    }
  }
  if (!closed_curve && !point_list_boundary.empty()) plan.boundary_points = std::move(point_list_boundary);
  if (plan.boundary_points.empty() && plan.axes.empty() && plan.planes.empty())
    r.fail("markups", "holds no ClosedCurve, point list, Line or Plane: nothing to plan with");
  return plan;
}

Plan read_markups(const std::string& path, Space target) {
  return parse_markups(detail::read_text_file(path, "markups file"), path, target);
}

} // namespace st
