#include "st/core/predicates.h"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

// The error-free transformations below are only error free under IEEE semantics.
#if defined(__FAST_MATH__)
#error "predicates.cpp relies on exact IEEE rounding: do not compile it with -ffast-math"
#endif
#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "predicates.cpp needs doubles evaluated in double precision (FLT_EVAL_METHOD == 0: SSE2, not x87)"
#endif

namespace st {
namespace {

// ---- error bounds ---------------------------------------------------------------------------------
//
// Shewchuk's bounds with eps = 2^-53 (half an ulp of 1), padded by a few eps^2 (harmless, and it
// covers any doubt about the rounding of the bound itself):
//   A: the plain double evaluation, relative to the permanent (the determinant with every product
//      replaced by its absolute value);
//   B: the determinant of the rounded differences, evaluated exactly, relative to the permanent;
//   C: B plus the first-order correction for the differences' rounding errors, relative to the
//      permanent, and the error of the estimate of the B expansion, relative to its value.
// The relative bounds hold while nothing underflows. The filter (stage A) runs on the raw input, where
// a product may underflow to a subnormal with an absolute error of up to 2^-1075: it only accepts a
// sign when the determinant clears the bound by more than 2^-1020 (|adz| + |bdz| + |cdz| + 1), which
// exceeds any such error, with normal-range arithmetic only (subnormal operands would cost ~100 cycles
// on many processors). The later stages run on input scaled into a range where nothing underflows or
// overflows (see prepare).
//
// Overflow makes the rounded determinant or its bound inf or NaN, which fails the filter's comparison
// and sends the call to the exact path.

constexpr double kEps = 0x1p-53;
constexpr double kErrBound2A = (3.0 + 64.0 * kEps) * kEps;
constexpr double kErrBound2B = (2.0 + 32.0 * kEps) * kEps;
constexpr double kErrBound2C = (9.0 + 128.0 * kEps) * kEps * kEps;
constexpr double kErrBound3A = (7.0 + 128.0 * kEps) * kEps;
constexpr double kErrBound3B = (3.0 + 64.0 * kEps) * kEps;
constexpr double kErrBound3C = (26.0 + 512.0 * kEps) * kEps * kEps;
constexpr double kResultErrBound = (3.0 + 16.0 * kEps) * kEps;
constexpr double kUnderflowMargin = 0x1p-1020;

inline int sign_of(double x) { return (x > 0.0) - (x < 0.0); }

// ---- error-free transformations -----------------------------------------------------------------

// x + y == a + b exactly, x = fl(a + b).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double b_virtual = x - a;
  const double a_virtual = x - b_virtual;
  y = (a - a_virtual) + (b - b_virtual);
}

// x + y == a - b exactly, x = fl(a - b).
inline void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double b_virtual = a - x;
  const double a_virtual = x + b_virtual;
  y = (a - a_virtual) + (b_virtual - b);
}

// x + y == a * b exactly, x = fl(a * b), while the error term does not underflow. With hardware FMA
// the error term is one fused multiply-add; without it (baseline x86-64 turns std::fma into a library
// call) it comes from Dekker's product of the halves split off by Veltkamp's method, which is exact
// under the same condition. The FMA branch is also the one taken whenever the compiler may contract
// a * b + c into an FMA, which would break the split arithmetic.
#if defined(__FP_FAST_FMA) || defined(FP_FAST_FMA)
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}
#else
inline void split(double a, double& hi, double& lo) {
  const double c = 134217729.0 * a; // 2^27 + 1
  const double big = c - a;
  hi = c - big;
  lo = a - hi;
}
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  double ahi, alo, bhi, blo;
  split(a, ahi, alo);
  split(b, bhi, blo);
  const double err1 = x - ahi * bhi;
  const double err2 = err1 - alo * bhi;
  const double err3 = err2 - ahi * blo;
  y = alo * blo - err3;
}
#endif

// ---- floating-point expansions ------------------------------------------------------------------
//
// An expansion is an array of nonoverlapping doubles sorted by increasing magnitude whose exact sum
// is the represented value; zero components are dropped, so the empty expansion is zero and the sign
// is the sign of the last component.

