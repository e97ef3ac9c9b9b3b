// reference-chain: the paper's initial-template pipeline done with off-the-shelf libraries, timed
// step by step on the same case as `surgical-template design`, so bench tables can show the
// kernel next to the best reference chain built from VTK 9 and OpenVDB.
//
//   reference-chain CASE.json [--runs N] [--json OUT.json]
//
// Steps (the rows of the paper's Table 1):
//  1. inner cut      vtkSelectPolyData (loop = the kernel's surface curve, ~1 point per mm)
//                    + vtkClipPolyData at 0 + vtkPolyDataConnectivityFilter
//  2. offset         OpenVDB meshToUnsignedDistanceField + volumeToMesh at the thickness
//  3. outer points   vtkPolyDataNormals on the inner surface; border samples moved by T along
//                    averaged normals and snapped onto the offset with vtkCellLocator
//  4. outer cut      vtkSelectPolyData + vtkClipPolyData + connectivity on the offset
//  5. connection     st::ruled_surface between the two borders, and the shell
// The shell is then checked with st::check_solid (untimed). Everything that prepares a step's
// input from the previous one outside the libraries (the kernel's curve, border loop ordering) is
// untimed; conversions between the libraries' mesh types are timed with the step that needs them.
// See README.md for what is and is not comparable with the kernel's times.

#include "st/io/case_file.h"
#include "st/core/errors.h"
#include "st/core/mesh.h"
#include "st/io/mesh_io.h"
#include "st/design/ruled_surface.h"
#include "st/design/surface_curve.h"
#include "st/core/topology.h"
#include "st/validate/validate.h"

#include "report_json.h"
#include "vtk_convert.h"

#include <nlohmann/json.hpp>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <vtkCellArray.h>
#include <vtkCellLocator.h>
#include <vtkClipPolyData.h>
#include <vtkAlgorithmOutput.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataConnectivityFilter.h>
#include <vtkPolyDataNormals.h>
#include <vtkSelectPolyData.h>
#include <vtkSmartPointer.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using st::Index;
using st::TriangleMesh;
using st::Vec3;
using st::bench::from_vtk;
using st::bench::median;
using st::bench::solid_json;
using st::bench::to_vtk;
using Clock = std::chrono::steady_clock;

// The steps in the order they run: (key in the JSON report, label on the console).
constexpr std::array<std::pair<const char*, const char*>, 5> kSteps{{
    {"inner_surface_segmentation", "inner cut (VTK)"},
    {"offset_of_inner_surface", "offset (OpenVDB)"},
    {"points_for_outer_surface_segmentation", "outer points (VTK locator)"},
    {"outer_surface_segmentation", "outer cut (VTK)"},
    {"connection_of_inner_and_outer_surfaces", "connection (st::ruled_surface)"},
}};

/// A step that did not give a usable result; the message says which step and why.
class StepFailed : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// ---- mesh conversions ---------------------------------------------------------------------------

// ---- VTK helpers --------------------------------------------------------------------------------

/// Collects the error messages a VTK filter reports (instead of letting them go to stderr only).
class ErrorCollector : public vtkCommand {
public:
  static ErrorCollector* New() { return new ErrorCollector; }
  void Execute(vtkObject*, unsigned long, void* data) override {
    if (data) message_ += (message_.empty() ? "" : "; ") + std::string(static_cast<const char*>(data));
  }
  void watch(vtkObject* filter) { filter->AddObserver(vtkCommand::ErrorEvent, this); }
  [[nodiscard]] const std::string& message() const { return message_; }

private:
  std::string message_;
};

void require_result(vtkPolyData* poly, const ErrorCollector& errors, const std::string& step) {
  if (!errors.message().empty()) throw StepFailed(step + ": VTK error: " + errors.message());
  if (poly == nullptr || poly->GetNumberOfPolys() == 0) throw StepFailed(step + ": VTK gave an empty surface");
}

/// The connected piece of `poly` nearest `keep` (or its largest piece), and its distance to `keep`.
std::pair<vtkSmartPointer<vtkPolyData>, double> nearest_piece(vtkAlgorithmOutput* port, const std::optional<Vec3>& keep,
                                                              ErrorCollector& errors) {
  vtkNew<vtkPolyDataConnectivityFilter> connectivity;
  errors.watch(connectivity);
  connectivity->SetInputConnection(port);
  if (keep) {
    connectivity->SetExtractionModeToClosestPointRegion();
    connectivity->SetClosestPoint(keep->data());
  } else {
    connectivity->SetExtractionModeToLargestRegion();
  }
  connectivity->Update();
  vtkSmartPointer<vtkPolyData> piece = connectivity->GetOutput();
  double distance = std::numeric_limits<double>::infinity();
  if (keep)
    for (vtkIdType v = 0; v < piece->GetNumberOfPoints(); ++v) {
      Vec3 p;
      piece->GetPoint(v, p.data());
      distance = std::min(distance, (p - *keep).norm());
    }
  return {piece, distance};
}

