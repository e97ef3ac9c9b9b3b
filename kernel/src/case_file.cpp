#include "st/case_file.h"

#include "st/errors.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace st {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

class Reader {
public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& why) const {
    throw InvalidInput(file_ + ": " + key + ": " + why);
  }

  double number(const json& j, const std::string& key) const {
    if (!j.is_number()) fail(key, "must be a number, got " + std::string(j.type_name()));
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(key, "must be finite");
    return v;
  }

  Vec3 point(const json& j, const std::string& key) const {
    if (!j.is_array() || j.size() != 3) fail(key, "must be an array of 3 numbers [x, y, z]");
    return {number(j[0], key + "[0]"), number(j[1], key + "[1]"), number(j[2], key + "[2]")};
  }

  std::string string(const json& j, const std::string& key) const {
    if (!j.is_string()) fail(key, "must be a string, got " + std::string(j.type_name()));
    return j.get<std::string>();
  }

  const json& required(const json& obj, const std::string& name, const std::string& key) const {
    if (!obj.contains(name)) fail(key, "is required");
    return obj.at(name);
  }

  void unknown_keys(const json& obj, const std::set<std::string>& known, const std::string& where,
                    std::vector<std::string>& warnings) const {
    for (const auto& [k, v] : obj.items())
      if (!known.count(k)) warnings.push_back(file_ + ": unknown key '" + where + k + "' ignored");
  }

private:
  std::string file_;
};

} // namespace

CaseFile parse_case(const std::string& text, const std::string& path) {
  const Reader r(path);
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) { // parse_error, and out_of_range for a number that overflows
    throw InvalidInput(path + ": not valid JSON: " + e.what());
  }
  if (!doc.is_object()) r.fail("(top level)", "must be a JSON object");
  CaseFile c;
  c.path = path;
  const fs::path folder = fs::absolute(fs::path(path)).parent_path();
  auto resolve = [&](const std::string& p) { return (folder / p).lexically_normal().string(); };

  const std::string format = r.string(r.required(doc, "format", "format"), "format");
  if (format != kCaseFormat)
    r.fail("format", "must be \"" + std::string(kCaseFormat) + "\", got \"" + format + "\"");
  r.unknown_keys(doc, {"format", "name", "bone", "boundary", "template", "tubes", "output"}, "", c.warnings);

  c.name = doc.contains("name") ? r.string(doc["name"], "name") : fs::path(path).stem().string();
  c.bone = resolve(r.string(r.required(doc, "bone", "bone"), "bone"));

  const json& boundary = r.required(doc, "boundary", "boundary");
  if (!boundary.is_object()) r.fail("boundary", "must be an object");
  r.unknown_keys(boundary, {"points", "inside", "markups"}, "boundary.", c.warnings);
  if (boundary.contains("markups") && !boundary.contains("points"))
    r.fail("boundary.markups", "3D Slicer markups are not supported by this version yet; give boundary.points");
  const json& points = r.required(boundary, "points", "boundary.points");
  if (!points.is_array()) r.fail("boundary.points", "must be an array of [x, y, z] points");
  if (points.size() < 3)
    r.fail("boundary.points", "needs at least 3 points, got " + std::to_string(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i)
    c.boundary_points.push_back(r.point(points[i], "boundary.points[" + std::to_string(i) + "]"));
  if (boundary.contains("inside")) c.inside = r.point(boundary["inside"], "boundary.inside");

  const json& tpl = r.required(doc, "template", "template");
  if (!tpl.is_object()) r.fail("template", "must be an object");
  r.unknown_keys(tpl, {"thickness", "clearance", "resolution", "sampling_step"}, "template.", c.warnings);
  c.thickness = r.number(r.required(tpl, "thickness", "template.thickness"), "template.thickness");
  if (!(c.thickness > 0.0)) r.fail("template.thickness", "must be > 0, got " + std::to_string(c.thickness));
  if (tpl.contains("clearance")) {
    c.clearance = r.number(tpl["clearance"], "template.clearance");
    if (c.clearance < 0.0) r.fail("template.clearance", "must be >= 0, got " + std::to_string(c.clearance));
  }
  if (tpl.contains("resolution")) {
    c.resolution = r.number(tpl["resolution"], "template.resolution");
    if (!(*c.resolution > 0.0)) r.fail("template.resolution", "must be > 0, got " + std::to_string(*c.resolution));
  }
  if (tpl.contains("sampling_step")) {
    const json& s = tpl["sampling_step"];
    if (!s.is_number_integer() && !(s.is_number() && std::floor(s.get<double>()) == s.get<double>()))
      r.fail("template.sampling_step", "must be an integer");
    const double v = s.get<double>();
    if (v < 1 || v > 1e6) r.fail("template.sampling_step", "must be between 1 and 1000000");
    c.sampling_step = static_cast<int>(v);
  }

  if (doc.contains("tubes")) {
    const json& tubes = doc["tubes"];
    if (!tubes.is_array()) r.fail("tubes", "must be an array");
    for (std::size_t i = 0; i < tubes.size(); ++i) {
      const std::string key = "tubes[" + std::to_string(i) + "]";
      const json& t = tubes[i];
      if (!t.is_object()) r.fail(key, "must be an object");
      r.unknown_keys(t, {"name", "entry", "direction", "inner_radius", "outer_radius", "length", "offset", "markups"},
                     key + ".", c.warnings);
      TubeSpec tube;
      tube.name = t.contains("name") ? r.string(t["name"], key + ".name") : std::to_string(i + 1);
      if (t.contains("markups") && !t.contains("entry"))
        r.fail(key + ".markups", "3D Slicer markups are not supported by this version yet; give entry and direction");
      tube.entry = r.point(r.required(t, "entry", key + ".entry"), key + ".entry");
      tube.direction = r.point(r.required(t, "direction", key + ".direction"), key + ".direction");
      const double len = tube.direction.stableNorm(); // no overflow for huge components
      if (!(len > 1e-12)) r.fail(key + ".direction", "must be non-zero");
      tube.direction /= len;
      if (!tube.direction.allFinite()) r.fail(key + ".direction", "must be a finite, non-zero vector");
      tube.inner_radius = r.number(r.required(t, "inner_radius", key + ".inner_radius"), key + ".inner_radius");
      tube.outer_radius = r.number(r.required(t, "outer_radius", key + ".outer_radius"), key + ".outer_radius");
      tube.length = r.number(r.required(t, "length", key + ".length"), key + ".length");
      if (t.contains("offset")) tube.offset = r.number(t["offset"], key + ".offset");
      if (!(tube.inner_radius > 0.0)) r.fail(key + ".inner_radius", "must be > 0");
      if (!(tube.outer_radius > tube.inner_radius)) r.fail(key + ".outer_radius", "must be > inner_radius");
      if (!(tube.length > 0.0)) r.fail(key + ".length", "must be > 0");
      if (tube.offset < 0.0) r.fail(key + ".offset", "must be >= 0");
      // The same bounds as check_tube (sleeve.h): a sleeve over 1 m wide or 10 m long is a unit error.
      if (tube.outer_radius >= 1e3) r.fail(key + ".outer_radius", "is absurd (must be under 1000 mm)");
      if (tube.length >= 1e4) r.fail(key + ".length", "is absurd (must be under 10000 mm)");
      if (tube.offset >= 1e4) r.fail(key + ".offset", "is absurd (must be under 10000 mm)");
      c.tubes.push_back(tube);
    }
  }
  if (doc.contains("output")) c.output = resolve(r.string(doc["output"], "output"));
  return c;
}

CaseFile read_case(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput(path + ": cannot open the case file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_case(text.str(), path);
}

} // namespace st
