#include "st/validate/stability.h"

#include "detail/format.h"
#include "validate/polytope.h"
#include "st/core/errors.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

namespace st {

namespace {

using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

/// An eigenvalue of sum a_i a_i^T below this leaves its motion free (every contact moves into or out
/// of the bone by less than 3e-5 per unit of motion); absolute, so that fewer contacts never free less.
constexpr double kFreeEigenvalue = 1e-9;

std::string direction_text(const Vec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.3f, %.3f, %.3f)", v.x(), v.y(), v.z());
  return buf;
}

/// Orthonormal basis (columns) of the null space of `m` (rows x n), by SVD with a relative threshold.
MatX null_space(const MatX& m, double threshold = 1e-9) {
  const Eigen::Index n = m.cols();
  if (m.rows() == 0) return MatX::Identity(n, n);
  const Eigen::JacobiSVD<MatX> svd(m, Eigen::ComputeFullV);
  const VecX& s = svd.singularValues();
  const double top = s.size() ? s(0) : 0.0;
  Eigen::Index rank = 0;
  while (rank < s.size() && s(rank) > threshold * std::max(top, 1.0)) ++rank;
  return svd.matrixV().rightCols(n - rank);
}

/// The order the contacts cut the section in. The vertices a cut makes and a later one removes are
/// the enumeration's cost; the final polytope is the same in any order. The rows farthest apart
/// (contacts whose normals or moment arms differ most) first, by farthest-point selection from the
/// first row, for up to 256 of them (a cost of 256 passes over the rows); the rest coarse to fine
/// along the sampling order (every 16th, 4th, then all), so that nearby contacts come late.
std::vector<std::size_t> cutting_order(const std::vector<Twist>& rows) {
  const std::size_t n = rows.size();
  std::vector<std::size_t> order;
  order.reserve(n);
  std::vector<char> taken(n, 0);
  std::vector<double> gap(n, std::numeric_limits<double>::infinity()); // to the nearest row taken
  for (std::size_t next = 0; order.size() < std::min<std::size_t>(n, 256);) {
    order.push_back(next);
    taken[next] = 1;
    double farthest = -1.0;
    for (std::size_t j = 0; j < n; ++j) {
      if (taken[j]) continue;
      gap[j] = std::min(gap[j], (rows[j] - rows[order.back()]).squaredNorm());
      if (gap[j] > farthest) farthest = gap[j], next = j; // ties: the lowest index
    }
  }
  for (const std::size_t stride : {16U, 4U, 1U})
    for (std::size_t i = 0; i < n; i += stride)
      if (!taken[i]) {
        taken[i] = 1;
        order.push_back(i);
      }
  return order;
}

Twist contact_row(const Contact& c, const Vec3& centroid, double scale) {
  Twist a;
  a.head<3>() = c.normal;
  a.tail<3>() = (c.point - centroid).cross(c.normal) / scale;
  return a;
}

} // namespace

std::string FreeMotion::describe() const {
  char buf[256];
  const std::string p = detail::where(point), dir = direction_text(direction);
  switch (kind) {
  case Kind::lift_off:
    return blocked ? "cannot lift off along " + dir + ": the bone holds it (an undercut)"
                   : "lifts off along " + dir + " (against the insertion direction)";
  case Kind::slide: std::snprintf(buf, sizeof buf, "slides along %s", dir.c_str()); break;
  case Kind::turn:
    std::snprintf(buf, sizeof buf, "turns about the axis through %s along %s", p.c_str(), dir.c_str());
    break;
  case Kind::screw:
    std::snprintf(buf, sizeof buf, "screws about the axis through %s along %s, %.3g mm per radian", p.c_str(),
                  dir.c_str(), pitch);
    break;
  }
  std::string text = buf;
  if (!keeps_contact) text += lift > 0.0 ? ", lifting off the bone" : ", lifting off part of the bone";
  return text;
}