/// vtkSelectPolyData (selection scalars along `loop`) + vtkClipPolyData at 0 +
/// vtkPolyDataConnectivityFilter: the piece on the side of the loop that holds `keep`, or without
/// it the smaller side's largest piece.
///
/// Which sign vtkSelectPolyData gives the selected region was not consistent in Debian's VTK 9.1
/// (it kept the wrong side on the vertebra bone and the right one on its offset with the same
/// settings), so both sides of the clip are kept and the one nearest `keep` is taken.
vtkSmartPointer<vtkPolyData> cut_with_loop(vtkPolyData* surface, const std::vector<Vec3>& loop,
                                           const std::optional<Vec3>& keep, const std::string& step) {
  vtkNew<vtkPoints> loop_points;
  for (const Vec3& p : loop) loop_points->InsertNextPoint(p.data());
  vtkNew<ErrorCollector> errors;

  vtkNew<vtkSelectPolyData> select;
  errors->watch(select);
  select->SetInputData(surface);
  select->SetLoop(loop_points);
  select->GenerateSelectionScalarsOn();
  if (keep) {
    select->SetSelectionModeToClosestPointRegion();
    select->SetClosestPoint(keep->data());
  } else {
    select->SetSelectionModeToSmallestRegion();
  }

  vtkNew<vtkClipPolyData> clip;
  errors->watch(clip);
  clip->SetInputConnection(select->GetOutputPort());
  clip->SetValue(0.0);
  clip->GenerateClippedOutputOn();

  auto [above, above_distance] = nearest_piece(clip->GetOutputPort(0), keep, *errors);
  auto [below, below_distance] = nearest_piece(clip->GetOutputPort(1), keep, *errors);
  const bool take_below =
      keep ? below_distance < above_distance : below->GetNumberOfCells() < above->GetNumberOfCells();
  vtkSmartPointer<vtkPolyData> result = take_below ? below : above;
  require_result(result, *errors, step);
  return result;
}

// ---- untimed preparation ------------------------------------------------------------------------

/// The closed polyline resampled to about `spacing` between points (keeps at least 3 points).
std::vector<Vec3> resample_closed(const std::vector<Vec3>& polyline, double spacing) {
  double length = 0.0;
  for (std::size_t i = 0; i < polyline.size(); ++i)
    length += (polyline[(i + 1) % polyline.size()] - polyline[i]).norm();
  const auto count = std::max<std::size_t>(3, static_cast<std::size_t>(std::lround(length / spacing)));
  const double step = length / static_cast<double>(count);
  std::vector<Vec3> result;
  double next = 0.0, walked = 0.0;
  for (std::size_t i = 0; i < polyline.size() && result.size() < count; ++i) {
    const Vec3& a = polyline[i];
    const Vec3& b = polyline[(i + 1) % polyline.size()];
    const double segment = (b - a).norm();
    while (next <= walked + segment && result.size() < count) {
      const double t = segment > 0.0 ? (next - walked) / segment : 0.0;
      result.push_back(a + t * (b - a));
      next += step;
    }
    walked += segment;
  }
  return result;
}

/// The longest border loop of `mesh`, in half-edge order (the mesh on its left seen from the
/// normal side), as vertex indices; throws StepFailed when the mesh has no border.
std::vector<Index> longest_border(const TriangleMesh& mesh, std::size_t* loop_count, const std::string& step) {
  const st::MeshTopology topology(mesh);
  std::vector<std::vector<Index>> loops;
  try {
    loops = st::border_loops(mesh, topology.all_opposites());
  } catch (const std::exception& e) {
    throw StepFailed(step + ": the border is not a set of simple loops: " + e.what());
  }
  if (loops.empty()) throw StepFailed(step + ": the surface has no border");
  *loop_count = loops.size();
  return *std::max_element(loops.begin(), loops.end(),
                           [](const auto& a, const auto& b) { return a.size() < b.size(); });
}

