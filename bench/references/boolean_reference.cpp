// boolean-reference: the guide's two Boolean operations done by an off-the-shelf library, timed on
// the operands the kernel wrote, so the benchmark can put the kernel's Boolean time next to
// CGAL's corefinement and VTK's Boolean filters on the same meshes.
//
//   boolean-reference DIR --library cgal|vtk-boolean|vtk-loop|kernel [--repeat N] [--budget S]
//                     [--max-memory-gb G] [--out RESULT.stl]
//
// DIR holds what `surgical-template design CASE --operands DIR` writes: body.stl (the closed
// template), columns.stl (the sleeve columns, united) and bores.stl (the bores, united). The guide
// is (body u columns) - bores; each run computes exactly that with the library:
//   cgal         CGAL::Polygon_mesh_processing::corefine_and_compute_union / _difference on
//                Surface_mesh<Epick::Point_3> (Exact_predicates_inexact_constructions_kernel)
//   vtk-boolean  vtkBooleanOperationPolyDataFilter (union, then difference)
//   vtk-loop     vtkLoopBooleanPolyDataFilter (union, then difference)
//   kernel       st::mesh_boolean on the same files (no seat; see README.md)
// Only the library's Boolean calls are timed (std::chrono::steady_clock); reading, conversion to the
// library's mesh, copies and the check are not. N runs (default 3) give the median of the union,
// the difference and their sum; with --budget S no further run is started once it would likely end
// after S seconds (the runs done are reported). The result of the last run is written as binary
// STL (--out, else a temporary file) and checked with st::check_solid twice: the library's mesh as
// it returned it (double coordinates, its own vertex sharing) and the STL as written and read back
// (float32, bit-equal corners welded), which is what a user gets.
//
// A library that throws, reports an error, runs out of memory or gives an empty result is a result,
// not a crash: the message goes to "failed" in the JSON. The address space is limited to G GiB
// (default 8, 0 for none), because VTK's filters can take all the machine's memory on some inputs.
// A library that crashes the process (VTK does, inside vtkIntersectionPolyDataFilter) cannot be
// caught here: run each library in its own process (bench/run_bench.py does, with a timeout) and
// read the progress on stderr ("union ...", "union: 1.2 s", VTK's messages as they arrive) to tell
// which step it was. The JSON report goes to stdout.
// Exit codes: 0 whenever the operands could be read, 1 when they cannot, 2 for bad arguments.

#include "st/boolean/boolean.h"
#include "st/core/mesh.h"
#include "st/io/mesh_io.h"
#include "st/validate/validate.h"

#include "report_json.h"
#include "vtk_convert.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/version.h>
#include <nlohmann/json.hpp>
#include <vtkBooleanOperationPolyDataFilter.h>
#include <vtkCellArray.h>
#include <vtkIdTypeArray.h>
#include <vtkLoopBooleanPolyDataFilter.h>
#include <vtkNew.h>
#include <vtkLogger.h>
#include <vtkOutputWindow.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkVersion.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <new>
#include <iostream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <sys/resource.h>
#include <unistd.h>
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
namespace PMP = CGAL::Polygon_mesh_processing;
using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Epick::Point_3>;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// One operation of one run that did not give a usable result; the message says which and why.
class StepFailed : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// The address-space limit (--max-memory-gb), for messages; 0 when there is none.
double g_memory_limit_gb = 0.0;

/// Runs `call` as the timed operation `step` ("union", "difference"): progress on stderr (so a
/// driver can tell which step a crash or a timeout hit), the seconds it took, and running out of
/// memory turned into a StepFailed that names the step.
template <class Call> double timed(const char* step, Call&& call) {
  std::cerr << "  " << step << " ..." << std::endl;
  const auto t0 = Clock::now();
  try {
    call();
  } catch (const std::bad_alloc&) {
    throw StepFailed(std::string(step) + ": out of memory" +
                     (g_memory_limit_gb > 0.0
                          ? " (limit " + std::to_string(static_cast<int>(g_memory_limit_gb)) + " GiB, --max-memory-gb)"
                          : std::string()));
  }
  const double seconds = seconds_since(t0);
  std::cerr << "  " << step << ": " << seconds << " s" << std::endl;
  return seconds;
}

