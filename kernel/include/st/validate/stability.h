#pragma once
// Seating stability: which small rigid motions the contacts between a guide and the bone leave free,
// and how firmly they hold the guide pressed along its insertion direction.
//
// Contacts. Points p_i of the guide's inner surface within a reach (clearance + h/4) of the bone, about
// one per mm^2 of area, each with n_i, the bone's outward normal there (sample_contacts).
//
// Free motions. A small rigid motion is a twist: a translation v and a rotation w about the contacts'
// centroid c, moving p_i by v + w x r_i (r_i = p_i - c). Contact i blocks it when it pushes p_i into the
// bone, n_i . (v + w x r_i) < 0, that is a_i . x < 0 with
//     x = (v, l w),   a_i = (n_i, (r_i x n_i) / l),
// where l, the contacts' RMS distance from c, makes turns and slides comparable (a turn by 1/l rad moves
// a typical contact by 1 mm). The free motions form the convex cone F = {x : a_i . x >= 0 for all i}.
// Its linear part (a_i . x = 0 for all i) keeps every contact: slides, turns and screws. The rest
// lifts off some contacts.
//
// Score. The guide is pressed along the insertion direction d through c. A free motion x rises
// against the press by lift(x) = -d . v. The score is the least rise of a unit free motion:
//     score = min { lift(x) : x in F, |x| = 1 }, clamped to [0, 1],
// 0 when some free motion does not rise against the press (a slide, a turn, a slide away from a cap,
// a drop deeper along d), 1 when the only free motion is the lift-off along -d itself (and when
// nothing at all is free: F = {0}). Dually it is the radius of the largest ball of wrenches (force,
// torque / l) around the press that the contact forces (n_i, r_i x n_i) balance: the largest
// disturbing force or torque, relative to the press, held in its worst direction. Monotone: adding a
// contact shrinks F, so the score never falls; removing one never raises it (for a fixed c and l).
//
// Computation (analyse_stability). The linear part is the null space of sum a_i a_i^T (eigenvalues
// below 1e-9: absolute, so that fewer contacts never free less). On its complement every free motion
// moves some contact off the bone and none into it, so g . x > 0 there with g = sum a_i, and the
// section of F by {g . x = 1} is a polytope of at most 5 dimensions. Its vertices, the extreme free
// motions, are found by cutting a box of half-width 1e4 (a guard: a motion held by less than 1e-4
// reads as free) by the contacts' half-spaces one at a time (double description, adjacency by
// rank); the minimum of a linear function over the unit vectors of a convex cone, where it is not
// negative, lies on an extreme ray, so score = min over them of lift(r) / |r|. Where to press: the
// outer point at which a push along d gives the highest score over the same extreme motions.

#include "st/core/aabb_tree.h"
#include "st/core/topology.h"
#include "st/core/mesh.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace st {

using Twist = Eigen::Matrix<double, 6, 1>; ///< (v, l w): mm, and rad scaled by the contacts' RMS radius

struct Contact {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ(); ///< the bone's outward normal (into the guide), unit
};

/// A free motion in words and numbers.
struct FreeMotion {
  enum class Kind { slide, turn, screw, lift_off }; ///< lift_off: the slide along -d
  Kind kind = Kind::slide;
  Vec3 direction = Vec3::UnitZ();             ///< of the slide, or of the turn's axis (unit)
  Vec3 point = Vec3::Zero();                  ///< a point of the turn's axis (turn, screw)
  double pitch = 0.0;                         ///< screw: mm along the axis per radian
  bool keeps_contact = false;                 ///< in the linear part: every contact stays (else some lift off)
  bool blocked = false;                       ///< lift_off only: not free, the bone holds the guide (an undercut)
  double lift = 0.0;                          ///< rise against the press per unit of motion, in [0, 1]
  Twist twist = Twist::Zero();                ///< unit
  [[nodiscard]] std::string describe() const; ///< "slides along (x, y, z)", "turns about the axis through ..."
};

/// The frame belongs to the guide: the score is monotone in the contacts for a fixed frame (comparing
/// subsets of one guide's contacts, pass the whole set's centroid and scale).
struct StabilityOptions {
  std::optional<Vec3> centroid; ///< the point the press goes through and turns are about; else the contacts' centroid
  double scale = 0.0;           ///< l, mm; 0: the contacts' RMS distance from the centroid
  double box = 1e4;             ///< half-width of the box the section is cut from (> 0)
};

struct StabilityReport {
  std::size_t contacts = 0;
  Vec3 centroid = Vec3::Zero();
  double scale = 0.0;                   ///< l, mm
  Vec3 direction = Vec3::UnitZ();       ///< the insertion direction d (unit)
  double score = 0.0;                   ///< in [0, 1], see above
  bool lift_off_free = false;           ///< the lift-off along -d is a free motion
  std::vector<FreeMotion> free_motions; ///< linear part, then free motions that do not rise (when the
                                        ///< score is 0) or the one that rises least, then the lift-off
  FreeMotion worst_motion;              ///< the free motion that rises least (the score's); the blocked
                                        ///< lift-off when no motion rises (the guide snaps on)
  std::vector<Twist> extreme_motions;   ///< unit extreme rays of F (vertices of P), when P is bounded
  bool bounded = false;                 ///< P is bounded (the score is not 0 for want of a rise)
};