// h = a - b as an expansion of length <= 2. Returns the length.
inline int diff_expansion(double a, double b, double* h) {
  double x, y;
  two_diff(a, b, x, y);
  int n = 0;
  if (y != 0.0) h[n++] = y;
  if (x != 0.0) h[n++] = x;
  return n;
}

// h = e + f (Shewchuk's Fast-Expansion-Sum with zero elimination; Two-Sum throughout). h must not
// alias e or f and holds elen + flen components.
int expansion_sum(int elen, const double* e, int flen, const double* f, double* h) {
  int ei = 0, fi = 0, hn = 0;
  auto next = [&]() {
    if (fi >= flen || (ei < elen && std::fabs(e[ei]) < std::fabs(f[fi]))) return e[ei++];
    return f[fi++];
  };
  if (elen + flen == 0) return 0;
  double q = next();
  while (ei < elen || fi < flen) {
    const double g = next();
    double x, y;
    two_sum(q, g, x, y);
    if (y != 0.0) h[hn++] = y;
    q = x;
  }
  if (q != 0.0) h[hn++] = q;
  return hn;
}

// h = b * e (Shewchuk's Scale-Expansion with zero elimination). h holds 2 * elen components.
int scale_expansion(int elen, const double* e, double b, double* h) {
  if (elen == 0 || b == 0.0) return 0;
  int hn = 0;
  double q, lo;
  two_product(e[0], b, q, lo);
  if (lo != 0.0) h[hn++] = lo;
  for (int i = 1; i < elen; ++i) {
    double hi_product, lo_product, sum, err;
    two_product(e[i], b, hi_product, lo_product);
    two_sum(q, lo_product, sum, err);
    if (err != 0.0) h[hn++] = err;
    two_sum(hi_product, sum, q, err);
    if (err != 0.0) h[hn++] = err;
  }
  if (q != 0.0) h[hn++] = q;
  return hn;
}

constexpr int kMaxFactor = 16; // longest e passed to product_expansion

// h = e * f for f of length <= 2 (a difference). h holds 4 * elen components.
int product_expansion(int elen, const double* e, int flen, const double* f, double* h) {
  if (flen == 0 || elen == 0) return 0;
  if (flen == 1) return scale_expansion(elen, e, f[0], h);
  double p0[2 * kMaxFactor], p1[2 * kMaxFactor];
  const int n0 = scale_expansion(elen, e, f[0], p0);
  const int n1 = scale_expansion(elen, e, f[1], p1);
  return expansion_sum(n0, p0, n1, p1, h);
}

// h = e1 * f1 - e2 * f2 for expansions of length <= 2. h holds 16 components.
int cross_difference(int e1n, const double* e1, int f1n, const double* f1, int e2n, const double* e2, int f2n,
                     const double* f2, double* h) {
  double left[8], right[8];
  const int ln = product_expansion(e1n, e1, f1n, f1, left);
  const int rn = product_expansion(e2n, e2, f2n, f2, right);
  for (int i = 0; i < rn; ++i) right[i] = -right[i];
  return expansion_sum(ln, left, rn, right, h);
}

inline int expansion_sign(int n, const double* e) {
  if (n == 0) return 0;
  return e[n - 1] > 0.0 ? 1 : -1;
}

// ---- big integers (only for inputs spanning a huge range of magnitudes) -------------------------

struct BigInt {
  int sign = 0;                     // -1, 0, +1
  std::vector<std::uint32_t> limbs; // magnitude, little endian, no leading zero limbs
};

void trim(std::vector<std::uint32_t>& v) {
  while (!v.empty() && v.back() == 0) v.pop_back();
}

int compare_magnitude(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
  if (a.size() != b.size()) return a.size() < b.size() ? -1 : 1;
  for (std::size_t i = a.size(); i-- > 0;)
    if (a[i] != b[i]) return a[i] < b[i] ? -1 : 1;
  return 0;
}

