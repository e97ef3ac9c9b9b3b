// Tests of the exact orientation predicates against an independent exact reference: every double is
// an integer times a power of two, so the determinants are evaluated on those integers with a 512-bit
// two's complement integer written here for the purpose.

#include "st/core/predicates.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

namespace {

using st::Vec3;

__extension__ typedef unsigned __int128 U128;

// 512-bit two's complement integer; + - * are exact as long as the true result fits.
struct Wide {
  std::array<std::uint64_t, 8> limb{};
};

Wide wide(std::int64_t v) {
  Wide w;
  w.limb.fill(v < 0 ? ~std::uint64_t{0} : 0);
  w.limb[0] = static_cast<std::uint64_t>(v);
  return w;
}

Wide operator+(const Wide& a, const Wide& b) {
  Wide r;
  U128 carry = 0;
  for (int i = 0; i < 8; ++i) {
    const U128 s = static_cast<U128>(a.limb[i]) + b.limb[i] + carry;
    r.limb[i] = static_cast<std::uint64_t>(s);
    carry = s >> 64;
  }
  return r;
}

Wide operator-(const Wide& a) {
  Wide r;
  for (int i = 0; i < 8; ++i) r.limb[i] = ~a.limb[i];
  return r + wide(1);
}

Wide operator-(const Wide& a, const Wide& b) { return a + (-b); }

Wide operator*(const Wide& a, const Wide& b) {
  Wide r;
  for (int i = 0; i < 8; ++i) {
    U128 carry = 0;
    for (int j = 0; i + j < 8; ++j) {
      const U128 t = static_cast<U128>(a.limb[i]) * b.limb[j] + r.limb[i + j] + carry;
      r.limb[i + j] = static_cast<std::uint64_t>(t);
      carry = t >> 64;
    }
  }
  return r;
}

int sign(const Wide& a) {
  if (a.limb[7] >> 63) return -1;
  for (std::uint64_t l : a.limb)
    if (l != 0) return 1;
  return 0;
}

Wide shifted_left(const Wide& a, int s) {
  Wide r;
  const int words = s / 64, bits = s % 64;
  for (int i = 7; i >= words; --i) {
    std::uint64_t v = a.limb[i - words] << bits;
    if (bits != 0 && i - words - 1 >= 0) v |= a.limb[i - words - 1] >> (64 - bits);
    r.limb[i] = v;
  }
  return r;
}

// Exponent of the lowest set bit of x != 0.
int lowest_bit(double x) {
  int e;
  const double f = std::frexp(std::fabs(x), &e);
  const auto m = static_cast<std::uint64_t>(std::ldexp(f, 53));
  return e - 53 + std::countr_zero(m);
}

// x / 2^unit exactly; x must be a multiple of 2^unit.
Wide exact_integer(double x, int unit) {
  if (x == 0.0) return {};
  int e;
  const double f = std::frexp(std::fabs(x), &e);
  auto m = static_cast<std::uint64_t>(std::ldexp(f, 53));
  int s = e - 53 - unit;
  for (; s < 0; ++s) {
    if (m & 1) throw std::logic_error("not a multiple of the unit");
    m >>= 1;
  }
  if (s > 300) throw std::logic_error("reference range exceeded");
  const Wide w = shifted_left(wide(static_cast<std::int64_t>(m)), s);
  return x < 0 ? -w : w;
}

// Exact integers for coordinates in units of their smallest set bit.
std::vector<Wide> exact_integers(const std::vector<double>& xs, int max_bits) {
  int unit = 1 << 20, top = -(1 << 20);
  for (double x : xs)
    if (x != 0.0) {
      unit = std::min(unit, lowest_bit(x));
      top = std::max(top, std::ilogb(x));
    }
  if (top - unit > max_bits) throw std::logic_error("reference range exceeded");
  std::vector<Wide> r;
  for (double x : xs) r.push_back(exact_integer(x, unit));
  return r;
}

int reference_orient2d(const double* a, const double* b, const double* c) {
  const auto v = exact_integers({a[0], a[1], b[0], b[1], c[0], c[1]}, 240);
  return sign((v[0] - v[4]) * (v[3] - v[5]) - (v[1] - v[5]) * (v[2] - v[4]));
}

int reference_orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const auto v = exact_integers({a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2]}, 160);
  Wide r[3][3];
  for (int k = 0; k < 3; ++k) {
    r[0][k] = v[k] - v[9 + k];
    r[1][k] = v[3 + k] - v[9 + k];
    r[2][k] = v[6 + k] - v[9 + k];
  }
  const Wide det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                   r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                   r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
  return sign(det);
}

