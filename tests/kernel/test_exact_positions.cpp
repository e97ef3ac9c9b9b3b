// Exact positions: boundary loops whose control points sit exactly on the mesh (on vertices, at edge
// midpoints, on edges) and loops that run along mesh edges, on regular synthetic meshes (plane grid,
// rounded box, cylinder, sphere) and on the example meshes.
//
// The cases reported in the issue are regression tests. The property test: 1000 loops; every loop
// whose curve is simple must give a valid template, with no refusal. On the scans, a loop refused
// also with its points moved off the mesh (a sparse spline jumping across a fold) is not a matter of
// exact positions: such loops are counted, at most 1 %.
// ST_PROPERTY_CASES sets its number of loops (default 1000, spread over the meshes).

#include "helpers.h"

#include "st/core/errors.h"
#include "st/core/topology.h"
#include "st/design/template_design.h"
#include "st/guide/tube.h"
#include "st/io/case_file.h"
#include "st/io/mesh_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <map>
#include <optional>
#include <random>
#include <set>

namespace st {
namespace {

/// A cube [-half, half]^3 gridded every h on its faces, each grid point moved onto the box of
/// half-size half - r grown by r: the flat faces keep their grid exactly, edges and corners are
/// rounded (a CAD-like regular mesh).
TriangleMesh make_rounded_box(double half, double r, double h) {
  const int n = static_cast<int>(std::lround(2.0 * half / h));
  TriangleMesh m;
  std::map<std::array<int, 3>, Index> ids;
  auto vertex = [&](const std::array<int, 3>& q) {
    auto [it, fresh] = ids.emplace(q, static_cast<Index>(m.positions.size()));
    if (fresh) {
      const Vec3 p(q[0] * h - half, q[1] * h - half, q[2] * h - half);
      const double inner = half - r;
      const Vec3 c = p.cwiseMax(Vec3::Constant(-inner)).cwiseMin(Vec3::Constant(inner));
      m.positions.push_back(c + r * (p - c).normalized());
    }
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::array<Index, 4> quad;
          const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) {
            std::array<int, 3> q{};
            q[axis] = side * n;
            q[u] = i + di[k];
            q[v] = j + dj[k];
            quad[k] = vertex(q);
          }
          // (u, v, axis) is right-handed: counter-clockwise in (u, v) faces +axis.
          if (side == 1) {
            m.triangles.push_back({quad[0], quad[1], quad[2]});
            m.triangles.push_back({quad[0], quad[2], quad[3]});
          } else {
            m.triangles.push_back({quad[0], quad[2], quad[1]});
            m.triangles.push_back({quad[0], quad[3], quad[2]});
          }
        }
    }
  return m;
}