std::vector<std::uint32_t> add_magnitude(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
  std::vector<std::uint32_t> r(std::max(a.size(), b.size()) + 1, 0);
  std::uint64_t carry = 0;
  for (std::size_t i = 0; i + 1 < r.size(); ++i) {
    const std::uint64_t s = carry + (i < a.size() ? a[i] : 0) + (i < b.size() ? b[i] : 0);
    r[i] = static_cast<std::uint32_t>(s);
    carry = s >> 32;
  }
  r.back() = static_cast<std::uint32_t>(carry);
  trim(r);
  return r;
}

// a - b for |a| >= |b|.
std::vector<std::uint32_t> subtract_magnitude(const std::vector<std::uint32_t>& a,
                                              const std::vector<std::uint32_t>& b) {
  std::vector<std::uint32_t> r(a.size(), 0);
  std::int64_t borrow = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    std::int64_t d = static_cast<std::int64_t>(a[i]) - (i < b.size() ? b[i] : 0) - borrow;
    borrow = d < 0 ? 1 : 0;
    if (d < 0) d += std::int64_t{1} << 32;
    r[i] = static_cast<std::uint32_t>(d);
  }
  trim(r);
  return r;
}

BigInt add(const BigInt& a, const BigInt& b) {
  if (a.sign == 0) return b;
  if (b.sign == 0) return a;
  if (a.sign == b.sign) return {a.sign, add_magnitude(a.limbs, b.limbs)};
  const int c = compare_magnitude(a.limbs, b.limbs);
  if (c == 0) return {};
  if (c > 0) return {a.sign, subtract_magnitude(a.limbs, b.limbs)};
  return {b.sign, subtract_magnitude(b.limbs, a.limbs)};
}

BigInt negate(BigInt a) {
  a.sign = -a.sign;
  return a;
}

BigInt subtract(const BigInt& a, const BigInt& b) { return add(a, negate(b)); }

BigInt multiply(const BigInt& a, const BigInt& b) {
  if (a.sign == 0 || b.sign == 0) return {};
  std::vector<std::uint32_t> r(a.limbs.size() + b.limbs.size(), 0);
  for (std::size_t i = 0; i < a.limbs.size(); ++i) {
    std::uint64_t carry = 0;
    for (std::size_t j = 0; j < b.limbs.size(); ++j) {
      const std::uint64_t t = static_cast<std::uint64_t>(a.limbs[i]) * b.limbs[j] + r[i + j] + carry;
      r[i + j] = static_cast<std::uint32_t>(t);
      carry = t >> 32;
    }
    r[i + b.limbs.size()] = static_cast<std::uint32_t>(carry);
  }
  trim(r);
  return {a.sign * b.sign, std::move(r)};
}

// The exponent of the lowest bit of the 53-bit integer significand of x != 0: |x| = m * 2^e.
int significand_exponent(double x) {
  int e;
  std::frexp(x, &e);
  return e - 53;
}

// x / 2^base as a big integer; x must be a multiple of 2^base.
BigInt big_from_double(double x, int base) {
  if (x == 0.0) return {};
  int e;
  const double f = std::frexp(std::fabs(x), &e);
  const auto m = static_cast<std::uint64_t>(std::ldexp(f, 53));
  const int shift = e - 53 - base;
  BigInt r;
  r.sign = x > 0.0 ? 1 : -1;
  r.limbs.assign(static_cast<std::size_t>(shift / 32) + 3, 0);
  const int bit = shift % 32;
  const std::size_t word = static_cast<std::size_t>(shift / 32);
  // m < 2^53, shifted by < 32 bits: spread over three 32-bit limbs.
  const std::uint64_t low = (m << bit) & 0xffffffffu;
  const std::uint64_t rest = bit == 0 ? (m >> 32) : (m >> (32 - bit));
  r.limbs[word] = static_cast<std::uint32_t>(low);
  r.limbs[word + 1] = static_cast<std::uint32_t>(rest & 0xffffffffu);
  r.limbs[word + 2] = static_cast<std::uint32_t>(rest >> 32);
  trim(r.limbs);
  return r;
}