// The plain floating-point evaluation the predicates protect against.
int naive_orient2d(const double* a, const double* b, const double* c) {
  const double det = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]);
  return (det > 0) - (det < 0);
}

int naive_orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
  const double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
  const double adz = a[2] - d[2], bdz = b[2] - d[2], cdz = c[2] - d[2];
  const double det = adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) + cdz * (adx * bdy - bdx * ady);
  return (det > 0) - (det < 0);
}

// x moved by n ulps.
double step(double x, int n) {
  for (; n > 0; --n) x = std::nextafter(x, HUGE_VAL);
  for (; n < 0; ++n) x = std::nextafter(x, -HUGE_VAL);
  return x;
}

} // namespace

TEST(Orient2d, BasicSignsAndDegenerateInput) {
  const double o[2] = {0, 0}, x[2] = {1, 0}, y[2] = {0, 1}, xy[2] = {2, 2}, m[2] = {-3, -3};
  EXPECT_EQ(st::orient2d(o, x, y), 1);
  EXPECT_EQ(st::orient2d(o, y, x), -1);
  EXPECT_EQ(st::orient2d(x, y, o), 1);
  EXPECT_EQ(st::orient2d(o, xy, m), 0); // collinear
  EXPECT_EQ(st::orient2d(o, o, x), 0);  // repeated point
  EXPECT_EQ(st::orient2d(x, x, x), 0);
  EXPECT_EQ(st::orient2d(o, o, o), 0);
  const double tiny[2] = {0x1p-1074, 0}, tiny_up[2] = {0, 0x1p-1074};
  EXPECT_EQ(st::orient2d(o, tiny, tiny_up), 1); // subnormal: products underflow to zero
  const double big1[2] = {0x1p1020, 0}, big2[2] = {0, 0x1p1020};
  EXPECT_EQ(st::orient2d(o, big1, big2), 1); // products overflow
  EXPECT_EQ(st::orient2d(big2, big1, o), -1);
}

TEST(Orient3d, ConventionPositiveBelowThePlane) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // (b - a) x (c - a) = +z: "above" is +z, and a point below gives +1.
  EXPECT_EQ(st::orient3d(a, b, c, Vec3(0, 0, -1)), 1);
  EXPECT_EQ(st::orient3d(a, b, c, Vec3(0.3, 0.3, 1e-300)), -1);
  EXPECT_EQ(st::orient3d(a, b, c, Vec3(5, -7, 0)), 0);
  EXPECT_EQ(st::orient3d(b, a, c, Vec3(0, 0, -1)), -1);           // odd permutation flips the sign
  EXPECT_EQ(st::orient3d(a, b, Vec3(2, 0, 0), Vec3(1, 2, 3)), 0); // collinear a, b, c
  EXPECT_EQ(st::orient3d(a, a, c, Vec3(1, 2, 3)), 0);             // repeated point
  EXPECT_EQ(st::orient3d(a, b, c, a), 0);
  EXPECT_EQ(st::orient3d(a, a, a, a), 0);
  // Non-finite input is outside the contract but must not crash or hang.
  const int s_nan = st::orient3d(a, b, c, Vec3(std::nan(""), 0, 0));
  const int s_inf = st::orient3d(a, b, c, Vec3(0, 0, HUGE_VAL));
  EXPECT_TRUE(s_nan >= -1 && s_nan <= 1 && s_inf >= -1 && s_inf <= 1);
  // Equals the sign of -((b - a) x (c - a)) . (d - a) on an asymmetric example.
  const Vec3 p(1, 2, 3), q(-2, 5, 1), r(4, -1, 2), s(0.5, 0.25, -3);
  const double v = -((q - p).cross(r - p)).dot(s - p);
  EXPECT_EQ(st::orient3d(p, q, r, s), (v > 0) - (v < 0));
  EXPECT_NE(v, 0.0);
}