FreeMotion describe_twist(const StabilityReport& report, const Twist& x, bool keeps_contact, double tolerance) {
  FreeMotion m;
  if (x.norm() == 0.0) return m; // no motion: a slide along +z of length 0, kept as the default
  m.twist = x.normalized();
  m.keeps_contact = keeps_contact;
  const Vec3 v = m.twist.head<3>(), w = m.twist.tail<3>() / report.scale;
  m.lift = keeps_contact ? 0.0 : std::max(0.0, -report.direction.dot(v));
  if (m.twist.tail<3>().norm() <= tolerance) {
    m.kind =
        v.normalized().dot(-report.direction) > 1.0 - tolerance ? FreeMotion::Kind::lift_off : FreeMotion::Kind::slide;
    m.direction = v.normalized();
    m.point = report.centroid;
    return m;
  }
  const double w2 = w.squaredNorm();
  m.direction = w.normalized();
  m.pitch = w.dot(v) / w2;
  m.point = report.centroid + w.cross(v) / w2;
  m.kind =
      std::abs(m.pitch) <= std::max(tolerance, 1e-3) * report.scale ? FreeMotion::Kind::turn : FreeMotion::Kind::screw;
  return m;
}

namespace {

/// sample_contacts() with the bone's vertex normals from normal_of(vertex).
template <class NormalOf>
std::vector<Contact> contacts_with(const TriangleMesh& inner, const AabbTree& bone, double reach, double spacing,
                                   const std::vector<std::uint8_t>& skip, bool toward_bone, NormalOf&& normal_of) {
  if (!(spacing > 0.0) || !std::isfinite(spacing)) throw InvalidInput("contacts: spacing must be > 0");
  std::vector<Contact> contacts;
  const double per_area = 1.0 / (spacing * spacing);
  double running = 0.0;
  std::size_t n = 0; // samples so far: the pattern's index
  // The R2 sequence (plastic number): well spread in the unit square, folded into the triangle.
  constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;
  for (Index f = 0; f < inner.face_count(); ++f) {
    if (f < skip.size() && skip[f]) continue;
    const Vec3 normal = toward_bone ? Vec3(-triangle_normal(inner, f)) : triangle_normal(inner, f);
    const double before = running;
    running += 0.5 * normal.norm() * per_area;
    const auto k = static_cast<std::size_t>(std::floor(running) - std::floor(before));
    const Triangle& t = inner.triangles[f];
    const Vec3 &a = inner.positions[t[0]], &b = inner.positions[t[1]], &c = inner.positions[t[2]];
    for (std::size_t j = 0; j < k; ++j, ++n) {
      double u = std::fmod(0.5 + a1 * static_cast<double>(n), 1.0),
             v = std::fmod(0.5 + a2 * static_cast<double>(n), 1.0);
      if (u + v > 1.0) {
        u = 1.0 - u;
        v = 1.0 - v;
      }
      const Vec3 p = a + u * (b - a) + v * (c - a);
      const auto cp = bone.closest_point(p, reach);
      if (!cp || cp->distance > reach) continue;
      const Triangle& bt = bone.mesh().triangles[cp->face];
      const Vec3 &b0 = bone.mesh().positions[bt[0]], &b1 = bone.mesh().positions[bt[1]],
                 &b2 = bone.mesh().positions[bt[2]];
      const Vec3 face = (b1 - b0).cross(b2 - b0);
      Vec3 nb = face;
      if (const double f2 = face.squaredNorm(); f2 > 0.0) { // barycentric weights of the closest point
        const Vec3 q = cp->point;
        const double w0 = (b1 - q).cross(b2 - q).dot(face) / f2, w1 = (b2 - q).cross(b0 - q).dot(face) / f2;
        const Vec3 smooth = w0 * normal_of(bt[0]) + w1 * normal_of(bt[1]) + (1.0 - w0 - w1) * normal_of(bt[2]);
        if (smooth.dot(face) > 0.0) nb = smooth;
      }
      if (nb.norm() == 0.0) nb = normal;
      if (nb.dot(normal) < 0.0) nb = -nb;
      if (nb.norm() == 0.0) continue;
      contacts.push_back({p, nb.normalized()});
    }
  }
  return contacts;
}

} // namespace

