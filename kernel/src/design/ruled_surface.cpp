#include "st/design/ruled_surface.h"

#include "detail/parallel.h"
#include "st/core/errors.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>

namespace st {

namespace {

// Shortest strips between open sequences P[0..m] and Q[0..n] (P[m] == P[0], Q[n] == Q[0] of the
// closed loops, Q rotated to start at each of `starts`), all at once. The spans from P_i are made once
// for every start, a block of rows at a time on all threads (the square roots are most of the work);
// then each start's row of path lengths, the starts' cells interleaved (one start's additions wait for
// no other's). Fills the costs and the moves (true: advance P) per start.
template <std::size_t K> void strips(const std::vector<Vec3>& p, const std::vector<Vec3>& q, const std::size_t* starts,
                                     double* costs, std::vector<char>* moves) {
  const std::size_t m = p.size(), n = q.size();
  const std::size_t base = *std::min_element(starts, starts + K);
  std::array<std::size_t, K> shift{}; // start c's Q_j is the unrolled Q's j + shift[c]
  for (std::size_t c = 0; c < K; ++c) shift[c] = starts[c] - base;
  const std::size_t width = n + 1 + *std::max_element(shift.begin(), shift.end());
  std::vector<Vec3> qr(width); // Q unrolled from base: no division per cell
  for (std::size_t t = 0; t < width; ++t) qr[t] = q[(base + t) % n];
  const std::size_t cols = n + 1;
  const std::size_t block = std::max<std::size_t>(1, (std::size_t{1} << 17) / width); // rows of spans at a time
  std::vector<double> spans(std::min(block, m + 1) * width);
  std::vector<double> dist(cols * K);               // [j][start]
  std::vector<std::uint8_t> from_p((m + 1) * cols); // [i][j], bit c: start c reached (i, j) from (i-1, j)
  for (std::size_t i0 = 0; i0 <= m; i0 += block) {
    const std::size_t rows = std::min(block, m + 1 - i0);
    detail::parallel_for(rows, 16, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t r = begin; r < end; ++r) {
        const Vec3& pi = p[(i0 + r) % m];
        double* span = spans.data() + r * width;
        for (std::size_t t = 0; t < width; ++t) span[t] = (pi - qr[t]).norm();
      }
    });
    for (std::size_t i = i0; i < i0 + rows; ++i) {
      const double* span = spans.data() + (i - i0) * width;
      std::uint8_t* row = from_p.data() + i * cols;
      std::array<double, K> left{}; // (i, j-1) per start
      for (std::size_t c = 0; c < K; ++c) {
        left[c] = i == 0 ? span[shift[c]] : dist[c] + span[shift[c]];
        dist[c] = left[c];
      }
      row[0] = i == 0 ? 0 : static_cast<std::uint8_t>((1u << K) - 1);
      for (std::size_t j = 1; j <= n; ++j) {
        double* d = dist.data() + j * K;
        unsigned from = 0;
        for (std::size_t c = 0; c < K; ++c) {
          const double s = span[j + shift[c]];
          const double up = d[c]; // (i-1, j)
          const bool from_up = i > 0 && up <= left[c];
          left[c] = (from_up ? up : left[c]) + s;
          d[c] = left[c];
          from |= static_cast<unsigned>(from_up) << c;
        }
        row[j] = static_cast<std::uint8_t>(from);
      }
    }
  }
  for (std::size_t c = 0; c < K; ++c) {
    costs[c] = dist[n * K + c];
    std::vector<char>& path = moves[c];
    path.clear();
    std::size_t i = m, j = n;
    while (i > 0 || j > 0) {
      const bool p_move = ((from_p[i * cols + j] >> c) & 1u) != 0;
      path.push_back(p_move);
      if (p_move) --i;
      else --j;
    }
    std::reverse(path.begin(), path.end());
  }
}

} // namespace

RuledResult ruled_surface(const std::vector<Vec3>& p, const std::vector<Vec3>& q, Index p_offset, Index q_offset,
                          const RuledOptions& options) {
  const std::size_t m = p.size(), n = q.size();
  if (m < 2 || n < 2)
    throw InvalidInput("ruled surface: each loop needs at least 2 points (got " + std::to_string(m) + " and " +
                       std::to_string(n) + ")");
  if (static_cast<double>(m + 1) * static_cast<double>(n + 1) > options.max_cells_millions * 1e6)
    throw InvalidInput("ruled surface: loops of " + std::to_string(m) + " and " + std::to_string(n) +
                       " points exceed the grid budget");

  // Closest Q to P_0, then a few neighbours of it as starting spans.
  std::size_t best_j = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < n; ++j) {
    const double d = (p[0] - q[j]).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best_j = j;
    }
  }
  const int k = std::max(1, options.start_candidates);
  std::vector<std::size_t> starts(static_cast<std::size_t>(k));
  std::vector<double> costs(starts.size());
  std::vector<std::vector<char>> moves(starts.size());
  for (int c = 0; c < k; ++c) {
    const long offset = (c % 2 == 0 ? 1 : -1) * static_cast<long>((c + 1) / 2);
    starts[c] = static_cast<std::size_t>(
        (static_cast<long>(best_j) + offset % static_cast<long>(n) + static_cast<long>(n)) % static_cast<long>(n));
  }
  // Up to eight starts at once (their chains in registers).
  for (std::size_t c = 0; c < starts.size(); c += 8) {
    const std::size_t* s = &starts[c];
    double* cost = &costs[c];
    std::vector<char>* path = &moves[c];
    switch (std::min<std::size_t>(8, starts.size() - c)) {
    case 1: strips<1>(p, q, s, cost, path); break;
    case 2: strips<2>(p, q, s, cost, path); break;
    case 3: strips<3>(p, q, s, cost, path); break;
    case 4: strips<4>(p, q, s, cost, path); break;
    case 5: strips<5>(p, q, s, cost, path); break;
    case 6: strips<6>(p, q, s, cost, path); break;
    case 7: strips<7>(p, q, s, cost, path); break;
    default: strips<8>(p, q, s, cost, path); break;
    }
  }
  double best_cost = std::numeric_limits<double>::infinity();
  std::size_t best = starts.size(); // none (costs not finite: no strip)
  for (std::size_t c = 0; c < starts.size(); ++c)
    if (costs[c] < best_cost) {
      best_cost = costs[c];
      best = c;
    }
  const std::vector<char> none;
  const std::vector<char>& best_moves = best < starts.size() ? moves[best] : none;
  const std::size_t best_start = best < starts.size() ? starts[best] : best_j;

  RuledResult result;
  result.span_length = best_cost;
  result.triangles.reserve(m + n);
  std::size_t i = 0, j = 0;
  auto P = [&](std::size_t a) { return p_offset + static_cast<Index>(a % m); };
  auto Q = [&](std::size_t b) { return q_offset + static_cast<Index>((b + best_start) % n); };
  for (char move : best_moves) {
    if (move) {
      result.triangles.push_back({P(i), P(i + 1), Q(j)});
      ++i;
    } else {
      result.triangles.push_back({P(i), Q(j + 1), Q(j)});
      ++j;
    }
  }
  return result;
}

} // namespace st