// Kettner et al. / Shewchuk's classroom example: p on a 256 x 256 grid of ulps at (0.5, 0.5), q and r
// far away on the line y = x. Plain double evaluation gets many signs wrong.
TEST(Orient2d, UlpGridNearALineMatchesExactReference) {
  const double q[2] = {12, 12}, r[2] = {24, 24};
  const double u = 0x1p-53; // ulp of 0.5
  int naive_wrong = 0, checked = 0;
  for (int i = 0; i < 256; ++i)
    for (int j = 0; j < 256; ++j) {
      const double p[2] = {0.5 + i * u, 0.5 + j * u};
      const int expected = reference_orient2d(p, q, r);
      ASSERT_EQ(expected, (j > i) - (j < i)); // p left of q -> r when above the line
      ASSERT_EQ(st::orient2d(p, q, r), expected) << i << " " << j;
      ASSERT_EQ(st::orient2d(q, r, p), expected);
      ASSERT_EQ(st::orient2d(r, q, p), -expected);
      naive_wrong += naive_orient2d(p, q, r) != expected;
      ++checked;
    }
  EXPECT_EQ(checked, 65536);
  EXPECT_GT(naive_wrong, 1000) << "the grid no longer exercises the exact path";
}

// The 3D analogue: d on a grid of ulps around a point of the plane x + y + z = 2.25 spanned by three
// far points.
TEST(Orient3d, UlpGridNearAPlaneMatchesExactReference) {
  const Vec3 a(12, 12, -21.75), b(24, -12, -9.75), c(-8, 20, -9.75);
  const st::PlaneOrientation plane(a, b, c);
  const double u = 0x1p-53; // ulp in [0.5, 1)
  int naive_wrong = 0, zeros = 0;
  for (int i = -12; i <= 12; ++i)
    for (int j = -12; j <= 12; ++j)
      for (int k = -12; k <= 12; ++k) {
        const Vec3 d(0.75 + i * u, 0.75 + j * u, 0.75 + k * u);
        const int expected = reference_orient3d(a, b, c, d);
        // (b - a) x (c - a) = (-384, -384, -384) points to i + j + k < 0: d there is above and
        // gives -1.
        ASSERT_EQ(expected, (i + j + k > 0) - (i + j + k < 0));
        ASSERT_EQ(st::orient3d(a, b, c, d), expected) << i << " " << j << " " << k;
        ASSERT_EQ(st::orient3d(b, c, a, d), expected);
        ASSERT_EQ(st::orient3d(d, b, c, a), -expected);
        ASSERT_EQ(plane(d), expected) << i << " " << j << " " << k;
        naive_wrong += naive_orient3d(a, b, c, d) != expected;
        zeros += expected == 0;
      }
  EXPECT_GT(zeros, 0);
  EXPECT_GT(naive_wrong, 100) << "the grid no longer exercises the exact path";
}

// Coordinates around 1e8 with perturbations of single ulps: d near a point of the plane
// x + y + z = 3e8 + 0.25 far from a, b, c.
TEST(Orient3d, LargeCoordinatesWithUlpPerturbations) {
  const Vec3 a(1e8, 1e8, 1e8 + 0.25), b(2e8 + 0.5, 0.5e8, 0.5e8 - 0.25), c(0.25e8, 2.5e8, 0.25e8 + 0.25);
  const Vec3 e(5.5e8 + 1.5, -3.5e8, 1e8 - 1.25); // e = a + 3 (b - a) - 2 (c - a)
  ASSERT_EQ(st::orient3d(a, b, c, e), 0);
  ASSERT_EQ(reference_orient3d(a, b, c, e), 0);
  int naive_wrong = 0, nonzero = 0;
  for (int i = -6; i <= 6; ++i)
    for (int j = -6; j <= 6; ++j)
      for (int k = -6; k <= 6; ++k) {
        const Vec3 d(step(e[0], i), step(e[1], j), step(e[2], k));
        const int expected = reference_orient3d(a, b, c, d);
        ASSERT_EQ(st::orient3d(a, b, c, d), expected) << i << " " << j << " " << k;
        ASSERT_EQ(st::orient3d(a, d, b, c), expected);
        ASSERT_EQ(st::PlaneOrientation(a, b, c)(d), expected);
        naive_wrong += naive_orient3d(a, b, c, d) != expected;
        nonzero += expected != 0;
      }
  EXPECT_GT(nonzero, 1000);
  EXPECT_GT(naive_wrong, 10) << "the grid no longer exercises the exact path";
}