struct Operands {
  TriangleMesh body, columns, bores;
};

/// The timed part of one run, seconds.
struct RunTimes {
  double unite = 0.0;
  double subtract = 0.0;
};

/// What a library gave over all runs.
struct Outcome {
  std::vector<RunTimes> runs;     ///< completed runs only
  TriangleMesh result;            ///< of the last completed run
  std::string failed;             ///< the first failure (runs stop there: the libraries are deterministic)
  RunTimes failed_run;            ///< the steps the failed run completed (0: not completed)
  std::vector<std::string> notes; ///< library messages that did not stop the run (VTK warnings, CGAL's flags)
  nlohmann::json inputs = nlohmann::json::object(); ///< the library's own view of its inputs, untimed
  double union_triangles = 0.0;                     ///< triangles of the union (last run)
};

/// Runs `run_once` up to `repeat` times; with `budget` > 0 no run is started that would likely end
/// after `budget` seconds (judged by the slowest run so far).
void repeat_runs(int repeat, double budget, Outcome& out,
                 const std::function<void(RunTimes&, TriangleMesh&)>& run_once) {
  const auto start = Clock::now();
  double slowest = 0.0;
  for (int i = 0; i < repeat; ++i) {
    if (i > 0 && budget > 0.0 && seconds_since(start) + slowest > budget) break;
    const auto t0 = Clock::now();
    RunTimes times;
    TriangleMesh result;
    try {
      run_once(times, result);
    } catch (const std::exception& e) {
      out.failed = e.what();
      out.failed_run = times;
      break;
    } catch (...) {
      out.failed = "an exception that is not a std::exception";
      out.failed_run = times;
      break;
    }
    out.runs.push_back(times);
    out.result = std::move(result);
    slowest = std::max(slowest, seconds_since(t0));
    std::cerr << "  run " << i + 1 << ": union " << times.unite << " s, difference " << times.subtract << " s\n";
  }
}

// ---- CGAL ---------------------------------------------------------------------------------------

SurfaceMesh to_cgal(const TriangleMesh& mesh, const std::string& what) {
  SurfaceMesh sm;
  sm.reserve(mesh.vertex_count(), 3 * mesh.face_count() / 2, mesh.face_count());
  std::vector<SurfaceMesh::Vertex_index> vertex;
  vertex.reserve(mesh.vertex_count());
  for (const Vec3& p : mesh.positions) vertex.push_back(sm.add_vertex(Epick::Point_3(p.x(), p.y(), p.z())));
  for (Index f = 0; f < mesh.face_count(); ++f) {
    const st::Triangle& t = mesh.triangles[f];
    if (sm.add_face(vertex[t[0]], vertex[t[1]], vertex[t[2]]) == SurfaceMesh::null_face())
      throw StepFailed(what + ": Surface_mesh::add_face refused triangle " + std::to_string(f) +
                       " (non-manifold or misoriented there)");
  }
  return sm;
}

TriangleMesh from_cgal(const SurfaceMesh& sm) {
  TriangleMesh mesh;
  std::vector<Index> index(sm.number_of_vertices() + sm.number_of_removed_vertices(), st::kInvalidIndex);
  for (const SurfaceMesh::Vertex_index v : sm.vertices()) {
    index[v.idx()] = mesh.vertex_count();
    const Epick::Point_3& p = sm.point(v);
    mesh.positions.emplace_back(p.x(), p.y(), p.z());
  }
  for (const SurfaceMesh::Face_index f : sm.faces()) {
    std::vector<Index> corners;
    for (const SurfaceMesh::Vertex_index v : CGAL::vertices_around_face(sm.halfedge(f), sm))
      corners.push_back(index[v.idx()]);
    for (std::size_t k = 1; k + 1 < corners.size(); ++k)
      mesh.triangles.push_back({corners[0], corners[k], corners[k + 1]});
  }
  return mesh;
}