/// Samples the points of `inner` (the guide's inner surface) within `reach` of `bone`, about one per
/// `spacing`^2 mm^2, deterministically (a fixed pattern in each face, a running sum of areas), with the
/// bone's normal at the closest point turned to agree with the inner surface's. The normal is the
/// bone's vertex normals interpolated there (the face's own where they cancel): on a tessellated
/// cylinder or sphere it is the smooth surface's, so turning about the axis is free as on the real
/// bone, not held by the facets' edges. Faces with
/// `skip[f]` set are left out (skip may be empty).
/// `toward_bone`: the inner faces' normals point into the bone (a closed guide's own facets), not
/// away from it (the designed inner surface, oriented as the bone). `bone_normals`: the bone's
/// vertex_normals() when the caller has them (else computed here).
std::vector<Contact> sample_contacts(const TriangleMesh& inner, const AabbTree& bone, double reach,
                                     double spacing = 1.0, const std::vector<std::uint8_t>& skip = {},
                                     bool toward_bone = false, const std::vector<Vec3>* bone_normals = nullptr);

/// The free motions and score of `contacts` pressed along `direction` (the insertion direction, onto
/// the bone; need not be unit). Throws InvalidInput for a zero direction. No contacts: every motion
/// is free, score 0.
StabilityReport analyse_stability(const std::vector<Contact>& contacts, const Vec3& direction,
                                  const StabilityOptions& options = {});

/// The score when the push along the report's direction is applied at `point` instead of through the
/// centroid (over the report's extreme motions; 0 when a motion keeps every contact).
double press_score(const StabilityReport& report, const Vec3& point);

/// The twist x = (v, l w) of the report's frame as a free motion (kind, axis, pitch, lift); a turn
/// part below `tolerance` (of the unit twist) makes it a slide, a pitch below 1e-3 l (or tolerance * l) a turn.
FreeMotion describe_twist(const StabilityReport& report, const Twist& x, bool keeps_contact, double tolerance = 1e-6);

struct PressPoint {
  Vec3 point = Vec3::Zero();
  double score = 0.0; ///< press_score there
};

/// Of `candidates` (points of the guide's outer surface), the one where a push along the direction
/// holds best (press_score); among equal scores (within 1e-3) the nearest to the line through the
/// centroid along the direction. Empty candidates: the centroid.
PressPoint best_press_point(const StabilityReport& report, const std::vector<Vec3>& candidates);

/// Which part of the boundary to extend against a free motion: the bone outside the covered region
/// (`region`, a tree over the covered bone), within `reach` of it, whose normal faces the motion
/// there best (cosine at least 0.5), nearer places first, and the rim point nearest it.
struct ExtensionHint {
  bool found = false;
  Vec3 rim_point = Vec3::Zero();
  Vec3 bone_point = Vec3::Zero();
  double facing = 0.0; ///< cosine between the bone's inward normal and the motion there
  [[nodiscard]] std::string describe() const;
};
/// `on_region`: bone closer than this to `region` counts as covered; `bone_normals` as for
/// sample_contacts.
ExtensionHint where_to_extend(const StabilityReport& report, const FreeMotion& motion, const std::vector<Vec3>& rim,
                              const TriangleMesh& bone, const AabbTree& region, double reach = 15.0,
                              double on_region = 0.05, const std::vector<Vec3>* bone_normals = nullptr);

/// Will a guide stay put: the whole analysis of one guide.
struct StabilityResult {
  bool analysed = false;
  std::vector<Contact> contacts; ///< inner-surface points within the reach of the bone, ~1 per mm^2
  StabilityReport report;        ///< free motions and score, pressed along the insertion direction
  PressPoint press;              ///< the outer-surface point where a push along the direction holds best
  ExtensionHint extend;          ///< where to extend the boundary against the worst motion (score < 0.5)
};

/// The contacts of `inner` (faces with skip[f] left out) within `reach` of the bone, their free motions
/// and score pressed along `direction`, the press point among `press_candidates` (at most 1000 of them
/// used, evenly), and, when the score is below 0.5, where to extend the boundary `rim` onto bone
/// outside `covered` (bone within `on_covered` of it counts as covered). `bone_topology`, the faces around
/// the bone's vertices when the caller has them: only the vertex normals read are made.
StabilityResult guide_stability(const TriangleMesh& inner, const AabbTree& bone, const Vec3& direction, double reach,
                                const std::vector<Vec3>& press_candidates, const std::vector<Vec3>& rim,
                                const AabbTree& covered, double on_covered = 0.05,
                                const std::vector<std::uint8_t>& skip = {}, bool toward_bone = false,
                                const MeshTopology* bone_topology = nullptr);

/// guide_stability in two parts. The first reads the inner surface and the bone only (the contacts
/// and the report; press and extension left empty), so it can run before the outer surface is made;
/// finish_stability adds the press point and the extension hint. Together they give what
/// guide_stability gives with the same arguments.
StabilityResult stability_of_contacts(const TriangleMesh& inner, const AabbTree& bone, const Vec3& direction,
                                      double reach, const std::vector<std::uint8_t>& skip = {},
                                      bool toward_bone = false, const MeshTopology* bone_topology = nullptr);
void finish_stability(StabilityResult& result, const AabbTree& bone, const std::vector<Vec3>& press_candidates,
                      const std::vector<Vec3>& rim, const AabbTree& covered, double on_covered = 0.05,
                      const MeshTopology* bone_topology = nullptr);

} // namespace st