// Random nearly degenerate input: a fourth point computed in floating point on the plane (or line)
// of the others, then moved by a few ulps.
TEST(Orient3d, RandomNearlyCoplanarPointsMatchExactReference) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> coord(-1.0, 1.0), weight(-2.0, 3.0);
  std::uniform_int_distribution<int> ulps(-2, 2), scale(-40, 40), small(-2, 3), coin(0, 1);
  // On a grid of 2^-40 the points and small integer combinations of them are exact.
  auto snap = [](double x) { return std::ldexp(std::nearbyint(std::ldexp(x, 40)), -40); };
  int nonzero = 0, zero = 0, naive_wrong = 0;
  for (int n = 0; n < 20000; ++n) {
    const int s = scale(rng);
    auto point = [&] { return Vec3(snap(coord(rng)), snap(coord(rng)), snap(coord(rng))); };
    Vec3 a = point(), b = point(), c = point();
    const bool exact = coin(rng); // exactly coplanar before the nudge
    const double w1 = exact ? small(rng) : weight(rng), w2 = exact ? small(rng) : weight(rng);
    Vec3 d = a + w1 * (b - a) + w2 * (c - a);
    const bool nudge = coin(rng);
    for (int k = 0; k < 3; ++k) d[k] = step(snap(d[k]), nudge ? ulps(rng) : 0);
    for (Vec3* p : {&a, &b, &c, &d})
      for (int k = 0; k < 3; ++k) (*p)[k] = std::ldexp((*p)[k], s);
    const int expected = reference_orient3d(a, b, c, d);
    ASSERT_EQ(st::orient3d(a, b, c, d), expected) << n;
    ASSERT_EQ(st::orient3d(b, a, c, d), -expected) << n;
    ASSERT_EQ(st::PlaneOrientation(a, b, c)(d), expected) << n;
    ASSERT_EQ(st::PlaneOrientation(b, a, c)(d), -expected) << n;
    ASSERT_EQ(st::orient3d(d, a, b, c), -expected) << n;
    naive_wrong += naive_orient3d(a, b, c, d) != expected;
    (expected == 0 ? zero : nonzero)++;
  }
  EXPECT_GT(zero, 100);
  EXPECT_GT(nonzero, 10000);
  EXPECT_GT(naive_wrong, 10);
}

TEST(Orient2d, RandomNearlyCollinearPointsMatchExactReference) {
  std::mt19937_64 rng(777);
  std::uniform_real_distribution<double> coord(-1.0, 1.0), weight(-2.0, 3.0);
  std::uniform_int_distribution<int> ulps(-2, 2), scale(-60, 60), small(-2, 3), coin(0, 1);
  auto snap = [](double x) { return std::ldexp(std::nearbyint(std::ldexp(x, 40)), -40); };
  int zero = 0, naive_wrong = 0;
  for (int n = 0; n < 20000; ++n) {
    const int s = scale(rng);
    double a[2] = {snap(coord(rng)), snap(coord(rng))}, b[2] = {snap(coord(rng)), snap(coord(rng))};
    const double w = coin(rng) ? small(rng) : weight(rng);
    const bool nudge = coin(rng);
    double c[2] = {step(snap(a[0] + w * (b[0] - a[0])), nudge ? ulps(rng) : 0),
                   step(snap(a[1] + w * (b[1] - a[1])), nudge ? ulps(rng) : 0)};
    for (double* p : {a, b, c})
      for (int k = 0; k < 2; ++k) p[k] = std::ldexp(p[k], s);
    const int expected = reference_orient2d(a, b, c);
    ASSERT_EQ(st::orient2d(a, b, c), expected) << n;
    ASSERT_EQ(st::orient2d(b, a, c), -expected) << n;
    ASSERT_EQ(st::orient2d(c, a, b), expected) << n;
    naive_wrong += naive_orient2d(a, b, c) != expected;
    zero += expected == 0;
  }
  EXPECT_GT(zero, 100);
  EXPECT_GT(naive_wrong, 10);
}