std::vector<Contact> sample_contacts(const TriangleMesh& inner, const AabbTree& bone, double reach, double spacing,
                                     const std::vector<std::uint8_t>& skip, bool toward_bone,
                                     const std::vector<Vec3>* bone_normals) {
  const std::vector<Vec3> own = bone_normals ? std::vector<Vec3>{} : vertex_normals(bone.mesh());
  const std::vector<Vec3>& normals = bone_normals ? *bone_normals : own;
  return contacts_with(inner, bone, reach, spacing, skip, toward_bone,
                       [&](Index v) -> const Vec3& { return normals[v]; });
}

StabilityReport analyse_stability(const std::vector<Contact>& contacts, const Vec3& direction,
                                  const StabilityOptions& options) {
  if (!direction.allFinite() || direction.norm() == 0.0)
    throw InvalidInput("stability: the insertion direction must be finite and non-zero");
  if (!(options.box > 0.0) || !std::isfinite(options.box)) throw InvalidInput("stability: box must be > 0");
  for (std::size_t i = 0; i < contacts.size(); ++i)
    if (!contacts[i].point.allFinite() || !contacts[i].normal.allFinite())
      throw InvalidInput("stability: contact " + std::to_string(i) + " is not finite");
  StabilityReport report;
  report.direction = direction.normalized();
  report.contacts = contacts.size();
  for (const Contact& c : contacts) report.centroid += c.point;
  if (!contacts.empty()) report.centroid /= static_cast<double>(contacts.size());
  if (options.centroid) report.centroid = *options.centroid;
  double spread = 0.0;
  for (const Contact& c : contacts) spread += (c.point - report.centroid).squaredNorm();
  report.scale = contacts.empty() ? 1.0 : std::sqrt(spread / static_cast<double>(contacts.size()));
  if (options.scale > 0.0) report.scale = options.scale;
  if (!(report.scale > 1e-9) || !std::isfinite(report.scale)) report.scale = 1.0;
  if (!report.centroid.allFinite()) throw InvalidInput("stability: the centroid must be finite");

  std::vector<Twist> rows;
  rows.reserve(contacts.size());
  Eigen::Matrix<double, 6, 6> m = Eigen::Matrix<double, 6, 6>::Zero();
  for (const Contact& c : contacts) {
    rows.push_back(contact_row(c, report.centroid, report.scale));
    m += rows.back() * rows.back().transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(m);
  std::vector<int> free_axes, held_axes;
  for (int k = 0; k < 6; ++k) (eigen.eigenvalues()(k) <= kFreeEigenvalue ? free_axes : held_axes).push_back(k);
  MatX linear(6, static_cast<Eigen::Index>(free_axes.size())), held(6, static_cast<Eigen::Index>(held_axes.size()));
  for (std::size_t k = 0; k < free_axes.size(); ++k)
    linear.col(static_cast<Eigen::Index>(k)) = eigen.eigenvectors().col(free_axes[k]);
  for (std::size_t k = 0; k < held_axes.size(); ++k)
    held.col(static_cast<Eigen::Index>(k)) = eigen.eigenvectors().col(held_axes[k]);

  // The linear part: its slides (no turn), then turns orthogonal to them.
  if (linear.cols() > 0) {
    const MatX slide_coeffs = null_space(linear.bottomRows(3));
    const MatX slides = linear * slide_coeffs;
    MatX turn_coeffs = null_space(slide_coeffs.transpose());
    const MatX turns = linear * turn_coeffs;
    for (Eigen::Index k = 0; k < slides.cols(); ++k) {
      Twist x = slides.col(k);
      if (-report.direction.dot(x.head<3>()) < 0.0) x = -x;
      report.free_motions.push_back(describe_twist(report, x, true));
    }
    for (Eigen::Index k = 0; k < turns.cols(); ++k) {
      Twist x = turns.col(k);
      if (x.tail<3>().dot(Vec3::Ones()) < 0.0) x = -x;
      report.free_motions.push_back(describe_twist(report, x, true));
    }
  }

  // The rest: the extreme rays of F within the held space, as the vertices of its section by
  // {g . y = 1}, g the sum of the contacts' rows there: every free motion outside the linear part
  // moves some contact off the bone and none into it, so g . y > 0 on F and the section is bounded
  // (the box only guards against motions held by less than 1 / box). z: coordinates in the section.
  Twist lift_row = Twist::Zero();
  lift_row.head<3>() = -report.direction;
  std::vector<VecX> rays; // unit, in held coordinates
  if (held.cols() > 0) {
    VecX g = VecX::Zero(held.cols());
    for (const Twist& a : rows) g += held.transpose() * a;
    g.normalize(); // the section's coordinates of order 1, whatever the number of contacts
    const VecX y0 = g;
    const MatX e = null_space(g.transpose()); // held.cols() x (held.cols() - 1), orthonormal
    stability_detail::Polytope p(e.cols(), options.box);
    bool empty = false;
    for (const std::size_t i : cutting_order(rows)) {
      const VecX b = held.transpose() * rows[i];
      const VecX h = e.transpose() * b;
      const double r = -b.dot(y0), hn = h.norm();
      if (hn <= 1e-12) {
        if (r > 1e-9) empty = true; // this contact blocks the whole section: nothing is free
      } else if (!p.cut(h / hn, r / hn)) {
        empty = true;
      }
      if (empty) break;
    }
    if (!empty)
      for (const VecX& z : p.vertices()) rays.push_back((y0 + e * z).normalized());
  }
  // Rise of each extreme free motion against the press; those that do not rise are free motions too.
  const VecX c = held.transpose() * lift_row;
  double least = std::numeric_limits<double>::infinity();
  VecX worst;
  std::vector<FreeMotion> level;
  for (const VecX& y : rays) {
    const double rise = c.dot(y);
    report.extreme_motions.push_back(held * y);
    if (rise < least) least = rise, worst = y;
    if (rise > 1e-9) continue;
    const Twist dir = held * y;
    const bool distinct = std::none_of(level.begin(), level.end(), [&](const FreeMotion& f) {
      return f.twist.dot(dir) > std::cos(15.0 * M_PI / 180.0);
    });
    if (distinct && level.size() < 4) {
      FreeMotion f = describe_twist(report, dir, false, 10.0 / options.box);
      f.lift = 0.0;
      level.push_back(f);
    }
  }
  report.free_motions.insert(report.free_motions.end(), level.begin(), level.end());

  report.lift_off_free =
      std::all_of(rows.begin(), rows.end(), [&](const Twist& a) { return a.dot(lift_row) >= -1e-6; });
  if (report.lift_off_free) report.free_motions.push_back(describe_twist(report, lift_row, false));

  // Bounded: every free motion rises against the press (the score is the least rise, > 0).
  report.bounded = linear.cols() == 0 && !rays.empty() && least > 1e-9;
  if (linear.cols() == 0 && rays.empty()) {
    report.score = 1.0; // nothing is free: held in every direction (it cannot come off either)
    report.worst_motion = describe_twist(report, lift_row, false);
    report.worst_motion.blocked = true;
  } else if (report.bounded) {
    report.score = std::clamp(least, 0.0, 1.0);
    report.worst_motion = describe_twist(report, held * worst, false);
    if (report.worst_motion.kind != FreeMotion::Kind::lift_off) // listed too: the free motion that rises least
      report.free_motions.insert(report.free_motions.begin(), report.worst_motion);
  } else {
    report.score = 0.0;
    report.worst_motion =
        report.free_motions.empty() ? describe_twist(report, lift_row, false) : report.free_motions.front();
    report.worst_motion.blocked = report.free_motions.empty() && !report.lift_off_free;
  }
  return report;
}

namespace {
/// A press can hold: there are extreme free motions and no motion keeps every contact (that one would
/// be free both ways, one of them not rising wherever the push is).
bool pressable(const StabilityReport& report) {
  return !report.extreme_motions.empty() && std::none_of(report.free_motions.begin(), report.free_motions.end(),
                                                         [](const FreeMotion& m) { return m.keeps_contact; });
}
} // namespace

double press_score(const StabilityReport& report, const Vec3& point) {
  if (!pressable(report)) return 0.0;
  Twist g;
  g.head<3>() = -report.direction;
  g.tail<3>() = -(point - report.centroid).cross(report.direction) / report.scale;
  double score = 1.0;
  for (const Twist& x : report.extreme_motions) score = std::min(score, g.dot(x));
  return std::max(score, 0.0);
}

PressPoint best_press_point(const StabilityReport& report, const std::vector<Vec3>& candidates) {
  // The rise of extreme motion x pushed at p is affine in p: alpha + beta . (p - c). Visited in order of
  // their lowest value over the candidates, the motions past the current minimum cannot lower it.
  double reach = 0.0;
  for (const Vec3& p : candidates) reach = std::max(reach, (p - report.centroid).norm());
  struct Rise {
    double alpha;
    Vec3 beta;
    double lowest;
  };
  std::vector<Rise> rises;
  for (const Twist& x : report.extreme_motions) {
    const Vec3 beta = -report.direction.cross(x.tail<3>()) / report.scale;
    const double alpha = -report.direction.dot(x.head<3>());
    rises.push_back({alpha, beta, alpha - beta.norm() * reach});
  }
  std::sort(rises.begin(), rises.end(), [](const Rise& a, const Rise& b) { return a.lowest < b.lowest; });
  // The score at p; below `floor` it stops early (and returns what it has, below floor).
  auto score_at = [&](const Vec3& p, double floor = -1.0) {
    if (!pressable(report)) return 0.0;
    double score = 1.0;
    for (const Rise& r : rises) {
      if (r.lowest >= score || score < floor) break;
      score = std::min(score, r.alpha + r.beta.dot(p - report.centroid));
    }
    return std::max(score, 0.0);
  };
  if (candidates.empty()) return {report.centroid, score_at(report.centroid)};
  // The best score, then among the candidates within 1e-3 of it the nearest to the line through the
  // centroid along the direction. A candidate already below the best so far less 1e-3 is out whatever
  // its exact score: every 16th is scored first, so that the best so far is high early.
  std::vector<double> scores(candidates.size(), -1.0);
  double top = 0.0;
  for (const std::size_t start : {0U, 1U})
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if ((i % 16 == 0) != (start == 0)) continue;
      scores[i] = score_at(candidates[i], top - 1e-3);
      top = std::max(top, scores[i]);
    }
  PressPoint best{candidates.front(), scores.front()};
  double best_off = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (scores[i] < top - 1e-3) continue;
    const Vec3 r = candidates[i] - report.centroid;
    const double off = (r - r.dot(report.direction) * report.direction).norm();
    if (off < best_off) {
      best = {candidates[i], scores[i]};
      best_off = off;
    }
  }
  return best;
}

