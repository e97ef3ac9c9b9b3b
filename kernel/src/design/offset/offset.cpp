#include "st/design/offset.h"

#include "design/offset/distance_band.h"
#include "detail/format.h"
#include "st/core/errors.h"
#include "st/core/tolerances.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace st {

using namespace offset_detail;

namespace {

// ---- sizing ---------------------------------------------------------------------------------------------

/// front_only: how far behind the border the rim is contoured, min(T/2, T - 2h) (shorter for
/// coarse cells, whose contour is rough anyway).
double front_margin(double distance, double h) { return std::max(0.0, std::min(0.5 * distance, distance - 2.0 * h)); }

/// Expected number of computed nodes: the slabs on both sides of the patch, the half-cylinder
/// around its border and a ball, all of radius "reach", capped by the grown bounding box.
double estimate_nodes(const Patch& patch, const BoundingBox& box, double distance, double h, bool front_only) {
  const double reach = distance + 4.0 * h;
  const double behind = front_only ? 3.0 * h : reach;
  const double pi = std::numbers::pi;
  const double volume = patch.area * (reach + behind) + patch.border_length * 0.5 * pi * reach * reach +
                        4.0 / 3.0 * pi * reach * reach * reach;
  const Vec3 size = box.size().array() + 2.0 * reach;
  return std::min(volume, size.prod()) / (h * h * h);
}

std::string format_budget_error(double h, double nodes, double budget) {
  char msg[240];
  std::snprintf(msg, sizeof msg,
                "offset: resolution h=%.4g mm needs about %.1f million cells, over the budget of %.1f "
                "million; use a coarser resolution",
                h, nodes * 1e-6, budget * 1e-6);
  return msg;
}

} // namespace

OffsetResult offset_surface(const TriangleMesh& surface, const OffsetOptions& options) {
  const double distance = options.distance;
  if (!std::isfinite(distance) || distance <= 0.0)
    throw InvalidInput("offset: the distance must be finite and > 0 mm, got " + detail::number(distance));
  if (!std::isfinite(options.cell_size) || options.cell_size < 0.0)
    throw InvalidInput("offset: the cell size must be finite and >= 0 mm (0 = automatic), got " +
                       detail::number(options.cell_size));
  if (options.cell_size > tol::kMaxCellSizePerOffset * distance)
    throw InvalidInput("offset: the cell size " + detail::mm(options.cell_size) + " is over half the distance " +
                       detail::mm(distance));
  if (std::isnan(options.max_cells) || options.max_cells <= 0.0) throw InvalidInput("offset: max_cells must be > 0");
  if (surface.empty()) throw InvalidInput("offset: the surface has no triangles");
  if (surface.triangles.size() >= (std::size_t{1} << 28))
    throw InvalidInput("offset: the surface has more than 2^28 triangles");
  check_mesh(surface, "offset");

  const Patch patch = build_patch(surface, options.front_only);
  const BoundingBox box = bounding_box(surface);

  double h = options.cell_size;
  if (h == 0.0) {
    h = std::min(distance / 8.0, std::max(distance / 16.0, 0.5 * mean_edge_length(surface)));
    while (estimate_nodes(patch, box, distance, h, options.front_only) > options.max_cells && h < 0.5 * distance)
      h = std::min(0.5 * distance, 1.1 * h);
  }
  const double expected = estimate_nodes(patch, box, distance, h, options.front_only);
  if (expected > options.max_cells) throw InvalidInput(format_budget_error(h, expected, options.max_cells));

  // Every node lies within "reach" of the patch; keep the stored indices inside [8, 2^20 - 8).
  const double reach = distance + 4.0 * h;
  const double span = (box.size().maxCoeff() + 2.0 * reach) / h + 16.0;
  if (!(span < static_cast<double>(kIndexOffset) - 16.0)) {
    char msg[200];
    std::snprintf(msg, sizeof msg,
                  "offset: the patch spans %.0f cells along one axis at h=%.4g mm, over the grid limit "
                  "of %lld; use a coarser resolution",
                  span, h, static_cast<long long>(kIndexOffset) - 16);
    throw InvalidInput(msg);
  }

  BandParams params;
  // Nodes sit off the patch's bounding box by a fraction of a cell far from any simple ratio (2 -
  // golden ratio): a flat, axis-aligned patch (a CAD mesh, a grid; its bounding box in its plane)
  // offset by a round thickness (a whole or half number of cells, as the defaults and round user
  // values give) would otherwise put the whole offset sheet on grid nodes, which the iso margin
  // resolves into thousands of micrometre triangles.
  params.origin = box.min - tol::kGridOriginShift * h * Vec3::Ones();
  params.h = h;
  params.iso = distance;
  // Nodes up to T + h/2 spread and anchor. A cube is contoured when all its corners are computed and
  // one anchors; an anchoring node spreads, and a cube's corners are 26-neighbours of each other, so
  // every cube with an anchoring corner is complete, and a crossed cube's anchoring corner below T
  // anchors as before. Left out: cubes whose only anchoring corners lie beyond T + h/2, at the end of
  // the rim's sheet behind the border, beyond the outer cut. (T + 2h computed 17 % more nodes; the
  // guides of the bench and the tests are the same.)
  params.limit = distance + 0.5 * h;
  params.seed_radius = 1.5 * h;
  params.margin = front_margin(distance, h);
  params.front_only = options.front_only;
  params.tetrahedra = options.tetrahedra;
  params.node_cap = 4.0 * options.max_cells;
  params.expected_nodes = static_cast<std::size_t>(expected);

  DistanceBand band(patch, params);
  band.seed();
  band.grow();

  OffsetResult result;
  Contour contour = band.contour();
  if (options.front_only) {
    remove_back_islands(contour, patch);
    split_pinched_vertices(contour.mesh, contour.border_candidates);
  }
  result.surface = std::move(contour.mesh);
  result.band_voxels = band.computed_nodes();
  result.cell_size = h;
  return result;
}

} // namespace st