// Nearly degenerate integer configurations, scaled per axis by powers of two (exact, and a positive
// diagonal scaling keeps the sign): coordinates from subnormal to near overflow, and magnitudes
// spanning up to 2000 binary orders, which the exact path must handle by scaling or big integers.
TEST(Orient3d, ExtremeMagnitudesAndSpansKeepTheSign) {
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<std::int64_t> xy(-(std::int64_t{1} << 36), std::int64_t{1} << 36);
  std::uniform_int_distribution<int> small(-3, 3), nudge(-1, 1);
  const int exponents[] = {-1060, -600, -200, 0, 200, 600, 950};
  int checked = 0;
  for (int n = 0; n < 12; ++n) {
    // Points on the plane z = z0 - nx x - ny y, the last one nudged by -1, 0 or +1 in z.
    const std::int64_t nx = small(rng), ny = small(rng), z0 = xy(rng);
    std::int64_t p[4][3];
    for (auto& q : p) {
      q[0] = xy(rng);
      q[1] = xy(rng);
      q[2] = z0 - nx * q[0] - ny * q[1];
    }
    p[3][2] += nudge(rng);
    Vec3 base[4];
    for (int i = 0; i < 4; ++i) base[i] = Vec3(double(p[i][0]), double(p[i][1]), double(p[i][2]));
    const int expected = reference_orient3d(base[0], base[1], base[2], base[3]);
    ASSERT_EQ(st::orient3d(base[0], base[1], base[2], base[3]), expected);
    for (int ex : exponents)
      for (int ey : exponents)
        for (int ez : exponents) {
          Vec3 s[4];
          for (int i = 0; i < 4; ++i)
            s[i] = Vec3(std::ldexp(base[i][0], ex), std::ldexp(base[i][1], ey), std::ldexp(base[i][2], ez));
          ASSERT_EQ(st::orient3d(s[0], s[1], s[2], s[3]), expected) << n << " " << ex << " " << ey << " " << ez;
          ASSERT_EQ(st::orient3d(s[1], s[0], s[2], s[3]), -expected);
          ASSERT_EQ(st::PlaneOrientation(s[0], s[1], s[2])(s[3]), expected);
          ++checked;
        }
  }
  EXPECT_EQ(checked, 12 * 343);
}

TEST(Orient2d, ExtremeMagnitudesAndSpansKeepTheSign) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<std::int64_t> xs(-(std::int64_t{1} << 50), std::int64_t{1} << 50);
  std::uniform_int_distribution<int> slope(-5, 5), nudge(-1, 1);
  const int exponents[] = {-1074 + 1, -1030, -700, -100, 0, 100, 700, 960};
  for (int n = 0; n < 40; ++n) {
    // Points on y = y0 + m x, the last nudged; |y| < 2^53 keeps them exact doubles.
    const std::int64_t m = slope(rng), y0 = xs(rng) / 8;
    std::int64_t p[3][2];
    for (auto& q : p) {
      q[0] = xs(rng) / 8;
      q[1] = y0 + m * q[0];
    }
    p[2][1] += nudge(rng);
    double base[3][2];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 2; ++k) base[i][k] = double(p[i][k]);
    const int expected = reference_orient2d(base[0], base[1], base[2]);
    for (int ex : exponents)
      for (int ey : exponents) {
        if (ex < -1060 || ey < -1060) continue; // keep 2^50-sized integers exact
        double s[3][2];
        for (int i = 0; i < 3; ++i) {
          s[i][0] = std::ldexp(base[i][0], ex);
          s[i][1] = std::ldexp(base[i][1], ey);
        }
        ASSERT_EQ(st::orient2d(s[0], s[1], s[2]), expected) << n << " " << ex << " " << ey;
        ASSERT_EQ(st::orient2d(s[1], s[0], s[2]), -expected);
      }
  }
  // Tiny integers right at the bottom of the subnormal range.
  const double a[2] = {0, 0}, b[2] = {3 * 0x1p-1074, 0x1p-1074}, c[2] = {6 * 0x1p-1074, 2 * 0x1p-1074};
  const double c_up[2] = {6 * 0x1p-1074, 3 * 0x1p-1074};
  EXPECT_EQ(st::orient2d(a, b, c), 0);
  EXPECT_EQ(st::orient2d(a, b, c_up), 1);
}