std::string ExtensionHint::describe() const {
  if (!found) return "no bone near the boundary faces this motion";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f", facing);
  return "extend the boundary near " + detail::where(rim_point) + " towards " + detail::where(bone_point) +
         ", where the bone faces the motion (cosine " + buf + ")";
}

namespace {

/// The box of the bone's vertices extension_with weighs: the rim's, grown by the reach.
BoundingBox hint_box(const std::vector<Vec3>& rim, double reach) {
  BoundingBox box;
  for (const Vec3& q : rim) box.extend(q);
  box.min -= Vec3::Constant(reach);
  box.max += Vec3::Constant(reach);
  return box;
}

/// where_to_extend() with the bone's vertex normals from normal_of(vertex).
template <class NormalOf> ExtensionHint extension_with(const StabilityReport& report, const FreeMotion& motion,
                                                       const std::vector<Vec3>& rim, const TriangleMesh& bone,
                                                       const AabbTree& region, double reach, double on_region,
                                                       NormalOf&& normal_of) {
  ExtensionHint hint;
  if (rim.empty() || bone.empty()) return hint;
  const BoundingBox box = hint_box(rim, reach);
  const Vec3 v = motion.twist.head<3>(), w = motion.twist.tail<3>() / report.scale;
  double best = -std::numeric_limits<double>::infinity();
  for (Index i = 0; i < bone.vertex_count(); ++i) {
    const Vec3& p = bone.positions[i];
    if (!box.contains(p)) continue;
    const Vec3 normal = normal_of(i);
    if (normal.norm() == 0.0) continue;
    const Vec3 u = v + w.cross(p - report.centroid);
    if (u.norm() < 1e-12) continue;
    double facing = -normal.normalized().dot(u.normalized());
    if (motion.keeps_contact) facing = std::abs(facing); // free both ways: bone facing either way holds one
    if (facing < 0.5) continue;
    // The value below is less than facing - 0.5 on_region / reach: a vertex that cannot beat the best
    // is passed before the (costly) search for the covered bone near it.
    if (facing - 0.5 * on_region / reach <= best) continue;
    const auto cp = region.closest_point(p, reach);
    if (!cp || cp->distance <= on_region) continue; // on the covered bone, or too far
    const double value = facing - 0.5 * cp->distance / reach;
    if (value <= best) continue;
    best = value;
    hint = {true, cp->point, p, facing};
  }
  if (hint.found) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec3& q : rim)
      if ((q - hint.bone_point).norm() < nearest) {
        nearest = (q - hint.bone_point).norm();
        hint.rim_point = q;
      }
  }
  return hint;
}

} // namespace