// Converts n coordinates to big integers in units of the smallest significand bit among them.
std::vector<BigInt> to_big_integers(const double* p, int n) {
  int base = INT_MAX;
  for (int i = 0; i < n; ++i)
    if (p[i] != 0.0) base = std::min(base, significand_exponent(p[i]));
  std::vector<BigInt> v;
  v.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) v.push_back(big_from_double(p[i], base));
  return v;
}

int orient2d_bigint(const double* p) {
  const std::vector<BigInt> v = to_big_integers(p, 6);
  const BigInt acx = subtract(v[0], v[4]), acy = subtract(v[1], v[5]);
  const BigInt bcx = subtract(v[2], v[4]), bcy = subtract(v[3], v[5]);
  return subtract(multiply(acx, bcy), multiply(acy, bcx)).sign;
}

int orient3d_bigint(const double* p) {
  const std::vector<BigInt> v = to_big_integers(p, 12);
  BigInt ad[3], bd[3], cd[3];
  for (int k = 0; k < 3; ++k) {
    ad[k] = subtract(v[k], v[9 + k]);
    bd[k] = subtract(v[3 + k], v[9 + k]);
    cd[k] = subtract(v[6 + k], v[9 + k]);
  }
  const BigInt ma = subtract(multiply(bd[0], cd[1]), multiply(cd[0], bd[1]));
  const BigInt mb = subtract(multiply(cd[0], ad[1]), multiply(ad[0], cd[1]));
  const BigInt mc = subtract(multiply(ad[0], bd[1]), multiply(bd[0], ad[1]));
  return add(add(multiply(ad[2], ma), multiply(bd[2], mb)), multiply(cd[2], mc)).sign;
}

// ---- exact evaluation ---------------------------------------------------------------------------
//
// Every value the expansion arithmetic produces is an integer multiple of the product of the input
// grids (the lowest set bits of the coordinates) and at most a small multiple of the largest input
// raised to the degree of the determinant. So the arithmetic is exact, and the floating-point
// estimates of stages B and C stay in the normal range, when every nonzero coordinate is a multiple of
// 2^min_bit and smaller than 2^max_exponent: for orient3d (degree 3) 2^-300 and 2^330 (products of
// three grid values >= 2^-900, values < 2^1000), for orient2d 2^-450 and 2^500. Other input is scaled
// by a power of two (exact, and the sign of the determinant does not change); input spanning too many
// binary orders for that goes to the big integers.

struct BitRange {
  int top;    // exponent of the highest set bit of a nonzero double
  int bottom; // exponent of its lowest set bit
};

inline BitRange bit_range(double x) {
  const auto bits = std::bit_cast<std::uint64_t>(x);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  std::uint64_t mantissa = bits & ((std::uint64_t{1} << 52) - 1);
  if (biased == 0) return {-1074 + 63 - std::countl_zero(mantissa), -1074 + std::countr_zero(mantissa)};
  mantissa |= std::uint64_t{1} << 52;
  return {biased - 1023, biased - 1075 + std::countr_zero(mantissa)};
}

enum class Route { kZero, kExpansion, kBigInt, kNonFinite };

// Decides how to evaluate exactly and scales p in place into [2^min_bit, 2^max_exponent) when needed.
Route prepare(double* p, int n, int min_bit, int max_exponent) {
  int top = INT_MIN, bottom = INT_MAX;
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(p[i])) return Route::kNonFinite;
    if (p[i] == 0.0) continue;
    const BitRange r = bit_range(p[i]);
    top = std::max(top, r.top);
    bottom = std::min(bottom, r.bottom);
  }
  if (top == INT_MIN) return Route::kZero;
  if (top < max_exponent && bottom >= min_bit) return Route::kExpansion;
  if (top - bottom >= max_exponent - min_bit - 1) return Route::kBigInt;
  const int shift = std::max(min_bit - bottom, std::min(0, max_exponent - 1 - top));
  for (int i = 0; i < n; ++i) p[i] = std::ldexp(p[i], shift);
  return Route::kExpansion;
}