/// CGAL's preconditions of corefine_and_compute_*: closed, no self-intersection, bounds a volume.
nlohmann::json cgal_input_checks(const SurfaceMesh& sm) {
  return {{"closed", CGAL::is_closed(sm)},
          {"self_intersecting", PMP::does_self_intersect(sm)},
          {"bounds_a_volume", PMP::does_bound_a_volume(sm)}};
}

Outcome run_cgal(const Operands& in, int repeat, double budget) {
  Outcome out;
  SurfaceMesh body, columns, bores;
  try {
    body = to_cgal(in.body, "body");
    if (!in.columns.empty()) columns = to_cgal(in.columns, "columns");
    bores = to_cgal(in.bores, "bores");
  } catch (const std::exception& e) {
    out.failed = std::string("conversion to Surface_mesh: ") + e.what();
    return out;
  }
  out.inputs["body"] = cgal_input_checks(body);
  if (!in.columns.empty()) out.inputs["columns"] = cgal_input_checks(columns);
  out.inputs["bores"] = cgal_input_checks(bores);

  repeat_runs(repeat, budget, out, [&](RunTimes& t, TriangleMesh& result) {
    // corefine_and_compute_* corefines its operands in place: fresh copies for every run (untimed).
    SurfaceMesh a = body, b = columns, c = bores, united, guide;
    if (in.columns.empty()) {
      united = a;
    } else {
      bool ok = false;
      t.unite = timed("union", [&] {
        try {
          ok = PMP::corefine_and_compute_union(a, b, united);
        } catch (const std::bad_alloc&) {
          throw;
        } catch (const std::exception& e) {
          throw StepFailed(std::string("union: CGAL threw: ") + e.what());
        }
      });
      if (!ok)
        throw StepFailed(
            "union: corefine_and_compute_union returned false (the output cannot be a 2-manifold surface mesh)");
    }
    out.union_triangles = static_cast<double>(united.number_of_faces());
    bool ok = false;
    t.subtract = timed("difference", [&] {
      try {
        ok = PMP::corefine_and_compute_difference(united, c, guide);
      } catch (const std::bad_alloc&) {
        throw;
      } catch (const std::exception& e) {
        throw StepFailed(std::string("difference: CGAL threw: ") + e.what());
      }
    });
    if (!ok)
      throw StepFailed("difference: corefine_and_compute_difference returned false (the output cannot be a 2-manifold "
                       "surface mesh)");
    if (guide.is_empty()) throw StepFailed("difference: CGAL gave an empty mesh");
    result = from_cgal(guide);
  });
  return out;
}

// ---- VTK ----------------------------------------------------------------------------------------

/// VTK's output window, replaced so that every error and warning of a filter and of the filters
/// it runs inside (vtkIntersectionPolyDataFilter's own warnings are "generic", with no object to
/// observe) is kept for the report, and printed to stderr at once: VTK may crash right after a
/// warning, and the driver shows the last ones.
class MessageWindow : public vtkOutputWindow {
public:
  static MessageWindow* New() {
    auto* window = new MessageWindow;
    window->InitializeObjectBase();
    return window;
  }
  void DisplayErrorText(const char* text) override { keep(true, text); }
  void DisplayWarningText(const char* text) override { keep(false, text); }
  void DisplayGenericWarningText(const char* text) override { keep(false, text); }
  void DisplayText(const char* text) override { keep(false, text); }
  void DisplayDebugText(const char*) override {}