ExtensionHint where_to_extend(const StabilityReport& report, const FreeMotion& motion, const std::vector<Vec3>& rim,
                              const TriangleMesh& bone, const AabbTree& region, double reach, double on_region,
                              const std::vector<Vec3>* bone_normals) {
  const std::vector<Vec3> own = bone_normals ? std::vector<Vec3>{} : vertex_normals(bone);
  const std::vector<Vec3>& normals = bone_normals ? *bone_normals : own;
  return extension_with(report, motion, rim, bone, region, reach, on_region,
                        [&](Index v) -> const Vec3& { return normals[v]; });
}

namespace {

// The bone's vertex normals where the contacts and the hint read them, made on first use: one at a
// time when the caller has the bone's topology, else all at once.
class BoneNormals {
public:
  BoneNormals(const TriangleMesh& mesh, const MeshTopology* topology) : mesh_(mesh), topology_(topology) {
    if (topology && &topology->mesh() != &mesh) throw InvalidInput("stability: the topology is not the bone's");
  }
  const Vec3& operator()(Index v) {
    start();
    if (topology_ && !made_[v]) {
      normals_[v] = topology_->vertex_normal(v);
      made_[v] = 1;
    }
    return normals_[v];
  }
  /// Makes the normals of the vertices in `box` at once, in one pass over the faces instead of a gather
  /// around each vertex (the hint weighs every vertex near the rim: a few hundred thousand on a fine
  /// scan). The same normals, bit for bit: each face's normal added to its corners in the order of the
  /// faces, as MeshTopology::vertex_normal adds those around a vertex, then divided by the length.
  void make_in(const BoundingBox& box) {
    start();
    if (!topology_) return; // all made
    std::vector<std::uint8_t> wanted(mesh_.vertex_count(), 0);
    bool any = false;
    for (Index v = 0; v < mesh_.vertex_count(); ++v)
      if (!made_[v] && box.contains(mesh_.positions[v])) {
        wanted[v] = 1;
        normals_[v] = Vec3::Zero();
        any = true;
      }
    if (!any) return;
    for (Index f = 0; f < mesh_.face_count(); ++f) {
      const Triangle& t = mesh_.triangles[f];
      if (!(wanted[t[0]] | wanted[t[1]] | wanted[t[2]])) continue;
      const Vec3 n = triangle_normal(mesh_, f);
      for (const Index v : t)
        if (wanted[v]) normals_[v] += n;
    }
    for (Index v = 0; v < mesh_.vertex_count(); ++v) {
      if (!wanted[v]) continue;
      if (const double len = normals_[v].norm(); len > 0.0) normals_[v] /= len;
      made_[v] = 1;
    }
  }

private:
  /// On first use: every normal without a topology, else room for those made one by one.
  void start() {
    if (!normals_.empty()) return;
    if (!topology_) {
      normals_ = vertex_normals(mesh_);
    } else {
      normals_.resize(mesh_.vertex_count());
      made_.assign(mesh_.vertex_count(), 0);
    }
  }