inline double estimate(int n, const double* e) {
  double q = 0.0;
  for (int i = 0; i < n; ++i) q += e[i];
  return q;
}

// e1 * f1 - e2 * f2 for doubles, as an expansion of length <= 4 in h.
inline int two_two_cross(double e1, double f1, double e2, double f2, double* h, double& p1, double& p2) {
  double l[2], r[2], t;
  two_product(e1, f1, p1, t);
  int ln = 0, rn = 0;
  if (t != 0.0) l[ln++] = t;
  if (p1 != 0.0) l[ln++] = p1;
  two_product(e2, f2, p2, t);
  if (t != 0.0) r[rn++] = -t;
  if (p2 != 0.0) r[rn++] = -p2;
  return expansion_sum(ln, l, rn, r, h);
}

// Stage D of orient2d on prepared coordinates: the determinant of the exact differences.
int orient2d_expansion(const double* p) {
  double acx[2], acy[2], bcx[2], bcy[2];
  const int acxn = diff_expansion(p[0], p[4], acx), acyn = diff_expansion(p[1], p[5], acy);
  const int bcxn = diff_expansion(p[2], p[4], bcx), bcyn = diff_expansion(p[3], p[5], bcy);
  double det[16];
  const int n = cross_difference(acxn, acx, bcyn, bcy, acyn, acy, bcxn, bcx, det);
  return expansion_sign(n, det);
}

// Stages B, C and D of orient2d on prepared coordinates (Shewchuk's orient2dadapt).
int orient2d_adaptive(const double* p) {
  double acx, acy, bcx, bcy, acxtail, acytail, bcxtail, bcytail;
  two_diff(p[0], p[4], acx, acxtail);
  two_diff(p[1], p[5], acy, acytail);
  two_diff(p[2], p[4], bcx, bcxtail);
  two_diff(p[3], p[5], bcy, bcytail);
  double b[4], detleft, detright;
  const int bn = two_two_cross(acx, bcy, acy, bcx, b, detleft, detright);
  double det = estimate(bn, b);
  const double detsum = std::fabs(detleft) + std::fabs(detright);
  if (std::fabs(det) > kErrBound2B * detsum) return sign_of(det);
  if (acxtail == 0.0 && acytail == 0.0 && bcxtail == 0.0 && bcytail == 0.0) return expansion_sign(bn, b);
  const double errbound = kErrBound2C * detsum + kResultErrBound * std::fabs(det);
  det += (acx * bcytail + bcy * acxtail) - (acy * bcxtail + bcx * acytail);
  if (std::fabs(det) > errbound) return sign_of(det);
  return orient2d_expansion(p);
}

int orient2d_exact(const double* a, const double* b, const double* c) {
  // Repeated points, or all on an axis-parallel line.
  if ((a[0] == b[0] && a[1] == b[1]) || (a[0] == c[0] && a[1] == c[1]) || (b[0] == c[0] && b[1] == c[1])) return 0;
  if ((a[0] == b[0] && a[0] == c[0]) || (a[1] == b[1] && a[1] == c[1])) return 0;
  double p[6] = {a[0], a[1], b[0], b[1], c[0], c[1]};
  switch (prepare(p, 6, -450, 500)) {
  case Route::kZero:
  case Route::kNonFinite: return 0;
  case Route::kBigInt: return orient2d_bigint(p);
  case Route::kExpansion: break;
  }
  return orient2d_adaptive(p);
}

