// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Interfaces.h>
#include <vdbi/Exceptions.h>
#include <vdbi/PatchMeshes.h>

#include "support/RandomVolumes.h"
#include "support/RawExtraction.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

class TestPatchMeshes : public ::testing::Test {};


// Every patch is a 2-manifold with boundary, so the halfedge structure accepts every
// triangle; vertices are the patch's own points, shared points keep their index.
TEST_F(TestPatchMeshes, testEveryTriangleIsAccepted)
{
    for (const auto g : vdbi_test::allGenerators()) for (unsigned seed = 1; seed <= 4; ++seed) {
        const auto result = vdbi_test::extractRaw(
            *vdbi_test::randomVolume(g, seed, 10, 2 + int(seed % 5)));
        const auto patches = vdbi::toPatchMeshes(result.mesh);
        ASSERT_EQ(patches.size(), result.mesh.patches.size());
        for (std::size_t p = 0; p < patches.size(); ++p) {
            const auto& pm = patches[p];
            EXPECT_EQ(pm.a, result.mesh.patches[p].a);
            EXPECT_EQ(pm.b, result.mesh.patches[p].b);
            EXPECT_EQ(pm.mesh.n_faces(), result.mesh.patches[p].triangleCount);
            ASSERT_EQ(pm.pointIndex.size(), pm.mesh.n_vertices());
            for (auto vh : pm.mesh.vertices()) {
                const auto& q = result.mesh.points[pm.pointIndex[vh.idx()]];
                EXPECT_EQ(pm.mesh.point(vh), vdbi::TriMesh::Point(q.x(), q.y(), q.z()));
            }
        }
    }
}

// A known-bad patch (three triangles on one edge) is refused with a TopologyError.
TEST_F(TestPatchMeshes, testComplexEdgeIsRefused)
{
    vdbi::InterfaceMesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    m.patches = {{0, 1, 0, 3}};
    EXPECT_THROW(vdbi::toPatchMeshes(m), vdbi::TopologyError);
}
