#include "st/guide/label.h"

#include "detail/format.h"
#include "st/core/errors.h"

#include <cstdint>

namespace st {

const char* label_mode_name(LabelMode mode) { return mode == LabelMode::emboss ? "emboss" : "engrave"; }

std::optional<LabelMode> label_mode_named(const std::string& name) {
  if (name == "engrave") return LabelMode::engrave;
  if (name == "emboss") return LabelMode::emboss;
  return std::nullopt;
}

std::optional<std::size_t> utf8_length(const std::string& text) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < text.size(); ++count) {
    const auto lead = static_cast<std::uint8_t>(text[i]);
    const std::size_t n = lead < 0x80           ? 1
                          : (lead >> 5) == 0x6  ? 2
                          : (lead >> 4) == 0xE  ? 3
                          : (lead >> 3) == 0x1E ? 4
                                                : 0;
    if (n == 0 || i + n > text.size()) return std::nullopt;
    for (std::size_t k = 1; k < n; ++k)
      if ((static_cast<std::uint8_t>(text[i + k]) >> 6) != 0x2) return std::nullopt;
    i += n;
  }
  return count;
}

std::optional<TubeProblem> label_problem(const LabelSpec& label) {
  using Problem = TubeProblem;
  const auto length = utf8_length(label.text);
  if (!length) return Problem{"text", "is not valid UTF-8"};
  if (*length == 0) return Problem{"text", "must not be empty"};
  if (*length > kMaxLabelLength)
    return Problem{"text", "is too long (" + std::to_string(*length) + " characters; at most " +
                               std::to_string(kMaxLabelLength) + ")"};
  if (!label.at.allFinite()) return Problem{"at", "must be finite"};
  if (!label.up.allFinite() || !(label.up.norm() > 1e-12)) return Problem{"up", "must be a finite, non-zero vector"};
  // The comparisons are written so that NaN fails each of them.
  if (!(label.height >= 1.0 && label.height < 50.0)) return Problem{"height", "must be at least 1 and under 50 (mm)"};
  if (!(label.depth >= kMinLabelDepth_mm && label.depth < 5.0))
    return Problem{"depth",
                   "must be at least " + detail::mm(kMinLabelDepth_mm) + " (legible once printed) and under 5 mm"};
  return std::nullopt;
}

void check_label(const LabelSpec& label) {
  if (const auto problem = label_problem(label))
    throw InvalidInput("label '" + label.name + "': " + problem->key + " " + problem->reason);
}

} // namespace st