// Stage D of orient3d on prepared coordinates: the determinant of the exact differences to d.
int orient3d_expansion(const double* p) {
  double ad[3][2], bd[3][2], cd[3][2];
  int adn[3], bdn[3], cdn[3];
  for (int k = 0; k < 3; ++k) {
    adn[k] = diff_expansion(p[k], p[9 + k], ad[k]);
    bdn[k] = diff_expansion(p[3 + k], p[9 + k], bd[k]);
    cdn[k] = diff_expansion(p[6 + k], p[9 + k], cd[k]);
  }
  // det = adz (bdx cdy - cdx bdy) + bdz (cdx ady - adx cdy) + cdz (adx bdy - bdx ady)
  double minor[16], ta[64], tb[64], tc[64];
  int tan = 0, tbn = 0, tcn = 0;
  if (adn[2] != 0) {
    const int mn = cross_difference(bdn[0], bd[0], cdn[1], cd[1], cdn[0], cd[0], bdn[1], bd[1], minor);
    tan = product_expansion(mn, minor, adn[2], ad[2], ta);
  }
  if (bdn[2] != 0) {
    const int mn = cross_difference(cdn[0], cd[0], adn[1], ad[1], adn[0], ad[0], cdn[1], cd[1], minor);
    tbn = product_expansion(mn, minor, bdn[2], bd[2], tb);
  }
  if (cdn[2] != 0) {
    const int mn = cross_difference(adn[0], ad[0], bdn[1], bd[1], bdn[0], bd[0], adn[1], ad[1], minor);
    tcn = product_expansion(mn, minor, cdn[2], cd[2], tc);
  }
  double ab[128], det[192];
  const int abn = expansion_sum(tan, ta, tbn, tb, ab);
  const int n = expansion_sum(abn, ab, tcn, tc, det);
  return expansion_sign(n, det);
}

// Stages B, C and D of orient3d on prepared coordinates (Shewchuk's orient3dadapt).
int orient3d_adaptive(const double* p) {
  double adx, bdx, cdx, ady, bdy, cdy, adz, bdz, cdz;
  double adxtail, bdxtail, cdxtail, adytail, bdytail, cdytail, adztail, bdztail, cdztail;
  two_diff(p[0], p[9], adx, adxtail);
  two_diff(p[3], p[9], bdx, bdxtail);
  two_diff(p[6], p[9], cdx, cdxtail);
  two_diff(p[1], p[10], ady, adytail);
  two_diff(p[4], p[10], bdy, bdytail);
  two_diff(p[7], p[10], cdy, cdytail);
  two_diff(p[2], p[11], adz, adztail);
  two_diff(p[5], p[11], bdz, bdztail);
  two_diff(p[8], p[11], cdz, cdztail);

  double bc[4], ca[4], ab[4];
  double bdxcdy, cdxbdy, cdxady, adxcdy, adxbdy, bdxady;
  const int bcn = two_two_cross(bdx, cdy, cdx, bdy, bc, bdxcdy, cdxbdy);
  const int can = two_two_cross(cdx, ady, adx, cdy, ca, cdxady, adxcdy);
  const int abn = two_two_cross(adx, bdy, bdx, ady, ab, adxbdy, bdxady);
  double adet[8], bdet[8], cdet[8], abdet[16], fin[24];
  const int an = scale_expansion(bcn, bc, adz, adet);
  const int bn = scale_expansion(can, ca, bdz, bdet);
  const int cn = scale_expansion(abn, ab, cdz, cdet);
  const int abdn = expansion_sum(an, adet, bn, bdet, abdet);
  const int finn = expansion_sum(abdn, abdet, cn, cdet, fin);
  double det = estimate(finn, fin);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * std::fabs(adz) +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * std::fabs(bdz) +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * std::fabs(cdz);
  if (std::fabs(det) > kErrBound3B * permanent) return sign_of(det);
  if (adxtail == 0.0 && bdxtail == 0.0 && cdxtail == 0.0 && adytail == 0.0 && bdytail == 0.0 && cdytail == 0.0 &&
      adztail == 0.0 && bdztail == 0.0 && cdztail == 0.0)
    return expansion_sign(finn, fin); // the differences were exact, so is fin

  const double errbound = kErrBound3C * permanent + kResultErrBound * std::fabs(det);
  det +=
      (adz * ((bdx * cdytail + cdy * bdxtail) - (bdy * cdxtail + cdx * bdytail)) + adztail * (bdx * cdy - bdy * cdx)) +
      (bdz * ((cdx * adytail + ady * cdxtail) - (cdy * adxtail + adx * cdytail)) + bdztail * (cdx * ady - cdy * adx)) +
      (cdz * ((adx * bdytail + bdy * adxtail) - (ady * bdxtail + bdx * adytail)) + cdztail * (adx * bdy - ady * bdx));
  if (std::fabs(det) > errbound) return sign_of(det);
  return orient3d_expansion(p);
}

