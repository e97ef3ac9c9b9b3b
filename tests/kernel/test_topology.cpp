// A mesh's derived connectivity: every half-edge's opposite found at once, per vertex, is the one
// found for it alone, on meshes with borders, non-manifold, turned and degenerate faces.

#include "helpers.h"

#include "st/core/topology.h"

#include <gtest/gtest.h>

#include <vector>

namespace st {
namespace {

using test::awkward_meshes;

TEST(MeshTopology, AllOppositesAreEachHalfEdgesOwn) {
  for (const TriangleMesh& mesh : awkward_meshes()) {
    const MeshTopology topology(mesh);
    const MeshTopology kept(mesh, MeshTopology::KeepOpposites{});
    const std::vector<Index> all = topology.all_opposites();
    ASSERT_EQ(all.size(), 3 * mesh.face_count());
    std::size_t borders = 0;
    for (Index h = 0; h < all.size(); ++h) {
      EXPECT_EQ(all[h], topology.opposite(h)) << h;
      EXPECT_EQ(kept.opposite(h), topology.opposite(h)) << h;
      borders += all[h] == kInvalidIndex;
    }
    EXPECT_GT(borders, 0u); // each mesh has edges without an opposite
    EXPECT_EQ(kept.all_opposites(), all);
  }
}

} // namespace
} // namespace st
