// SPDX-License-Identifier: Apache-2.0
/// @file TestMeshChecker.cc
/// @brief The mesh checker accepts correct interface meshes and detects every kind of defect
/// it claims to detect (a checker that cannot fail proves nothing). The meshes come from the
/// independent plain face extraction of hand-made grids, then are broken on purpose.

#include "support/HandMadeGrids.h"
#include "support/MeshChecker.h"

#include <openvdb/openvdb.h>

#include <gtest/gtest.h>

using vdbi::Label;

class TestMeshChecker : public ::testing::Test
{
protected:
    void SetUp() override { openvdb::initialize(); }
};

namespace {

/// Appends a point with key @a key (keyScale 2) and returns its index. The key is a copy: it
/// may be one of the mesh's own, which the push_back can move (ASan found it).
unsigned
addPoint(vdbi::InterfaceMesh& mesh, const vdbi::VertexKey key)
{
    mesh.pointKeys.push_back(key);
    mesh.points.emplace_back(key[0] / 2.0, key[1] / 2.0, key[2] / 2.0);
    return unsigned(mesh.points.size() - 1);
}

/// Inserts @a tri as the last triangle of patch @a p (later patches shift).
void
insertTriangle(vdbi::InterfaceMesh& mesh, std::size_t p, const openvdb::Vec3I& tri)
{
    auto& patch = mesh.patches[p];
    mesh.triangles.insert(mesh.triangles.begin()
        + std::ptrdiff_t(patch.firstTriangle + patch.triangleCount), tri);
    ++patch.triangleCount;
    for (std::size_t q = p + 1; q < mesh.patches.size(); ++q) ++mesh.patches[q].firstTriangle;
}

void
eraseTriangle(vdbi::InterfaceMesh& mesh, std::size_t t)
{
    mesh.triangles.erase(mesh.triangles.begin() + std::ptrdiff_t(t));
    for (auto& patch : mesh.patches) {
        if (t >= patch.firstTriangle && t < patch.firstTriangle + patch.triangleCount) {
            --patch.triangleCount;
        } else if (patch.firstTriangle > t) {
            --patch.firstTriangle;
        }
    }
}

} // namespace

TEST_F(TestMeshChecker, testPlainMeshesOfWellComposedGrids)
{
    // The plain extraction of a grid without critical elements is a correct interface mesh:
    // every check passes. Its faces per label pair are the hand counts of HandMadeGrids.h,
    // which also pins those counts for the grids with critical elements.
    for (const auto& c : vdbi_test::handMadeCases()) {
        SCOPED_TRACE(c.name);
        EXPECT_EQ(vdbi_test::interfaceFacesPerPair(*c.grid), c.faces);
        if (c.criticalEdges + c.criticalVertices > 0) continue;
        const auto report = vdbi_test::checkMesh(vdbi_test::plainInterfaceMesh(*c.grid));
        EXPECT_TRUE(report.ok()) << report.summary();
        EXPECT_EQ(report.tJunctions, 0u);
    }
    const auto cube =
        vdbi_test::checkMesh(vdbi_test::plainInterfaceMesh(*vdbi_test::singleVoxel()));
    EXPECT_EQ(cube.triangles, 12u);
    EXPECT_EQ(cube.points, 8u);
    EXPECT_EQ(cube.labels.at(1).euler, 2);
    EXPECT_DOUBLE_EQ(cube.labels.at(1).volume, 1.0);
    EXPECT_DOUBLE_EQ(cube.labels.at(0).volume, -1.0);
    // Patches of three labels meeting along a line: every patch has a boundary, and every
    // boundary edge is a boundary edge of another patch.
    const auto t = vdbi_test::checkMesh(vdbi_test::plainInterfaceMesh(*vdbi_test::tJunction3()));
    EXPECT_EQ(t.patches, 6u);
    for (const auto& p : t.patchReports) EXPECT_GT(p.boundaryEdges, 0u);
    EXPECT_EQ(t.sum(&vdbi_test::PatchReport::unmatchedBoundaryEdges), 0u);
    // Nested surfaces: volumes 98 and 27, the background minus both; Euler 2, 4, 2.
    const auto shell =
        vdbi_test::checkMesh(vdbi_test::plainInterfaceMesh(*vdbi_test::hollowShellFilled()));
    EXPECT_DOUBLE_EQ(shell.labels.at(1).volume, 98.0);
    EXPECT_DOUBLE_EQ(shell.labels.at(2).volume, 27.0);
    EXPECT_DOUBLE_EQ(shell.labels.at(0).volume, -125.0);
    EXPECT_EQ(shell.labels.at(0).euler, 2);
    EXPECT_EQ(shell.labels.at(1).euler, 4);
    EXPECT_EQ(shell.labels.at(2).euler, 2);
    EXPECT_TRUE(vdbi_test::volumeEqualsFineVoxels(shell.labels.at(2), 27));
    const auto torus = vdbi_test::checkMesh(vdbi_test::plainInterfaceMesh(*vdbi_test::torusRing()));
    EXPECT_EQ(torus.labels.at(1).euler, 0);
}