  const TriangleMesh& mesh_;
  const MeshTopology* topology_;
  std::vector<Vec3> normals_;
  std::vector<std::uint8_t> made_;
};

StabilityResult contacts_part(const TriangleMesh& inner, const AabbTree& bone, const Vec3& direction, double reach,
                              const std::vector<std::uint8_t>& skip, bool toward_bone, BoneNormals& normal_of) {
  StabilityResult out;
  out.analysed = true;
  out.contacts = contacts_with(inner, bone, reach, 1.0, skip, toward_bone, normal_of);
  out.report = analyse_stability(out.contacts, direction);
  return out;
}

void finish_part(StabilityResult& result, const AabbTree& bone, const std::vector<Vec3>& press_candidates,
                 const std::vector<Vec3>& rim, const AabbTree& covered, double on_covered, BoneNormals& normal_of) {
  std::vector<Vec3> candidates;
  const std::size_t step = std::max<std::size_t>(1, (press_candidates.size() + 999) / 1000);
  for (std::size_t i = 0; i < press_candidates.size(); i += step) candidates.push_back(press_candidates[i]);
  result.press = best_press_point(result.report, candidates);
  constexpr double kHintReach = 15.0; // mm from the rim
  if (result.report.score < 0.5 && !result.report.free_motions.empty() && !rim.empty()) {
    normal_of.make_in(hint_box(rim, kHintReach));
    result.extend = extension_with(result.report, result.report.worst_motion, rim, bone.mesh(), covered, kHintReach,
                                   on_covered, normal_of);
  }
}

} // namespace

