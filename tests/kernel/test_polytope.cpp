// The vertex enumeration under the stability analysis (validate/polytope.h) against brute force: every
// m of the constraints solved together, the feasible solutions kept. Random systems (simple: every
// vertex on exactly m hyperplanes, the edge index at work) and integer ones (many hyperplanes through
// one vertex, parallel and repeated ones: the counting fall-back at work), in 2 to 5 dimensions.

#include "validate/polytope.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cstdlib>
#include <random>
#include <vector>

namespace st {
namespace {

using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

struct HalfSpace {
  VecX h; // unit
  double r;
};

/// Systems tried per dimension (ST_PROPERTY_CASES / 10, default 50).
int systems() {
  const char* env = std::getenv("ST_PROPERTY_CASES");
  return env ? std::max(5, std::atoi(env) / 10) : 50;
}

/// Every vertex of {h . z >= r} within the box, by solving each m of the constraints.
std::vector<VecX> brute_force(int m, double box, std::vector<HalfSpace> all) {
  for (int k = 0; k < m; ++k) {
    all.push_back({VecX::Unit(m, k), -box});
    all.push_back({-VecX::Unit(m, k), -box});
  }
  std::vector<VecX> out;
  std::vector<int> pick(static_cast<std::size_t>(m));
  for (int k = 0; k < m; ++k) pick[static_cast<std::size_t>(k)] = k;
  const int n = static_cast<int>(all.size());
  while (true) {
    MatX a(m, m);
    VecX b(m);
    for (int k = 0; k < m; ++k) {
      a.row(k) = all[static_cast<std::size_t>(pick[static_cast<std::size_t>(k)])].h.transpose();
      b(k) = all[static_cast<std::size_t>(pick[static_cast<std::size_t>(k)])].r;
    }
    const Eigen::FullPivLU<MatX> lu(a);
    if (lu.rank() == m) {
      const VecX z = lu.solve(b);
      const bool feasible = std::all_of(
          all.begin(), all.end(), [&](const HalfSpace& c) { return c.h.dot(z) - c.r >= -1e-9 * (1.0 + z.norm()); });
      const bool seen = std::any_of(out.begin(), out.end(), [&](const VecX& v) { return (v - z).norm() < 1e-6; });
      if (feasible && !seen) out.push_back(z);
    }
    int k = m - 1; // the next m-subset
    while (k >= 0 && pick[static_cast<std::size_t>(k)] == n - m + k) --k;
    if (k < 0) break;
    ++pick[static_cast<std::size_t>(k)];
    for (int j = k + 1; j < m; ++j) pick[static_cast<std::size_t>(j)] = pick[static_cast<std::size_t>(j - 1)] + 1;
  }
  return out;
}

/// Enumerates with the polytope and compares with brute force; false when the polytope came out empty.
void expect_same_vertices(int m, double box, const std::vector<HalfSpace>& constraints, const char* what, int trial) {
  stability_detail::Polytope p(m, box);
  bool empty = false;
  for (const HalfSpace& c : constraints)
    if (!p.cut(c.h, c.r)) empty = true;
  const std::vector<VecX> got = empty ? std::vector<VecX>{} : p.vertices();
  const std::vector<VecX> want = brute_force(m, box, constraints);
  ASSERT_EQ(got.size(), want.size()) << what << " system " << trial << " in " << m << " dimensions";
  for (const VecX& v : want)
    EXPECT_TRUE(std::any_of(got.begin(), got.end(), [&](const VecX& g) { return (g - v).norm() < 1e-6; }))
        << what << " system " << trial << ": vertex (" << v.transpose() << ") missing";
}

TEST(Polytope, RandomSystemsGiveTheBruteForceVertices) {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> offset(-1.0, 0.3);
  for (int m = 2; m <= 5; ++m)
    for (int trial = 0; trial < systems(); ++trial) {
      std::vector<HalfSpace> cs;
      const int n = m == 5 ? 9 : 12;
      for (int i = 0; i < n; ++i) {
        VecX h(m);
        for (int k = 0; k < m; ++k) h(k) = normal(rng);
        cs.push_back({h.normalized(), offset(rng)});
      }
      expect_same_vertices(m, 4.0, cs, "random", trial);
    }
}

TEST(Polytope, DegenerateIntegerSystemsGiveTheBruteForceVertices) {
  // Coefficients in {-1, 0, 1} and offsets in {-1, 0}: hyperplanes through the same vertices, on the
  // box's faces, parallel and repeated.
  std::mt19937 rng(12);
  std::uniform_int_distribution<int> coefficient(-1, 1), offset(-1, 0);
  for (int m = 2; m <= 5; ++m)
    for (int trial = 0; trial < systems(); ++trial) {
      std::vector<HalfSpace> cs;
      const int n = m == 5 ? 8 : 11;
      while (static_cast<int>(cs.size()) < n) {
        VecX h(m);
        for (int k = 0; k < m; ++k) h(k) = coefficient(rng);
        if (h.norm() == 0.0) continue;
        const double norm = h.norm();
        cs.push_back({h / norm, offset(rng) / norm});
      }
      expect_same_vertices(m, 2.0, cs, "integer", trial);
    }
}

} // namespace
} // namespace st