TEST_F(TestMeshChecker, testWithoutKeys)
{
    // Without keys vertices are point indices and the volume comes from the points.
    auto mesh = vdbi_test::plainInterfaceMesh(*vdbi_test::hollowShell());
    mesh.pointKeys.clear();
    const auto report = vdbi_test::checkMesh(mesh);
    EXPECT_FALSE(report.usedKeys);
    EXPECT_TRUE(report.ok()) << report.summary();
    EXPECT_NEAR(report.labels.at(1).volume, 98.0, 1e-9);
    EXPECT_EQ(report.labels.at(1).euler, 4);
}

TEST_F(TestMeshChecker, testDetectsFlippedTriangle)
{
    // One triangle turned over uses a directed edge of its neighbour a second time.
    auto mesh = vdbi_test::plainInterfaceMesh(*vdbi_test::singleVoxel());
    std::swap(mesh.triangles[3][1], mesh.triangles[3][2]);
    const auto report = vdbi_test::checkMesh(mesh);
    EXPECT_FALSE(report.ok());
    EXPECT_GT(report.patchReports[0].duplicateDirectedEdges, 0u);
    EXPECT_GT(report.labels.at(1).orientationErrors, 0u);
}

TEST_F(TestMeshChecker, testDetectsHole)
{
    // A removed triangle leaves 3 edges in one triangle each: the label surfaces are open,
    // the patch has a boundary no other patch shares, and V - E + F drops from 2 to 1.
    auto mesh = vdbi_test::plainInterfaceMesh(*vdbi_test::singleVoxel());
    eraseTriangle(mesh, 5);
    const auto report = vdbi_test::checkMesh(mesh);
    EXPECT_FALSE(report.ok());
    EXPECT_EQ(report.labels.at(1).openEdges, 3u);
    EXPECT_EQ(report.labels.at(0).openEdges, 3u);
    EXPECT_EQ(report.patchReports[0].boundaryEdges, 3u);
    EXPECT_EQ(report.patchReports[0].unmatchedBoundaryEdges, 3u);
    EXPECT_EQ(report.labels.at(1).euler, 1);
    // Inside a multi-patch mesh too: a hole in patch (1,2) of corner4 is no other patch's
    // boundary.
    auto corner = vdbi_test::plainInterfaceMesh(*vdbi_test::corner4());
    std::size_t p = 0;
    while (!(corner.patches[p].a == 1 && corner.patches[p].b == 2)) ++p;
    eraseTriangle(corner, corner.patches[p].firstTriangle);
    const auto c = vdbi_test::checkMesh(corner);
    EXPECT_FALSE(c.ok());
    EXPECT_GT(c.patchReports[p].unmatchedBoundaryEdges, 0u);
}

TEST_F(TestMeshChecker, testDetectsDuplicatedTriangle)
{
    auto mesh = vdbi_test::plainInterfaceMesh(*vdbi_test::singleVoxel());
    insertTriangle(mesh, 0, mesh.triangles[2]);
    const auto report = vdbi_test::checkMesh(mesh);
    EXPECT_FALSE(report.ok());
    EXPECT_EQ(report.patchReports[0].duplicateTriangles, 1u);
    EXPECT_EQ(report.duplicateTrianglesGlobal, 1u);
    // The same triangle in two patches (turned over: a face claimed by both sides).
    auto two = vdbi_test::plainInterfaceMesh(*vdbi_test::tJunction3());
    const auto tri = two.triangles[0];
    insertTriangle(two, 1, openvdb::Vec3I(tri[0], tri[2], tri[1]));
    const auto r2 = vdbi_test::checkMesh(two);
    EXPECT_FALSE(r2.ok());
    EXPECT_EQ(r2.duplicateTrianglesGlobal, 1u);
}

