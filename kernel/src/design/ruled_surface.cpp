#include "st/design/ruled_surface.h"

#include "detail/parallel.h"
#include "st/core/errors.h"

#include <algorithm>
#include <limits>

namespace st {

namespace {

// Shortest strip between open sequences P[0..m] and Q[0..n] (P[m] == P[0], Q[n] == Q[0] of the
// closed loops, rotated so Q starts at `q_start`). Returns the cost and fills `moves` (true: advance P).
double strip(const std::vector<Vec3>& p, const std::vector<Vec3>& q, std::size_t q_start, std::vector<char>& moves) {
  const std::size_t m = p.size(), n = q.size();
  // The loops unrolled once (P[m] == P[0]; Q rotated to start at q_start): no division per cell.
  std::vector<Vec3> pr(m + 1), qr(n + 1);
  for (std::size_t i = 0; i <= m; ++i) pr[i] = p[i % m];
  for (std::size_t j = 0; j <= n; ++j) qr[j] = q[(j + q_start) % n];
  auto P = [&](std::size_t i) -> const Vec3& { return pr[i]; };
  auto Q = [&](std::size_t j) -> const Vec3& { return qr[j]; };
  const std::size_t cols = n + 1;
  std::vector<double> dist(cols);
  std::vector<char> from_p((m + 1) * cols); // true: reached (i, j) from (i-1, j)
  // Row 0.
  dist[0] = (P(0) - Q(0)).norm();
  for (std::size_t j = 1; j <= n; ++j) {
    dist[j] = dist[j - 1] + (P(0) - Q(j)).norm();
    from_p[j] = 0;
  }
  for (std::size_t i = 1; i <= m; ++i) {
    const Vec3& pi = P(i);
    dist[0] = dist[0] + (pi - Q(0)).norm();
    from_p[i * cols] = 1;
    for (std::size_t j = 1; j <= n; ++j) {
      const double span = (pi - Q(j)).norm();
      const double up = dist[j];       // (i-1, j)
      const double left = dist[j - 1]; // (i, j-1)
      if (up <= left) {
        dist[j] = up + span;
        from_p[i * cols + j] = 1;
      } else {
        dist[j] = left + span;
        from_p[i * cols + j] = 0;
      }
    }
  }
  moves.clear();
  std::size_t i = m, j = n;
  while (i > 0 || j > 0) {
    const bool p_move = from_p[i * cols + j] != 0;
    moves.push_back(p_move);
    if (p_move) --i;
    else --j;
  }
  std::reverse(moves.begin(), moves.end());
  return dist[n];
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
  // The candidates' strips are independent: on all threads, the best taken in candidate order.
  std::vector<std::size_t> starts(static_cast<std::size_t>(k));
  std::vector<double> costs(starts.size());
  std::vector<std::vector<char>> moves(starts.size());
  for (int c = 0; c < k; ++c) {
    const long offset = (c % 2 == 0 ? 1 : -1) * static_cast<long>((c + 1) / 2);
    starts[c] = static_cast<std::size_t>(
        (static_cast<long>(best_j) + offset % static_cast<long>(n) + static_cast<long>(n)) % static_cast<long>(n));
  }
  detail::parallel_for(starts.size(), 1, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) costs[c] = strip(p, q, starts[c], moves[c]);
  });
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