  std::vector<std::string> errors, warnings;

private:
  void keep(bool error, const char* raw) {
    if (raw == nullptr) return;
    std::string text(raw);
    // VTK puts "ERROR: In FILE, line N\n" and "vtkClass (0x...): " before the message.
    if (text.rfind("ERROR: In ", 0) == 0 || text.rfind("Warning: In ", 0) == 0 ||
        text.rfind("Generic Warning: In ", 0) == 0)
      if (const auto line = text.find('\n'); line != std::string::npos) text = text.substr(line + 1);
    if (const auto at = text.find("): "); at != std::string::npos && at < 80 && text.rfind("vtk", 0) == 0)
      text = text.substr(at + 3);
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    if (errors.size() + warnings.size() < 20)
      std::cerr << "  vtk " << (error ? "error" : "warning") << ": " << text << std::endl;
    (error ? errors : warnings).push_back(text);
  }
};

/// The window installed by main() for the VTK libraries.
MessageWindow* g_vtk_messages = nullptr;

std::string joined(const std::vector<std::string>& messages, std::size_t at_most = 3) {
  std::string text;
  for (std::size_t i = 0; i < messages.size() && i < at_most; ++i) text += (i ? "; " : "") + messages[i];
  if (messages.size() > at_most) text += "; ... (" + std::to_string(messages.size()) + " messages)";
  return text;
}

/// vtkBooleanOperationPolyDataFilter or vtkLoopBooleanPolyDataFilter: `op` of a and b.
template <class Filter> vtkSmartPointer<vtkPolyData> vtk_boolean(vtkPolyData* a, vtkPolyData* b, int op,
                                                                 const char* step, double& seconds,
                                                                 std::vector<std::string>& notes) {
  vtkNew<Filter> filter;
  MessageWindow& messages = *g_vtk_messages;
  messages.errors.clear();
  messages.warnings.clear();
  filter->SetOperation(op);
  filter->SetInputData(0, a);
  filter->SetInputData(1, b);
  seconds = timed(step, [&] { filter->Update(); });
  if constexpr (std::is_same_v<Filter, vtkLoopBooleanPolyDataFilter>)
    if (filter->GetStatus() != 1)
      notes.push_back(std::string(step) + ": vtkLoopBooleanPolyDataFilter status " +
                      std::to_string(filter->GetStatus()) + " (0: the operation failed)");
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->DeepCopy(filter->GetOutput());
  for (const std::string& w : messages.warnings) notes.push_back(std::string(step) + ": warning: " + w);
  for (const std::string& e : messages.errors) notes.push_back(std::string(step) + ": error: " + e);
  if (result->GetNumberOfPolys() == 0)
    throw StepFailed(std::string(step) + ": VTK gave an empty surface" +
                     (messages.errors.empty() ? std::string() : " (" + joined(messages.errors) + ")"));
  return result;
}

template <class Filter>
Outcome run_vtk(const Operands& in, int repeat, double budget, int union_op, int difference_op) {
  Outcome out;
  const vtkSmartPointer<vtkPolyData> body = to_vtk(in.body), bores = to_vtk(in.bores);
  const vtkSmartPointer<vtkPolyData> columns = in.columns.empty() ? nullptr : to_vtk(in.columns);
  repeat_runs(repeat, budget, out, [&](RunTimes& t, TriangleMesh& result) {
    std::vector<std::string> notes;
    vtkSmartPointer<vtkPolyData> united = body;
    if (columns) united = vtk_boolean<Filter>(body, columns, union_op, "union", t.unite, notes);
    out.union_triangles = static_cast<double>(united->GetNumberOfPolys());
    const vtkSmartPointer<vtkPolyData> guide =
        vtk_boolean<Filter>(united, bores, difference_op, "difference", t.subtract, notes);
    result = from_vtk(guide);
    out.notes = std::move(notes); // of the last run
  });
  return out;
}

// ---- the kernel, on the same files --------------------------------------------------------------