inline bool same3(const double* a, const double* b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

int orient3d_exact(const double* a, const double* b, const double* c, const double* d) {
  // Repeated points, or a coordinate constant over all four points (a zero column).
  if (same3(a, d) || same3(b, d) || same3(c, d) || same3(a, b) || same3(a, c) || same3(b, c)) return 0;
  for (int k = 0; k < 3; ++k)
    if (a[k] == d[k] && b[k] == d[k] && c[k] == d[k]) return 0;
  double p[12] = {a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2]};
  switch (prepare(p, 12, -300, 330)) {
  case Route::kZero:
  case Route::kNonFinite: return 0;
  case Route::kBigInt: return orient3d_bigint(p);
  case Route::kExpansion: break;
  }
  return orient3d_adaptive(p);
}

} // namespace

int orient2d(const double* a, const double* b, const double* c) {
  const double detleft = (a[0] - c[0]) * (b[1] - c[1]);
  const double detright = (a[1] - c[1]) * (b[0] - c[0]);
  const double det = detleft - detright;
  const double errbound = kErrBound2A * (std::fabs(detleft) + std::fabs(detright));
  if (std::fabs(det) - errbound > kUnderflowMargin) return sign_of(det);
  return orient2d_exact(a, b, c);
}

int orient3d(const Vec3& pa, const Vec3& pb, const Vec3& pc, const Vec3& pd) {
  const double* a = pa.data();
  const double* b = pb.data();
  const double* c = pc.data();
  const double* d = pd.data();
  const double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
  const double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
  const double adz = a[2] - d[2], bdz = b[2] - d[2], cdz = c[2] - d[2];
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double aadz = std::fabs(adz), abdz = std::fabs(bdz), acdz = std::fabs(cdz);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * aadz +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * abdz +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * acdz;
  const double errbound = kErrBound3A * permanent;
  if (std::fabs(det) - errbound > kUnderflowMargin * (aadz + abdz + acdz + 1.0)) return sign_of(det);
  return orient3d_exact(a, b, c, d);
}

PlaneOrientation::PlaneOrientation(const Vec3& a, const Vec3& b, const Vec3& c) : a_(a), b_(b), c_(c) {
  const double bax = b[0] - a[0], bay = b[1] - a[1], baz = b[2] - a[2];
  const double cax = c[0] - a[0], cay = c[1] - a[1], caz = c[2] - a[2];
  const double bay_caz = bay * caz, baz_cay = baz * cay;
  const double baz_cax = baz * cax, bax_caz = bax * caz;
  const double bax_cay = bax * cay, bay_cax = bay * cax;
  minor_ = Vec3(bay_caz - baz_cay, baz_cax - bax_caz, bax_cay - bay_cax);
  permanent_ = Vec3(std::fabs(bay_caz) + std::fabs(baz_cay), std::fabs(baz_cax) + std::fabs(bax_caz),
                    std::fabs(bax_cay) + std::fabs(bay_cax));
}

int PlaneOrientation::operator()(const Vec3& d) const {
  // det = (d - a) . ((b - a) x (c - a)) = -orient3d's determinant.
  const double dax = d[0] - a_[0], day = d[1] - a_[1], daz = d[2] - a_[2];
  const double det = dax * minor_[0] + day * minor_[1] + daz * minor_[2];
  const double adax = std::fabs(dax), aday = std::fabs(day), adaz = std::fabs(daz);
  const double errbound = kErrBound3A * (adax * permanent_[0] + aday * permanent_[1] + adaz * permanent_[2]);
  if (std::fabs(det) - errbound > kUnderflowMargin * (adax + aday + adaz + 1.0)) return -sign_of(det);
  return orient3d(a_, b_, c_, d);
}

} // namespace st