// ---- one run of the chain ----------------------------------------------------------------------

struct ChainInput {
  TriangleMesh bone;
  vtkSmartPointer<vtkPolyData> bone_vtk;
  std::vector<Vec3> loop; ///< the kernel's boundary curve, ~1 point per mm
  std::optional<Vec3> inside;
  double thickness = 0.0;
  double resolution = 0.0; ///< OpenVDB voxel size
  std::optional<int> sampling_step;
};

struct ChainRun {
  std::map<std::string, double> seconds; ///< per completed step (keys of kSteps)
  std::optional<st::SolidReport> solid;
  std::string failed;
  std::size_t inner_triangles = 0, inner_border_loops = 0, inner_rim_points = 0;
  std::size_t offset_triangles = 0, outer_points = 0, outer_triangles = 0, outer_border_loops = 0;
  std::size_t shell_triangles = 0;
};

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void run_chain(const ChainInput& in, ChainRun& run) {
  const double T = in.thickness;

  // 1. Inner cut.
  auto t0 = Clock::now();
  vtkSmartPointer<vtkPolyData> inner_vtk = cut_with_loop(in.bone_vtk, in.loop, in.inside, "inner cut");
  run.seconds[kSteps[0].first] = seconds_since(t0);
  const TriangleMesh inner = from_vtk(inner_vtk);
  run.inner_triangles = inner.face_count();

  // 2. Offset: unsigned distance in world units, contoured at T.
  t0 = Clock::now();
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  points.reserve(inner.vertex_count());
  for (const Vec3& p : inner.positions)
    points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  for (const st::Triangle& t : inner.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  const auto transform = openvdb::math::Transform::createLinearTransform(in.resolution);
  const auto band = static_cast<float>(T / in.resolution + 2.0);
  const openvdb::FloatGrid::Ptr grid =
      openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(*transform, points, triangles, quads, band);
  points.clear();
  triangles.clear();
  openvdb::tools::volumeToMesh(*grid, points, triangles, quads, T, 0.0);
  TriangleMesh offset;
  for (const openvdb::Vec3s& p : points) offset.positions.emplace_back(p.x(), p.y(), p.z());
  for (const openvdb::Vec3I& t : triangles) offset.triangles.push_back({t[0], t[1], t[2]});
  for (const openvdb::Vec4I& q : quads) {
    offset.triangles.push_back({q[0], q[1], q[2]});
    offset.triangles.push_back({q[0], q[2], q[3]});
  }
  if (offset.empty()) throw StepFailed("offset: OpenVDB gave an empty surface");
  // The offset is closed (both sides of the patch); make its triangles face outward.
  if (st::signed_volume(offset) < 0.0)
    for (st::Triangle& t : offset.triangles) std::swap(t[1], t[2]);
  vtkSmartPointer<vtkPolyData> offset_vtk = to_vtk(offset);
  run.seconds[kSteps[1].first] = seconds_since(t0);
  run.offset_triangles = offset.face_count();

  // Untimed: the inner border as one ordered loop (the kernel gets it from its cut for free).
  const std::vector<Index> rim = longest_border(inner, &run.inner_border_loops, "inner cut");
  run.inner_rim_points = rim.size();

  // 3. Outer points: every `step` border points, moved by T along the normal averaged over the
  //    step and snapped onto the offset; also the point above the region's centre that picks the
  //    side to keep.
  t0 = Clock::now();
  vtkNew<vtkPolyDataNormals> normals_filter;
  normals_filter->SetInputData(to_vtk(inner));
  normals_filter->ComputePointNormalsOn();
  normals_filter->ComputeCellNormalsOff();
  normals_filter->SplittingOff();
  normals_filter->ConsistencyOff();
  normals_filter->AutoOrientNormalsOff();
  normals_filter->Update();
  vtkDataArray* normals = normals_filter->GetOutput()->GetPointData()->GetNormals();
  if (normals == nullptr) throw StepFailed("outer points: vtkPolyDataNormals gave no normals");
  auto normal_at = [&](Index v) {
    Vec3 n;
    normals->GetTuple(v, n.data());
    return n;
  };
  vtkNew<vtkCellLocator> locator;
  locator->SetDataSet(offset_vtk);
  locator->BuildLocator();
  auto closest_on_offset = [&](const Vec3& p) {
    Vec3 c;
    vtkIdType cell = -1;
    int sub_id = 0;
    double d2 = 0.0;
    locator->FindClosestPoint(p.data(), c.data(), cell, sub_id, d2);
    return c;
  };
  const std::size_t m = rim.size();
  double rim_length = 0.0;
  for (std::size_t i = 0; i < m; ++i)
    rim_length += (inner.positions[rim[(i + 1) % m]] - inner.positions[rim[i]]).norm();
  // The kernel's rule: a sample about T/2 apart unless the case gives the step in border points.
  int step = in.sampling_step.value_or(
      std::max(1, static_cast<int>(std::lround(0.5 * T / (rim_length / static_cast<double>(m))))));
  step = std::clamp(step, 1, std::max(1, static_cast<int>(m / 3)));
  const int half = std::max(1, step / 2);
  std::vector<Vec3> outer_loop;
  for (std::size_t i = 0; i < m; i += static_cast<std::size_t>(step)) {
    if (i != 0 && m - i < static_cast<std::size_t>(step) / 2) break;
    Vec3 n = Vec3::Zero();
    for (int k = -half; k <= half; ++k)
      n += normal_at(rim[(i + m + static_cast<std::size_t>(k + static_cast<int>(m))) % m]);
    if (n.squaredNorm() == 0.0) continue;
    outer_loop.push_back(closest_on_offset(inner.positions[rim[i]] + T * n.normalized()));
  }
  // Above the region: from the inner vertex nearest the inside point (or the centroid).
  Vec3 target = Vec3::Zero();
  if (in.inside) {
    target = *in.inside;
  } else {
    for (const Vec3& p : inner.positions) target += p;
    target /= static_cast<double>(inner.vertex_count());
  }
  Index centre = 0;
  for (Index v = 1; v < inner.vertex_count(); ++v)
    if ((inner.positions[v] - target).squaredNorm() < (inner.positions[centre] - target).squaredNorm()) centre = v;
  const Vec3 above = closest_on_offset(inner.positions[centre] + T * normal_at(centre).normalized());
  run.seconds[kSteps[2].first] = seconds_since(t0);
  run.outer_points = outer_loop.size();
  if (outer_loop.size() < 3) throw StepFailed("outer points: fewer than 3 border samples");

  // 4. Outer cut.
  t0 = Clock::now();
  vtkSmartPointer<vtkPolyData> outer_vtk = cut_with_loop(offset_vtk, outer_loop, above, "outer cut");
  run.seconds[kSteps[3].first] = seconds_since(t0);
  const TriangleMesh outer = from_vtk(outer_vtk);
  run.outer_triangles = outer.face_count();
  const std::vector<Index> outer_rim = longest_border(outer, &run.outer_border_loops, "outer cut");

  // 5. Connection: the ruled wall and the shell (inner reversed + outer + wall), as the kernel does.
  t0 = Clock::now();
  std::vector<Vec3> p_loop, q_loop;
  for (Index v : rim) p_loop.push_back(inner.positions[v]);
  for (Index v : outer_rim) q_loop.push_back(outer.positions[v]);
  const st::RuledResult wall = st::ruled_surface(p_loop, q_loop, 0, static_cast<Index>(m));
  TriangleMesh shell;
  const Index n_inner = inner.vertex_count();
  shell.positions = inner.positions;
  shell.positions.insert(shell.positions.end(), outer.positions.begin(), outer.positions.end());
  for (const st::Triangle& t : inner.triangles) shell.triangles.push_back({t[0], t[2], t[1]});
  for (const st::Triangle& t : outer.triangles)
    shell.triangles.push_back({t[0] + n_inner, t[1] + n_inner, t[2] + n_inner});
  for (const st::Triangle& t : wall.triangles) {
    st::Triangle s{};
    for (int k = 0; k < 3; ++k) s[k] = t[k] < m ? rim[t[k]] : outer_rim[t[k] - m] + n_inner;
    shell.triangles.push_back(s);
  }
  run.seconds[kSteps[4].first] = seconds_since(t0);
  run.shell_triangles = shell.face_count();

  // Untimed: the shell as a solid.
  run.solid = st::check_solid(shell);
}

// ---- reporting ----------------------------------------------------------------------------------

int usage() {
  std::cerr << "usage: reference-chain CASE.json [--runs N] [--json OUT.json]\n";
  return 2;
}

} // namespace