Outcome run_kernel(const Operands& in, int repeat, double budget) {
  Outcome out;
  st::BooleanOptions options; // as the guide does: the operands are closed, no seat
  options.check_operands = false;
  repeat_runs(repeat, budget, out, [&](RunTimes& t, TriangleMesh& result) {
    TriangleMesh united = in.body;
    if (!in.columns.empty()) {
      st::BooleanResult u;
      t.unite = timed("union", [&] {
        try {
          u = st::mesh_boolean(in.body, in.columns, st::BooleanOp::Union, options);
        } catch (const std::bad_alloc&) {
          throw;
        } catch (const std::exception& e) {
          throw StepFailed(std::string("union: ") + e.what());
        }
      });
      if (u.attempts > 1) out.notes.push_back("union: perturbed by " + std::to_string(u.perturbation) + " mm");
      united = std::move(u.mesh);
    }
    out.union_triangles = united.face_count();
    st::BooleanResult d;
    t.subtract = timed("difference", [&] {
      try {
        d = st::mesh_boolean(united, in.bores, st::BooleanOp::Difference, options);
      } catch (const std::bad_alloc&) {
        throw;
      } catch (const std::exception& e) {
        throw StepFailed(std::string("difference: ") + e.what());
      }
    });
    if (d.attempts > 1) out.notes.push_back("difference: perturbed by " + std::to_string(d.perturbation) + " mm");
    if (d.mesh.empty()) throw StepFailed("difference: empty result");
    result = std::move(d.mesh);
  });
  return out;
}

// ---- reporting ----------------------------------------------------------------------------------

std::string library_version(const std::string& library) {
  if (library == "cgal") return "CGAL " CGAL_VERSION_STR;
  if (library == "kernel") return "st_kernel (this tree)";
  return std::string("VTK ") + vtkVersion::GetVTKVersion();
}

int usage() {
  std::cerr << "usage: boolean-reference DIR --library cgal|vtk-boolean|vtk-loop|kernel [--repeat N] [--budget S]"
               " [--max-memory-gb G] [--out RESULT.stl]\n";
  return 2;
}

} // namespace

