#pragma once
// Typed access to JSON documents with errors that name the file and the key (case files, 3D
// Slicer markups, sleeve presets). Every failure throws InvalidInput("<file>: <key>: <why>").

#include "input_file.h"
#include "st/core/errors.h"
#include "st/core/mesh.h"
#include "st/core/tolerances.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace st::detail {

using nlohmann::json;

class JsonReader {
public:
  explicit JsonReader(std::string file) : file_(std::move(file)) {}

  const std::string& file() const { return file_; }

  [[noreturn]] void fail(const std::string& key, const std::string& why) const {
    throw InvalidInput(file_ + ": " + key + ": " + why);
  }

  /// The document in `text`; any JSON error (syntax, a number that overflows) as InvalidInput.
  json parse(const std::string& text) const {
    try {
      return json::parse(text);
    } catch (const json::exception& e) {
      throw InvalidInput(file_ + ": not valid JSON: " + e.what());
    }
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

/// The whole file as bytes; InvalidInput naming `what` and the path when it cannot be opened.
inline std::string read_text_file(const std::string& path, const std::string& what) {
  check_input_file(path, what, tol::kMaxTextFileBytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput(path + ": cannot open the " + what);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

} // namespace st::detail