int main(int argc, char** argv) {
  std::string case_path, json_path;
  int runs = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--runs" && i + 1 < argc) {
      runs = std::atoi(argv[++i]);
      if (runs < 1) return usage();
    } else if (arg == "--json" && i + 1 < argc) {
      json_path = argv[++i];
    } else if (!arg.empty() && arg[0] != '-' && case_path.empty()) {
      case_path = arg;
    } else {
      return usage();
    }
  }
  if (case_path.empty()) return usage();

  ChainInput input;
  st::CaseFile c;
  try {
    c = st::read_case(case_path);
    input.bone = st::read_mesh(c.bone);
    input.inside = c.inside;
    input.thickness = c.thickness;
    input.resolution = c.resolution.value_or(c.thickness / 8.0);
    input.sampling_step = c.sampling_step;
    // Untimed: the loop is the kernel's boundary curve, so both chains cut along the same curve.
    const st::MeshTopology topology(input.bone);
    st::CurveOptions curve_options;
    curve_options.also_index = c.inside;
    const st::SurfaceCurve curve = st::trace_surface_curve(topology, c.boundary_points, curve_options);
    input.loop = resample_closed(curve.polyline, 1.0);
  } catch (const std::exception& e) {
    std::cerr << "reference-chain: " << e.what() << "\n";
    return 1;
  }
  input.bone_vtk = to_vtk(input.bone);
  openvdb::initialize();

  std::vector<ChainRun> results(static_cast<std::size_t>(runs));
  for (ChainRun& run : results) {
    try {
      run_chain(input, run);
    } catch (const std::exception& e) {
      run.failed = e.what();
    }
  }

  nlohmann::json report;
  report["case"] = c.name;
  report["runs"] = runs;
  report["bone_triangles"] = input.bone.face_count();
  report["loop_points"] = input.loop.size();
  report["resolution"] = input.resolution;
  nlohmann::json times = nlohmann::json::object();
  double total = 0.0;
  bool complete = true;
  std::printf("%s: %u bone triangles, loop of %zu points, voxel %.3f mm, %d runs\n", c.name.c_str(),
              input.bone.face_count(), input.loop.size(), input.resolution, runs);
  for (const auto& [key, label] : kSteps) {
    std::vector<double> samples;
    for (const ChainRun& run : results)
      if (const auto it = run.seconds.find(key); it != run.seconds.end()) samples.push_back(it->second);
    // A step counts only when it completed in every run.
    if (samples.size() != results.size()) {
      complete = false;
      std::printf("  %-32s %s\n", label, samples.empty() ? "not reached" : "failed in some runs");
      continue;
    }
    const double seconds = median(samples);
    times[key] = seconds;
    total += seconds;
    std::printf("  %-32s %8.3f s\n", label, seconds);
  }
  if (complete) {
    times["initial_template_generation"] = total;
    std::printf("  %-32s %8.3f s\n", "initial template generation", total);
  }
  report["times"] = times;

  const ChainRun& first = results.front();
  report["counts"] = {{"inner_triangles", first.inner_triangles},
                      {"inner_border_loops", first.inner_border_loops},
                      {"inner_rim_points", first.inner_rim_points},
                      {"offset_triangles", first.offset_triangles},
                      {"outer_points", first.outer_points},
                      {"outer_triangles", first.outer_triangles},
                      {"outer_border_loops", first.outer_border_loops},
                      {"shell_triangles", first.shell_triangles}};
  std::printf("  counts: inner %zu triangles (%zu border loops, rim %zu), offset %zu, outer points %zu, "
              "outer %zu triangles (%zu border loops), shell %zu\n",
              first.inner_triangles, first.inner_border_loops, first.inner_rim_points, first.offset_triangles,
              first.outer_points, first.outer_triangles, first.outer_border_loops, first.shell_triangles);
  for (const ChainRun& run : results)
    if (!run.failed.empty()) {
      report["failed"] = run.failed;
      std::printf("  FAILED: %s\n", run.failed.c_str());
      break;
    }
  for (const ChainRun& run : results)
    if (run.solid) {
      report["solid"] = solid_json(*run.solid);
      std::printf("  solid: %s; closed %s, manifold %s, oriented %s, self-intersection-free %s\n",
                  run.solid->summary().c_str(), run.solid->closed() ? "yes" : "no",
                  run.solid->manifold() ? "yes" : "no", run.solid->oriented() ? "yes" : "no",
                  run.solid->self_intersections == 0 ? "yes" : "no");
      break;
    }

  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << report.dump(2) << "\n";
    if (!out) {
      std::cerr << "reference-chain: cannot write " << json_path << "\n";
      return 1;
    }
  }
  return 0;
}