TEST_F(TestMeshChecker, testDetectsDegenerateTriangle)
{
    auto mesh = vdbi_test::plainInterfaceMesh(*vdbi_test::singleVoxel());
    const auto t = mesh.triangles[0];
    insertTriangle(mesh, 0, openvdb::Vec3I(t[0], t[1], t[1]));
    const auto report = vdbi_test::checkMesh(mesh);
    EXPECT_FALSE(report.ok());
    EXPECT_EQ(report.patchReports[0].degenerateTriangles, 1u);
    // An unwelded copy of a point (same key, another index) is caught as well.
    auto copy = vdbi_test::plainInterfaceMesh(*vdbi_test::singleVoxel());
    const unsigned dup = addPoint(copy, copy.pointKeys[copy.triangles[0][0]]);
    copy.triangles[0][0] = dup;
    const auto r2 = vdbi_test::checkMesh(copy);
    EXPECT_FALSE(r2.ok());
    EXPECT_EQ(r2.duplicatePoints, 1u);
}

TEST_F(TestMeshChecker, testDetectsNonManifoldEdge)
{
    // A third triangle on an edge of the cube (a fin).
    auto mesh = vdbi_test::plainInterfaceMesh(*vdbi_test::singleVoxel());
    const auto t = mesh.triangles[0];
    const unsigned apex = addPoint(mesh, {7, 7, 7});
    insertTriangle(mesh, 0, openvdb::Vec3I(t[1], t[0], apex));
    const auto report = vdbi_test::checkMesh(mesh);
    EXPECT_FALSE(report.ok());
    EXPECT_EQ(report.patchReports[0].nonManifoldEdges, 1u);
    EXPECT_GT(report.labels.at(1).openEdges, 0u);
    // The plain extraction of two voxels sharing an edge has 4 triangles at that edge.
    const auto edge =
        vdbi_test::checkMesh(vdbi_test::plainInterfaceMesh(*vdbi_test::twoVoxelsSharingEdge()));
    EXPECT_FALSE(edge.ok());
    EXPECT_EQ(edge.patchReports[0].nonManifoldEdges, 1u);
}

TEST_F(TestMeshChecker, testDetectsTJunction)
{
    // Split one edge of one triangle at its midpoint, but not the neighbour across it: the
    // midpoint lies inside the neighbour's edge (found exactly on the keys), and the label
    // surfaces are open along it.
    auto mesh = vdbi_test::plainInterfaceMesh(*vdbi_test::singleVoxel());
    const auto t = mesh.triangles[0];
    const auto& k0 = mesh.pointKeys[t[0]];
    const auto& k1 = mesh.pointKeys[t[1]];
    const unsigned mid =
        addPoint(mesh, {(k0[0] + k1[0]) / 2, (k0[1] + k1[1]) / 2, (k0[2] + k1[2]) / 2});
    mesh.triangles[0] = openvdb::Vec3I(t[0], mid, t[2]);
    insertTriangle(mesh, 0, openvdb::Vec3I(mid, t[1], t[2]));
    const auto report = vdbi_test::checkMesh(mesh);
    EXPECT_FALSE(report.ok());
    EXPECT_EQ(report.tJunctions, 1u);
    EXPECT_GT(report.labels.at(1).openEdges, 0u);
}

TEST_F(TestMeshChecker, testDetectsTwoClosedFansAtVertex)
{
    // Two cubes sharing only a corner: every edge is fine, but the shared vertex has two
    // closed fans (the pinch that §2's antipodal rule exists for).
    const auto report =
        vdbi_test::checkMesh(vdbi_test::plainInterfaceMesh(*vdbi_test::twoVoxelsSharingVertex()));
    EXPECT_FALSE(report.ok());
    EXPECT_EQ(report.patchReports[0].nonManifoldEdges, 0u);
    EXPECT_EQ(report.patchReports[0].closedFanPlusMore, 1u);
    EXPECT_EQ(report.labels.at(1).badFanVertices, 1u);
    EXPECT_EQ(report.labels.at(0).badFanVertices, 1u);
    EXPECT_EQ(report.labels.at(1).openEdges, 0u);
}