int main(int argc, char** argv) {
  std::string dir, library, out_path;
  int repeat = 3;
  g_memory_limit_gb = 8.0;
  double budget = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--library" && i + 1 < argc) {
      library = argv[++i];
    } else if (arg == "--repeat" && i + 1 < argc) {
      repeat = std::atoi(argv[++i]);
      if (repeat < 1) return usage();
    } else if (arg == "--budget" && i + 1 < argc) {
      budget = std::atof(argv[++i]);
    } else if (arg == "--max-memory-gb" && i + 1 < argc) {
      g_memory_limit_gb = std::atof(argv[++i]);
    } else if (arg == "--out" && i + 1 < argc) {
      out_path = argv[++i];
    } else if (!arg.empty() && arg[0] != '-' && dir.empty()) {
      dir = arg;
    } else {
      return usage();
    }
  }
  if (dir.empty() || (library != "cgal" && library != "vtk-boolean" && library != "vtk-loop" && library != "kernel"))
    return usage();

  if (g_memory_limit_gb > 0.0) {
    // VTK's filters can take all the memory there is on some inputs (see README.md): a bound on
    // the address space turns that into a failed allocation that is reported.
    const auto bytes = static_cast<rlim_t>(g_memory_limit_gb * 1024.0 * 1024.0 * 1024.0);
    const rlimit limit{bytes, bytes};
    setrlimit(RLIMIT_AS, &limit);
  }

  Operands in;
  nlohmann::json report;
  report["library"] = library;
  report["version"] = library_version(library);
  report["operands_dir"] = dir;
  report["max_memory_gb"] = g_memory_limit_gb;
  try {
    in.body = st::read_mesh(dir + "/body.stl");
    if (std::filesystem::exists(dir + "/columns.stl")) in.columns = st::read_mesh(dir + "/columns.stl");
    in.bores = st::read_mesh(dir + "/bores.stl");
  } catch (const std::exception& e) {
    std::cerr << "boolean-reference: " << e.what() << "\n";
    return 1;
  }
  report["operands"] = {{"body_triangles", in.body.face_count()},
                        {"columns_triangles", in.columns.face_count()},
                        {"bores_triangles", in.bores.face_count()}};
  std::cerr << library << " on " << dir << ": body " << in.body.face_count() << ", columns " << in.columns.face_count()
            << ", bores " << in.bores.face_count() << " triangles, " << repeat << " runs\n";

  vtkNew<MessageWindow> vtk_messages;
  vtkOutputWindow::SetInstance(vtk_messages);
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF); // the window prints them, once
  g_vtk_messages = vtk_messages;

  Outcome outcome;
  if (library == "cgal") outcome = run_cgal(in, repeat, budget);
  else if (library == "vtk-boolean")
    outcome =
        run_vtk<vtkBooleanOperationPolyDataFilter>(in, repeat, budget, vtkBooleanOperationPolyDataFilter::VTK_UNION,
                                                   vtkBooleanOperationPolyDataFilter::VTK_DIFFERENCE);
  else if (library == "vtk-loop")
    outcome = run_vtk<vtkLoopBooleanPolyDataFilter>(in, repeat, budget, vtkLoopBooleanPolyDataFilter::VTK_UNION,
                                                    vtkLoopBooleanPolyDataFilter::VTK_DIFFERENCE);
  else outcome = run_kernel(in, repeat, budget);

  report["runs"] = outcome.runs.size();
  report["repeat"] = repeat;
  if (!outcome.inputs.empty()) report["inputs"] = outcome.inputs;
  if (!outcome.runs.empty()) {
    std::vector<double> unite, subtract, total;
    for (const RunTimes& t : outcome.runs) {
      unite.push_back(t.unite);
      subtract.push_back(t.subtract);
      total.push_back(t.unite + t.subtract);
    }
    report["times"] = {{"union", median(unite)}, {"difference", median(subtract)}, {"total", median(total)}};
    report["union_triangles"] = outcome.union_triangles;
  }
  if (!outcome.failed.empty()) {
    report["failed"] = outcome.failed;
    if (outcome.failed_run.unite > 0.0) report["failed_run_times"] = {{"union", outcome.failed_run.unite}};
  }
  if (!outcome.notes.empty()) {
    report["messages"] = outcome.notes.size() > 20
                             ? std::vector<std::string>(outcome.notes.begin(), outcome.notes.begin() + 20)
                             : outcome.notes;
    report["message_count"] = outcome.notes.size();
  }

  if (!outcome.result.empty()) {
    // The library's mesh as it returned it.
    report["solid"] = solid_json(st::check_solid(outcome.result));
    // The STL as written and read back (float32, bit-equal corners welded): what a user gets.
    const bool temporary = out_path.empty();
    const std::string path =
        temporary
            ? (std::filesystem::temp_directory_path() / ("boolean-reference-" + std::to_string(::getpid()) + ".stl"))
                  .string()
            : out_path;
    try {
      st::write_stl(outcome.result, path, "boolean-reference " + library);
      report["solid_stl"] = solid_json(st::check_solid(st::read_mesh(path)));
      if (!temporary) report["result"] = path;
    } catch (const std::exception& e) {
      report["solid_stl"] = {{"valid", false}, {"summary", std::string("cannot be written or read back: ") + e.what()}};
    }
    if (temporary) std::filesystem::remove(path);
  }
  // The verdicts: of the library's mesh, and of its STL file (what the benchmark's table shows).
  report["valid"] = report.contains("solid") && report["solid"]["valid"].get<bool>() && outcome.failed.empty();
  report["valid_stl"] =
      report.contains("solid_stl") && report["solid_stl"]["valid"].get<bool>() && outcome.failed.empty();

  if (report.contains("times"))
    std::cerr << "  median: union " << report["times"]["union"] << " s, difference " << report["times"]["difference"]
              << " s, total " << report["times"]["total"] << " s\n";
  if (!outcome.failed.empty()) std::cerr << "  FAILED: " << outcome.failed << "\n";
  if (report.contains("solid")) std::cerr << "  result: " << report["solid"]["summary"].get<std::string>() << "\n";
  if (report.contains("solid_stl"))
    std::cerr << "  as STL: " << report["solid_stl"]["summary"].get<std::string>() << "\n";
  std::cout << report.dump(2) << std::endl;
  return 0;
}
