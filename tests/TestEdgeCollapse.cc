// SPDX-License-Identifier: Apache-2.0

#include <vdbi/EdgeCollapse.h>
#include <vdbi/Interfaces.h>
#include <vdbi/PatchMeshes.h>

#include "support/RandomVolumes.h"
#include "support/RawExtraction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

class TestEdgeCollapse : public ::testing::Test {};

namespace {

using vdbi::TriMesh;

/// Every connectivity field, point and deletion flag of @a a and @a b that differs, as text
/// (empty when they are the same mesh, handle for handle).
std::string
connectivityDifference(const TriMesh& a, const TriMesh& b)
{
    if (a.n_vertices() != b.n_vertices() || a.n_halfedges() != b.n_halfedges()
        || a.n_faces() != b.n_faces()) {
        return "element counts differ";
    }
    std::string diff;
    auto note = [&](const std::string& what, int idx) {
        if (diff.size() < 400) diff += what + " " + std::to_string(idx) + "; ";
    };
    for (int i = 0; i < int(a.n_vertices()); ++i) {
        const TriMesh::VertexHandle v(i);
        if (a.halfedge_handle(v) != b.halfedge_handle(v)) note("vertex halfedge", i);
        if (a.point(v) != b.point(v)) note("vertex point", i);
        if (a.status(v).deleted() != b.status(v).deleted()) note("vertex deleted", i);
    }
    for (int i = 0; i < int(a.n_halfedges()); ++i) {
        const TriMesh::HalfedgeHandle h(i);
        if (a.to_vertex_handle(h) != b.to_vertex_handle(h)) note("halfedge vertex", i);
        if (a.next_halfedge_handle(h) != b.next_halfedge_handle(h)) note("halfedge next", i);
        if (a.prev_halfedge_handle(h) != b.prev_halfedge_handle(h)) note("halfedge prev", i);
        if (a.face_handle(h) != b.face_handle(h)) note("halfedge face", i);
        if (a.has_halfedge_status() && a.status(h).deleted() != b.status(h).deleted()) {
            note("halfedge deleted", i);
        }
    }
    for (int i = 0; i < int(a.n_edges()); ++i) {
        const TriMesh::EdgeHandle e(i);
        if (a.status(e).deleted() != b.status(e).deleted()) note("edge deleted", i);
    }
    for (int i = 0; i < int(a.n_faces()); ++i) {
        const TriMesh::FaceHandle f(i);
        if (a.halfedge_handle(f) != b.halfedge_handle(f)) note("face halfedge", i);
        if (a.status(f).deleted() != b.status(f).deleted()) note("face deleted", i);
    }
    return diff;
}

/// Patch meshes of seeded random volumes: open patches whose boundaries touch themselves,
/// closed ones, tiny ones.
std::vector<TriMesh>
randomPatchMeshes(std::uint64_t seed)
{
    std::vector<TriMesh> meshes;
    for (const auto g : vdbi_test::allGenerators()) {
        const auto result = vdbi_test::extractRaw(
            *vdbi_test::randomVolume(g, seed, 8, 2 + int(seed % 4)));
        for (auto& pm : vdbi::toPatchMeshes(result.mesh)) meshes.push_back(std::move(pm.mesh));
    }
    return meshes;
}

void
requestStatus(TriMesh& mesh, bool halfedgeStatus)
{
    mesh.request_vertex_status();
    mesh.request_edge_status();
    mesh.request_face_status();
    if (halfedgeStatus) mesh.request_halfedge_status();
}

} // namespace


// The link-condition test and the valence agree with OpenMesh's on every halfedge and vertex.
TEST_F(TestEdgeCollapse, testSameDecisionsAsOpenMesh)
{
    std::size_t allowed = 0, refused = 0;
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
        for (TriMesh& mesh : randomPatchMeshes(seed)) {
            requestStatus(mesh, false);
            for (const auto v : mesh.vertices()) {
                ASSERT_EQ(vdbi::vertexValence(mesh, v), int(mesh.valence(v)));
            }
            for (const auto h : mesh.halfedges()) {
                const bool ours = vdbi::isCollapseOk(mesh, h);
                ASSERT_EQ(ours, mesh.is_collapse_ok(h)) << "halfedge " << h.idx();
                ++(ours ? allowed : refused);
            }
        }
    }
    // Both answers occur often: the comparison means something.
    EXPECT_GT(allowed, 1000u);
    EXPECT_GT(refused, 1000u);
}

// Random sequences of collapses leave exactly the connectivity (every handle, every deletion
// flag) that OpenMesh's collapse() leaves, with and without halfedge status.
TEST_F(TestEdgeCollapse, testSameEditsAsOpenMesh)
{
    std::size_t collapses = 0, removedFaces = 0;
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
        vdbi_test::Rng rng(seed);
        for (TriMesh& original : randomPatchMeshes(seed)) {
            const bool halfedgeStatus = rng.chance(0.5);
            TriMesh theirs = original, ours = original;
            requestStatus(theirs, halfedgeStatus);
            requestStatus(ours, halfedgeStatus);
            const int attempts = std::min(2 * int(original.n_halfedges()), 300);
            for (int k = 0; k < attempts; ++k) {
                const TriMesh::HalfedgeHandle h(int(rng.below(theirs.n_halfedges())));
                const bool ok = theirs.is_collapse_ok(h);
                ASSERT_EQ(vdbi::isCollapseOk(ours, h), ok);
                if (!ok) continue;
                // Each side of the edge with a triangle loses it.
                const TriMesh::HalfedgeHandle o = theirs.opposite_halfedge_handle(h);
                removedFaces += !theirs.is_boundary(h) + !theirs.is_boundary(o);
                theirs.collapse(h);
                vdbi::collapseEdge(ours, h);
                ++collapses;
                const std::string diff = connectivityDifference(theirs, ours);
                ASSERT_TRUE(diff.empty()) << "after collapsing halfedge " << h.idx() << ": "
                                          << diff;
            }
            // And the same after compaction, ours and the library's.
            theirs.garbage_collection();
            vdbi::collectGarbage(ours);
            ASSERT_TRUE(connectivityDifference(theirs, ours).empty());
        }
    }
    EXPECT_GT(collapses, 1000u);
    EXPECT_GT(removedFaces, 1000u);
}