StabilityResult stability_of_contacts(const TriangleMesh& inner, const AabbTree& bone, const Vec3& direction,
                                      double reach, const std::vector<std::uint8_t>& skip, bool toward_bone,
                                      const MeshTopology* bone_topology) {
  BoneNormals normal_of(bone.mesh(), bone_topology);
  return contacts_part(inner, bone, direction, reach, skip, toward_bone, normal_of);
}

void finish_stability(StabilityResult& result, const AabbTree& bone, const std::vector<Vec3>& press_candidates,
                      const std::vector<Vec3>& rim, const AabbTree& covered, double on_covered,
                      const MeshTopology* bone_topology) {
  BoneNormals normal_of(bone.mesh(), bone_topology);
  finish_part(result, bone, press_candidates, rim, covered, on_covered, normal_of);
}

// One set of the bone's normals for both parts.
StabilityResult guide_stability(const TriangleMesh& inner, const AabbTree& bone, const Vec3& direction, double reach,
                                const std::vector<Vec3>& press_candidates, const std::vector<Vec3>& rim,
                                const AabbTree& covered, double on_covered, const std::vector<std::uint8_t>& skip,
                                bool toward_bone, const MeshTopology* bone_topology) {
  BoneNormals normal_of(bone.mesh(), bone_topology);
  StabilityResult out = contacts_part(inner, bone, direction, reach, skip, toward_bone, normal_of);
  finish_part(out, bone, press_candidates, rim, covered, on_covered, normal_of);
  return out;
}

} // namespace st
