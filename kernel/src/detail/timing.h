#pragma once
// The kernel's step times (the report's `times`): a steady clock and seconds since a start.

#include <chrono>

namespace st::detail {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

} // namespace st::detail
