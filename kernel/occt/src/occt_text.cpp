#include "st/occt/occt_text.h"

#include "st/core/errors.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <Font_BRepTextBuilder.hxx>
#include <Font_FontMgr.hxx>
#include <GCPnts_QuasiUniformDeflection.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Ax3.hxx>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <mutex>

namespace st {

namespace {

constexpr const char* kLabelFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
/// Shortest edge of an outline polygon, mm.
constexpr double kMinOutlineEdge_mm = 0.15;

/// The wire as one closed polygon: its edges in order, each from its start to its end as the wire
/// runs, the curves sampled within `deflection`.
std::vector<Point2> wire_polygon(const TopoDS_Wire& wire, const TopoDS_Face& face, double deflection) {
  std::vector<Point2> points;
  for (BRepTools_WireExplorer we(wire, face); we.More(); we.Next()) {
    const TopoDS_Edge& edge = we.Current();
    const BRepAdaptor_Curve curve(edge);
    std::vector<Point2> run;
    GCPnts_QuasiUniformDeflection sampler(curve, deflection);
    if (sampler.IsDone() && sampler.NbPoints() >= 2) {
      for (int i = 1; i <= sampler.NbPoints(); ++i) {
        const gp_Pnt q = sampler.Value(i);
        run.push_back({q.X(), q.Y()});
      }
    } else {
      for (const double u : {curve.FirstParameter(), curve.LastParameter()}) {
        const gp_Pnt q = curve.Value(u);
        run.push_back({q.X(), q.Y()});
      }
    }
    if (edge.Orientation() == TopAbs_REVERSED) std::reverse(run.begin(), run.end());
    run.pop_back(); // the next edge starts there
    points.insert(points.end(), run.begin(), run.end());
  }
  // No edge shorter than kMinOutlineEdge_mm: the guide's Boolean operation meets the text's walls in
  // float coordinates, where much shorter edges collapse.
  std::vector<Point2> kept;
  for (const Point2& q : points)
    if (kept.empty() || std::hypot(q[0] - kept.back()[0], q[1] - kept.back()[1]) >= kMinOutlineEdge_mm)
      kept.push_back(q);
  while (kept.size() > 3 &&
         std::hypot(kept.front()[0] - kept.back()[0], kept.front()[1] - kept.back()[1]) < kMinOutlineEdge_mm)
    kept.pop_back();
  return kept;
}

/// The font at `height`: through the font manager, else the file at its Debian path.
bool init_font(Font_BRepFont& font, double height) {
  // The font manager is one shared instance: its first search is not safe from two threads.
  static std::mutex search;
  const std::lock_guard<std::mutex> lock(search);
  if (font.FindAndInit(kLabelFont, Font_FontAspect_Regular, height, Font_StrictLevel_Aliases)) return true;
  return std::filesystem::exists(kLabelFontPath) && font.Init(kLabelFontPath, height, 0);
}

/// The outlines of `text` at font size `size`, as the font draws them (baseline at y = 0).
std::vector<LabelPolygon> font_outlines(const std::string& text, double size, double deflection) {
  std::vector<LabelPolygon> polygons;
  try {
    Font_BRepFont font;
    if (!init_font(font, size))
      throw GeometryError(std::string("labels: the font ") + kLabelFont +
                          " was not found (Debian: fonts-dejavu-core, " + kLabelFontPath + ")");
    Font_BRepTextBuilder builder;
    const TopoDS_Shape shape = builder.Perform(font, NCollection_String(text.c_str()), gp_Ax3());
    for (TopExp_Explorer fx(shape, TopAbs_FACE); fx.More(); fx.Next()) {
      const TopoDS_Face face = TopoDS::Face(fx.Current());
      const TopoDS_Wire outer = BRepTools::OuterWire(face);
      LabelPolygon polygon;
      polygon.loops.push_back(wire_polygon(outer, face, deflection));
      for (TopExp_Explorer wx(face, TopAbs_WIRE); wx.More(); wx.Next())
        if (!wx.Current().IsSame(outer))
          polygon.loops.push_back(wire_polygon(TopoDS::Wire(wx.Current()), face, deflection));
      polygons.push_back(std::move(polygon));
    }
  } catch (const Standard_Failure& e) {
    const char* message = e.GetMessageString();
    throw GeometryError(std::string("label text: OpenCASCADE failed (") + e.DynamicType()->Name() + ")" +
                        (message && *message ? std::string(": ") + message : std::string()));
  }
  return polygons;
}

struct Extent {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
};

Extent extent(const std::vector<LabelPolygon>& polygons) {
  Extent e;
  for (const auto& polygon : polygons)
    for (const auto& loop : polygon.loops)
      for (const Point2& q : loop)
        e.x0 = std::min(e.x0, q[0]), e.x1 = std::max(e.x1, q[0]), e.y0 = std::min(e.y0, q[1]),
        e.y1 = std::max(e.y1, q[1]);
  return e;
}

/// A capital H's height per unit of font size (DejaVu Sans: 0.729).
double cap_height_ratio() {
  static const double ratio = [] {
    const Extent e = extent(font_outlines("H", 10.0, 1e-3));
    if (!(e.y1 > e.y0)) throw GeometryError(std::string("labels: the font ") + kLabelFont + " draws no capital H");
    return (e.y1 - e.y0) / 10.0;
  }();
  return ratio;
}

} // namespace

std::vector<LabelPolygon> text_outlines(const std::string& text, double height, double deflection) {
  if (!(height > 0.0) || !std::isfinite(height)) throw InvalidInput("label text: height must be finite and > 0");
  if (!(deflection > 0.0) || !std::isfinite(deflection))
    throw InvalidInput("label text: deflection must be finite and > 0");
  const auto length = utf8_length(text);
  if (!length) throw InvalidInput("label text is not valid UTF-8");
  if (*length == 0) throw InvalidInput("label text is empty");
  std::vector<LabelPolygon> polygons = font_outlines(text, height / cap_height_ratio(), deflection);
  if (polygons.empty()) throw InvalidInput("label text '" + text + "' has nothing to draw (only spaces?)");
  const Extent e = extent(polygons);
  const double cx = 0.5 * (e.x0 + e.x1), cy = 0.5 * (e.y0 + e.y1);
  for (auto& polygon : polygons)
    for (auto& loop : polygon.loops)
      for (Point2& q : loop) q = {q[0] - cx, q[1] - cy};
  return polygons;
}

void fill_label_outlines(std::vector<LabelSpec>& labels) {
  for (LabelSpec& label : labels) {
    check_label(label);
    label.outlines = text_outlines(label.text, label.height);
  }
}

} // namespace st