/// An open cylinder along z: `segments` around, rings every `ring` mm.
TriangleMesh make_cylinder(double radius, double length, int segments, double ring) {
  const int rings = static_cast<int>(std::lround(length / ring));
  TriangleMesh m;
  for (int k = 0; k <= rings; ++k)
    for (int s = 0; s < segments; ++s) {
      const double a = 2.0 * M_PI * s / segments;
      m.positions.emplace_back(radius * std::cos(a), radius * std::sin(a), k * ring);
    }
  for (int k = 0; k < rings; ++k)
    for (int s = 0; s < segments; ++s) {
      const Index a = k * segments + s, b = k * segments + (s + 1) % segments;
      const Index c = (k + 1) * segments + (s + 1) % segments, d = (k + 1) * segments + s;
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  return m;
}

struct Shape {
  std::string name;
  TriangleMesh mesh;
  double thickness = 2.0;
  int rings = 8;         // the region: faces within this many edge steps of a centre vertex
  bool synthetic = true; // loops also carry a tube whose entry is a vertex
};

/// A failing loop as a case file (and its mesh beside it) in test-output/exact_positions, to replay
/// with `surgical-template design`.
void save_failure(const Shape& shape, const TemplateOptions& o, int k) {
  const std::filesystem::path dir = std::filesystem::path(test::output_dir()) / "exact_positions";
  std::filesystem::create_directories(dir);
  CaseFile c;
  c.name = "exact-" + std::to_string(k);
  c.bone = (dir / (shape.name + ".stl")).string();
  std::replace(c.bone.begin(), c.bone.end(), ' ', '_');
  if (!std::filesystem::exists(c.bone)) write_stl(shape.mesh, c.bone);
  c.boundary_points = o.boundary_points;
  c.inside = o.inside;
  c.thickness = o.thickness;
  c.tubes = o.tubes;
  write_case(c, (dir / (c.name + ".json")).string());
}

/// The boundary loop (vertex ids, in order) of the faces whose vertices all lie within `rings` edge
/// steps of `centre`, when that region is a disk (one boundary loop, no mesh border, Euler
/// characteristic 1); empty otherwise.
std::vector<Index> ring_loop(const MeshTopology& topo, Index centre, int rings) {
  const TriangleMesh& mesh = topo.mesh();
  std::map<Index, int> depth{{centre, 0}};
  std::deque<Index> queue{centre};
  while (!queue.empty()) {
    const Index v = queue.front();
    queue.pop_front();
    if (depth[v] == rings) continue;
    for (const Index f : topo.faces_of(v))
      for (const Index w : mesh.triangles[f])
        if (depth.emplace(w, depth[v] + 1).second) queue.push_back(w);
  }
  std::set<Index> region;
  for (const auto& [v, d] : depth)
    for (const Index f : topo.faces_of(v)) {
      const Triangle& t = mesh.triangles[f];
      if (depth.count(t[0]) && depth.count(t[1]) && depth.count(t[2])) region.insert(f);
    }
  std::map<Index, Index> next; // boundary: from vertex -> to vertex, region on the left
  std::set<std::pair<Index, Index>> edges;
  for (const Index f : region)
    for (Index k = 0; k < 3; ++k) {
      const Index h = 3 * f + k;
      const Index o = topo.opposite(h);
      if (o == kInvalidIndex) return {}; // a mesh border or non-manifold edge: a hole
      edges.insert(std::minmax(topo.from_vertex(h), topo.to_vertex(h)));
      if (!region.count(o / 3)) {
        if (next.count(topo.from_vertex(h))) return {}; // pinched
        next[topo.from_vertex(h)] = topo.to_vertex(h);
      }
    }
  std::set<Index> vertices;
  for (const Index f : region)
    for (const Index v : mesh.triangles[f]) vertices.insert(v);
  if (static_cast<long>(vertices.size()) - static_cast<long>(edges.size()) + static_cast<long>(region.size()) != 1)
    return {};
  if (next.empty()) return {};
  std::vector<Index> loop{next.begin()->first};
  while (loop.size() <= next.size()) {
    const Index w = next[loop.back()];
    if (w == loop.front()) break;
    loop.push_back(w);
  }
  return loop.size() == next.size() ? loop : std::vector<Index>{};
}

const std::string kCrossesItself = "crosses itself";

/// Why the template of `o` on `mesh` is refused or invalid (kCrossesItself when the curve crosses
/// itself), or nothing when it is a valid solid.
std::optional<std::string> design_error(const TriangleMesh& mesh, const TemplateOptions& o) {
  try {
    const TemplateResult r = design_template(mesh, o);
    if (!r.solid.valid()) return r.solid.summary();
  } catch (const CurveCrossesItself&) {
    return kCrossesItself;
  } catch (const std::exception& e) {
    return std::string(e.what());
  }
  return std::nullopt;
}

/// Whether the loop is refused too with its control points moved off the mesh's vertices and edges
/// (by up to 0.1 mm, three times at random).
bool refused_off_exact_positions(const TriangleMesh& mesh, const TemplateOptions& o, std::mt19937& rng) {
  std::uniform_real_distribution<double> shift(-0.1, 0.1);
  for (int k = 0; k < 3; ++k) {
    TemplateOptions moved = o;
    for (Vec3& p : moved.boundary_points) p += Vec3(shift(rng), shift(rng), shift(rng));
    if (!design_error(mesh, moved)) return false;
  }
  return true;
}

enum class Kind { Vertices, Midpoints, OnEdges, AlongEdges };
const char* kind_name(Kind k) {
  switch (k) {
  case Kind::Vertices: return "vertices";
  case Kind::Midpoints: return "edge midpoints";
  case Kind::OnEdges: return "points on edges";
  case Kind::AlongEdges: return "along edges";
  }
  return "";
}

TEST(ExactPositions, LoopsOnVerticesAndEdgesGiveValidTemplates) {
  const char* env = std::getenv("ST_PROPERTY_CASES");
  const int total = env ? std::atoi(env) : 1000;
  std::vector<Shape> shapes;
  shapes.push_back(
      {"plane grid", test::make_height_field(0, 60, 0, 60, 60, [](double, double) { return 0.0; }), 2.0, 10});
  shapes.push_back({"rounded box", make_rounded_box(20.0, 5.0, 1.0), 2.0, 8});
  shapes.push_back({"cylinder", make_cylinder(10.0, 60.0, 160, 1.0), 2.0, 8});
  shapes.push_back({"sphere", test::make_icosphere(20.0, 5), 2.0, 8});
  for (const char* name : {"tibia", "sacrum", "vertebrae_lumbar_L2-L5_ssm_mean"}) {
    Shape s{name, read_mesh(test::examples_dir() + "/meshes/" + name + ".stl.gz"), 2.0, 12, false};
    shapes.push_back(std::move(s));
  }
  std::mt19937 rng(17), shift_rng(29);
  int tested = 0, skipped = 0, refused_anyway = 0, not_simple = 0;
  std::vector<std::string> failures;
  const int per_shape = std::max(1, total / static_cast<int>(shapes.size()));
  for (const Shape& shape : shapes) {
    const MeshTopology topo(shape.mesh);
    std::uniform_int_distribution<Index> any_vertex(0, shape.mesh.vertex_count() - 1);
    int done = 0;
    for (int attempt = 0; done < per_shape && attempt < 20 * per_shape; ++attempt) {
      const Index centre = any_vertex(rng);
      if (topo.faces_of(centre).empty()) continue;
      const std::vector<Index> loop = ring_loop(topo, centre, shape.rings);
      if (loop.size() < 12) {
        ++skipped;
        continue;
      }
      const Kind kind = static_cast<Kind>(done % 4);
      const int count = kind == Kind::AlongEdges ? static_cast<int>(loop.size()) : 6 + static_cast<int>(rng() % 7);
      std::vector<Vec3> points;
      std::uniform_real_distribution<double> unit(0.05, 0.95);
      for (int i = 0; i < count; ++i) {
        const std::size_t at = i * loop.size() / count;
        const Vec3& a = shape.mesh.positions[loop[at]];
        const Vec3& b = shape.mesh.positions[loop[(at + 1) % loop.size()]];
        switch (kind) {
        case Kind::Vertices:
        case Kind::AlongEdges: points.push_back(a); break;
        case Kind::Midpoints: points.push_back(0.5 * (a + b)); break;
        case Kind::OnEdges: {
          const double t = unit(rng);
          points.push_back((1.0 - t) * a + t * b);
          break;
        }
        }
      }
      TemplateOptions o;
      o.boundary_points = points;
      o.thickness = shape.thickness;
      o.inside = shape.mesh.positions[centre]; // a vertex too
      if (shape.synthetic && done % 3 == 0) {
        // A drilling tube whose entry is the centre vertex, along the (mean of its faces') normal.
        Vec3 normal = Vec3::Zero();
        for (const Index f : topo.faces_of(centre)) normal += triangle_normal(shape.mesh, f);
        TubeSpec tube;
        tube.name = "on-vertex";
        tube.entry = shape.mesh.positions[centre];
        tube.direction = -normal.normalized();
        tube.inner_radius = 1.1;
        tube.outer_radius = 2.5;
        tube.length = 8.0;
        tube.offset = 2.0;
        o.tubes = {tube};
      }
      ++done;
      ++tested;
      const std::optional<std::string> error = design_error(shape.mesh, o);
      if (error && *error == kCrossesItself) {
        --tested; // the spline through these points is not a simple loop
        ++not_simple;
      } else if (error && !shape.synthetic && refused_off_exact_positions(shape.mesh, o, shift_rng)) {
        // On a scan, a sparse spline can leave the ring of faces it was drawn on (jump across a
        // fold of the sacrum): not a matter of exact positions when the same loop moved off them
        // is refused as well. Counted and bounded below.
        ++refused_anyway;
      } else if (error) {
        failures.push_back(shape.name + " (" + kind_name(kind) + ", centre vertex " + std::to_string(centre) +
                           "): " + *error);
        save_failure(shape, o, tested);
      }
    }
  }
  std::string report;
  for (std::size_t i = 0; i < failures.size() && i < 20; ++i) report += "\n  " + failures[i];
  EXPECT_TRUE(failures.empty()) << failures.size() << " of " << tested << " loops refused or invalid:" << report;
  EXPECT_GE(tested, total * 8 / 10) << "too few loops tested (" << skipped << " regions not disks, " << not_simple
                                    << " curves not simple)";
  EXPECT_LE(refused_anyway, tested / 100) << "loops on the scans refused at and off exact positions alike";
  std::printf("%d loops: %d valid, %d failed, %d on scans refused off the exact positions too; not tested: %d "
              "curves not simple, %d regions not disks\n",
              tested, tested - static_cast<int>(failures.size()) - refused_anyway, static_cast<int>(failures.size()),
              refused_anyway, not_simple, skipped);
}

/// The template of `points` on `mesh` (thickness 2 mm) is a valid solid.
void expect_valid_template(const TriangleMesh& mesh, const std::vector<Vec3>& points,
                           std::optional<Vec3> inside = std::nullopt) {
  TemplateOptions o;
  o.boundary_points = points;
  o.inside = inside;
  o.thickness = 2.0;
  const TemplateResult r = design_template(mesh, o);
  EXPECT_TRUE(r.solid.valid()) << r.solid.summary();
}

TEST(ExactPositions, SquareOnTheGridVerticesOfAFlatFace) {
  // Was: "cannot follow the surface between (-8, -8, 20) and (-8, -8, 20)" (a walk from a vertex).
  expect_valid_template(make_rounded_box(20.0, 5.0, 1.0), {{-8, -8, 20}, {8, -8, 20}, {8, 8, 20}, {-8, 8, 20}});
  expect_valid_template(test::make_height_field(0, 40, 0, 40, 40, [](double, double) { return 0.0; }),
                        {{10, 10, 0}, {30, 10, 0}, {30, 30, 0}, {10, 30, 0}}, Vec3(20, 20, 0));
}

TEST(ExactPositions, LoopAroundARoundedCornerOnGridVertices) {
  // Was: "the offset surface is missing above the inner surface near (28.37, 28.37, 28.37)". Six grid
  // vertices on the flat parts of the three faces around a corner rounded with radius 5, and the
  // same hexagon with its corners at the edge midpoints next to them.
  const TriangleMesh box = make_rounded_box(20.0, 5.0, 1.0);
  expect_valid_template(box, {{20, 8, 14}, {20, 14, 8}, {14, 20, 8}, {8, 20, 14}, {8, 14, 20}, {14, 8, 20}});
  expect_valid_template(box, {{20, 8.5, 14}, {20, 14, 8.5}, {14, 20, 8.5}, {8.5, 20, 14}, {8.5, 14, 20}, {14, 8.5, 20}},
                        Vec3(20, 14, 14));
}

TEST(ExactPositions, HalfCylinderLoopOnRingsOfVertices) {
  // Points at 0, 45, ..., 180 degrees on two rings of a 160-segment cylinder with 1 mm rings: every
  // spline sample between them lies on a ring of vertices. Also moved off them at random by up to
  // 0.13 mm (samples still land on the rings).
  const TriangleMesh cylinder = make_cylinder(10.0, 40.0, 160, 1.0);
  std::vector<Vec3> loop;
  for (const double z : {10.0, 30.0})
    for (int i = 0; i <= 4; ++i) {
      const double a = (z == 10.0 ? i : 4 - i) * M_PI / 4.0;
      loop.emplace_back(10.0 * std::cos(a), 10.0 * std::sin(a), z);
    }
  expect_valid_template(cylinder, loop);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> shift(-0.13, 0.13);
  for (int k = 0; k < 5; ++k) {
    std::vector<Vec3> moved = loop;
    for (Vec3& p : moved) p += Vec3(shift(rng), shift(rng), 0.0);
    expect_valid_template(cylinder, moved);
  }
}

TEST(ExactPositions, ExampleCasesWithControlPointsOnTheirNearestVertices) {
  // Was, for the sacrum and the maxilla: "cannot follow the surface between (376.79, 86.30, 358.66)
  // and (376.79, 86.30, 358.66)".
  for (const char* name : {"sacrum-iliosacral", "maxilla-implants", "tibia-osteotomy", "vertebra-pedicle"}) {
    const CaseFile c = read_case(test::examples_dir() + "/cases/" + name + ".json");
    const TriangleMesh bone = read_mesh(c.bone);
    auto nearest_vertex = [&](const Vec3& p) {
      Index best = 0;
      for (Index v = 1; v < bone.vertex_count(); ++v)
        if ((bone.positions[v] - p).squaredNorm() < (bone.positions[best] - p).squaredNorm()) best = v;
      return bone.positions[best];
    };
    TemplateOptions o = st::test::case_options(c);
    for (Vec3& p : o.boundary_points) p = nearest_vertex(p);
    if (o.inside) o.inside = nearest_vertex(*o.inside);
    const TemplateResult r = design_template(bone, o);
    EXPECT_TRUE(r.solid.valid()) << name << ": " << r.solid.summary();
  }
}

} // namespace
} // namespace st