// Mixed magnitudes inside one call: a huge and a tiny extent on one plane.
TEST(Orient3d, HugeAndTinyCoordinatesInOneCall) {
  const Vec3 a(0, 0, 0), b(0x1p900, 0, 0), c(0, 0x1p-900, 0);
  EXPECT_EQ(st::orient3d(a, b, c, Vec3(0x1p-1074, 0x1p-1074, 0)), 0);
  EXPECT_EQ(st::orient3d(a, b, c, Vec3(0x1p1000, -0x1p-1000, 0x1p-1074)), -1);
  EXPECT_EQ(st::orient3d(a, b, c, Vec3(0x1p1000, -0x1p-1000, -0x1p-1074)), 1);
  // A plane through huge points, tilted by a tiny amount: d at height 2^-1074 above z = 0 ...
  const Vec3 p(-0x1p1000, -0x1p1000, 0), q(0x1p1000, -0x1p1000, 0), r(0, 0x1p1000, 0);
  EXPECT_EQ(st::orient3d(p, q, r, Vec3(0x1p-500, 0x1p-600, 0x1p-1074)), -1);
  EXPECT_EQ(st::orient3d(p, q, r, Vec3(0x1p-500, 0x1p-600, 0)), 0);
  // ... and with the plane itself tilted so that its height at d is exactly d's height.
  const Vec3 r_tilted(0, 0x1p1000, 0x1p-73); // height 2^-73 (y + 2^1000) / 2^1001
  EXPECT_EQ(st::orient3d(p, q, r_tilted, Vec3(0, -0x1p1000, 0)), 0);
  EXPECT_EQ(st::orient3d(p, q, r_tilted, Vec3(0, -0x1p1000, 0x1p-1074)), -1);
  EXPECT_EQ(st::orient3d(p, q, r_tilted, Vec3(5, 0, 0x1p-74)), 0);         // on the plane
  EXPECT_EQ(st::orient3d(p, q, r_tilted, Vec3(5, 0x1p-1000, 0x1p-74)), 1); // just below it
  EXPECT_EQ(st::orient3d(p, q, r_tilted, Vec3(5, -0x1p-1000, 0x1p-74)), -1);
  // One plane's filter, whose products overflow or underflow here, falls back to the exact sign.
  const std::array<std::array<Vec3, 4>, 10> calls = {{{a, b, c, Vec3(0x1p-1074, 0x1p-1074, 0)},
                                                      {a, b, c, Vec3(0x1p1000, -0x1p-1000, 0x1p-1074)},
                                                      {a, b, c, Vec3(0x1p1000, -0x1p-1000, -0x1p-1074)},
                                                      {p, q, r, Vec3(0x1p-500, 0x1p-600, 0x1p-1074)},
                                                      {p, q, r, Vec3(0x1p-500, 0x1p-600, 0)},
                                                      {p, q, r_tilted, Vec3(0, -0x1p1000, 0)},
                                                      {p, q, r_tilted, Vec3(0, -0x1p1000, 0x1p-1074)},
                                                      {p, q, r_tilted, Vec3(5, 0, 0x1p-74)},
                                                      {p, q, r_tilted, Vec3(5, 0x1p-1000, 0x1p-74)},
                                                      {p, q, r_tilted, Vec3(5, -0x1p-1000, 0x1p-74)}}};
  for (const auto& [x, y, z, d] : calls) EXPECT_EQ(st::PlaneOrientation(x, y, z)(d), st::orient3d(x, y, z, d));
}

// The coordinates a Boolean meets: float32 values of a template in mm, one face's plane against the
// corners of many faces, exactly on it (integer combinations on a grid), an ulp off it, and anywhere.
TEST(PlaneOrientation, OnePlaneAgainstManyPointsGivesOrient3dsSign) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> coord(-60.0, 60.0);
  std::uniform_int_distribution<int> small(-3, 3), ulps(-1, 1);
  auto grid = [](double x) { return std::ldexp(std::nearbyint(std::ldexp(x, 12)), -12); }; // float32-exact
  int zero = 0, nonzero = 0;
  for (int n = 0; n < 2000; ++n) {
    const Vec3 a(grid(coord(rng)), grid(coord(rng)), grid(coord(rng)));
    const Vec3 b(grid(coord(rng)), grid(coord(rng)), grid(coord(rng)));
    const Vec3 c(grid(coord(rng)), grid(coord(rng)), grid(coord(rng)));
    const st::PlaneOrientation plane(a, b, c);
    for (int m = 0; m < 20; ++m) {
      Vec3 d = m % 2 == 0 ? Vec3(a + small(rng) * (b - a) + small(rng) * (c - a))
                          : Vec3(grid(coord(rng)), grid(coord(rng)), grid(coord(rng)));
      if (m % 4 == 2)
        for (int k = 0; k < 3; ++k) d[k] = step(d[k], ulps(rng));
      const int expected = reference_orient3d(a, b, c, d);
      ASSERT_EQ(plane(d), expected) << n << " " << m;
      (expected == 0 ? zero : nonzero)++;
    }
  }
  EXPECT_GT(zero, 5000);
  EXPECT_GT(nonzero, 20000);
}