TEST_F(TestMeshChecker, testOpenFansAndClosedFanPlusMore)
{
    // Inside a patch, a boundary may touch itself: two triangles sharing only a vertex give
    // two open fans there, which is allowed (counted). A closed fan plus anything else is not.
    vdbi::InterfaceMesh bowtie;
    bowtie.keyScale = 2;
    const unsigned c = addPoint(bowtie, {0, 0, 0});
    const unsigned a1 = addPoint(bowtie, {2, 0, 0}), a2 = addPoint(bowtie, {2, 2, 0});
    const unsigned b1 = addPoint(bowtie, {-2, 0, 0}), b2 = addPoint(bowtie, {-2, -2, 0});
    bowtie.triangles = {openvdb::Vec3I(c, a1, a2), openvdb::Vec3I(c, b1, b2)};
    vdbi::InterfacePatch patch;
    patch.a = 1;
    patch.b = 2;
    patch.triangleCount = 2;
    bowtie.patches = {patch};
    const auto open = vdbi_test::checkMesh(bowtie);
    EXPECT_EQ(open.patchReports[0].severalOpenFans, 1u);
    EXPECT_EQ(open.patchReports[0].closedFanPlusMore, 0u);
    EXPECT_EQ(open.patchReports[0].nonManifoldEdges, 0u);

    auto mesh = vdbi_test::plainInterfaceMesh(*vdbi_test::singleVoxel());
    const unsigned corner = mesh.triangles[0][0];
    const vdbi::VertexKey k = mesh.pointKeys[corner]; // a copy: addPoint grows pointKeys
    const unsigned p1 = addPoint(mesh, {k[0] + 10, k[1] + 20, k[2]});
    const unsigned p2 = addPoint(mesh, {k[0] + 20, k[1] + 10, k[2] + 4});
    insertTriangle(mesh, 0, openvdb::Vec3I(corner, p1, p2));
    const auto closed = vdbi_test::checkMesh(mesh);
    EXPECT_FALSE(closed.ok());
    EXPECT_EQ(closed.patchReports[0].closedFanPlusMore, 1u);
}

TEST_F(TestMeshChecker, testVoxelSetEuler)
{
    // V - E + F - C of unions of closed cubes: a cube 1, a ring 0, a shell around a cavity 2,
    // two cubes sharing a corner (contractible) 1, an 8^3 tile 1.
    EXPECT_EQ(vdbi_test::voxelSetEuler(*vdbi_test::singleVoxel(), 1), 1);
    EXPECT_EQ(vdbi_test::voxelSetEuler(*vdbi_test::torusRing(), 1), 0);
    EXPECT_EQ(vdbi_test::voxelSetEuler(*vdbi_test::hollowShell(), 1), 2);
    EXPECT_EQ(vdbi_test::voxelSetEuler(*vdbi_test::twoVoxelsSharingVertex(), 1), 1);
    EXPECT_EQ(vdbi_test::voxelSetEuler(*vdbi_test::activeTileGrid(), 3), 1);
}

TEST_F(TestMeshChecker, testCompareWithPlainFaces)
{
    // The plain extraction equals itself; a mesh with one triangle re-split differently, or
    // one face missing, does not.
    const auto grid = vdbi_test::torusRing();
    const auto mesh = vdbi_test::plainInterfaceMesh(*grid);
    EXPECT_EQ(vdbi_test::compareWithPlainFaces(mesh, *grid), "");
    auto missing = mesh;
    eraseTriangle(missing, 0);
    EXPECT_NE(vdbi_test::compareWithPlainFaces(missing, *grid), "");
    auto flipped = mesh;
    std::swap(flipped.triangles[4][0], flipped.triangles[4][1]);
    EXPECT_NE(vdbi_test::compareWithPlainFaces(flipped, *grid), "");
    EXPECT_EQ(vdbi_test::compareMeshes(mesh, mesh), "");
    EXPECT_NE(vdbi_test::compareMeshes(mesh, flipped), "");
}
