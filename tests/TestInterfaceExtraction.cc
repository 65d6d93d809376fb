// SPDX-License-Identifier: Apache-2.0

#include <vdbi/CriticalElements.h>
#include <vdbi/Fattening.h>
#include <vdbi/InterfaceExtraction.h>
#include <vdbi/Interfaces.h>
#include <vdbi/RefinedLabels.h>

#include "support/MeshChecker.h"
#include "support/RawExtraction.h"

#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <set>
#include <utility>
#include <vector>

using openvdb::Coord;

class TestInterfaceExtraction : public ::testing::Test {};

namespace {

openvdb::Int32Grid::Ptr
gridOf(const std::vector<std::pair<Coord, int>>& voxels, int background = 0)
{
    auto grid = openvdb::Int32Grid::create(background);
    auto acc = grid->getAccessor();
    for (const auto& v : voxels) acc.setValueOn(v.first, v.second);
    return grid;
}

} // namespace

// A single voxel: one patch (0, 1), its 6 faces as 12 triangles on the cube's 8 corners,
// every normal pointing from 0 into 1, i.e. into the cube.
TEST_F(TestInterfaceExtraction, testSingleVoxel)
{
    const auto r = vdbi_test::extractRaw(*gridOf({{Coord(2, 3, 4), 1}}));
    const auto& m = r.mesh;
    ASSERT_EQ(m.patches.size(), 1u);
    EXPECT_EQ(m.patches[0].a, 0);
    EXPECT_EQ(m.patches[0].b, 1);
    EXPECT_EQ(m.triangles.size(), 12u);
    EXPECT_EQ(m.points.size(), 8u);
    // The voxel cube spans index [c - 0.5, c + 0.5] around its centre (OpenVDB convention).
    for (const auto& p : m.points) {
        EXPECT_TRUE(p.x() == 1.5 || p.x() == 2.5);
        EXPECT_TRUE(p.y() == 2.5 || p.y() == 3.5);
        EXPECT_TRUE(p.z() == 3.5 || p.z() == 4.5);
    }
    // Inward normals: the signed volume of the patch as oriented is minus one voxel.
    double volume = 0;
    for (const auto& t : m.triangles) {
        volume += m.points[t[0]].dot(m.points[t[1]].cross(m.points[t[2]])) / 6.0;
    }
    EXPECT_DOUBLE_EQ(volume, -1.0);
}

// Two face-adjacent voxels of labels 1 and 2: patches (0,1) and (0,2) with 5 faces each and
// (1,2) with the shared face; 12 distinct corners.
TEST_F(TestInterfaceExtraction, testTwoLabels)
{
    const auto r = vdbi_test::extractRaw(*gridOf({{Coord(0, 0, 0), 1}, {Coord(1, 0, 0), 2}}));
    const auto& m = r.mesh;
    ASSERT_EQ(m.patches.size(), 3u);
    EXPECT_EQ(m.patches[0].triangleCount, 10u);
    EXPECT_EQ(m.patches[1].triangleCount, 10u);
    EXPECT_EQ(m.patches[2].a, 1);
    EXPECT_EQ(m.patches[2].b, 2);
    EXPECT_EQ(m.patches[2].triangleCount, 2u);
    EXPECT_EQ(m.points.size(), 12u);
    // The shared face points from 1 (x < 1) into 2 (x > 1): +x.
    const auto& t = m.triangles[m.patches[2].firstTriangle];
    const auto n = (m.points[t[1]] - m.points[t[0]]).cross(m.points[t[2]] - m.points[t[0]]);
    EXPECT_GT(n.x(), 0.0);
}

// Two voxels sharing only an edge: the edge's N1 and its end points' N2 go to the dominant
// background, which cuts 17 subvoxels from each voxel (the union of a 1x1x5 column and two
// 2x2x2 corners of each 5^3). Coarse faces with a split edge become fans from their centre.
TEST_F(TestInterfaceExtraction, testEdgeContactIsSeparated)
{
    const auto r = vdbi_test::extractRaw(*gridOf({{Coord(0, 0, 0), 1}, {Coord(1, 1, 0), 1}}));
    EXPECT_EQ(r.statistics.criticalEdges, 1u);
    EXPECT_EQ(r.statistics.criticalVertices, 2u);
    EXPECT_EQ(r.statistics.subdividedVoxels, 12u);
    EXPECT_EQ(r.statistics.relabelledSubvoxels, 34u);
    EXPECT_EQ(r.statistics.subdivision, 5);
    ASSERT_EQ(r.mesh.patches.size(), 1u);
    // Every vertex key is on the key grid: 2s per voxel, fine points even, centres odd*s.
    EXPECT_EQ(r.mesh.keyScale, 10);
    std::set<vdbi::VertexKey> keys(r.mesh.pointKeys.begin(), r.mesh.pointKeys.end());
    EXPECT_EQ(keys.size(), r.mesh.points.size()); // no duplicate vertices
}

// A block of subdivided voxels (s = 6) holding 24^3 isolated fine cubes of label 1, one at
// every even fine point: 8 corners each, so the block emits 110,592 keys, more than its
// 16-bit corner indices can hold. Exact counts, and a closed manifold.
TEST_F(TestInterfaceExtraction, testBlockWithMoreThan65536Keys)
{
    const int s = 6;
    vdbi::RefinedLabels refined;
    auto coarse = openvdb::Int32Grid::create(0);
    refined.fine = openvdb::Int32Grid::create(0);
    refined.subdivided = openvdb::MaskGrid::create(false);
    refined.subdivision = s;
    coarse->tree().setValueOn(Coord(0, 0, 0)); // the block's leaf exists
    auto fine = refined.fine->getAccessor();
    auto mask = refined.subdivided->getAccessor();
    for (int x = 0; x < 8; ++x) for (int y = 0; y < 8; ++y) for (int z = 0; z < 8; ++z) {
        mask.setValueOn(Coord(x, y, z));
    }
    for (int x = 0; x < 8 * s; x += 2) for (int y = 0; y < 8 * s; y += 2) {
        for (int z = 0; z < 8 * s; z += 2) fine.setValueOn(Coord(x, y, z), 1);
    }
    refined.coarse = coarse;
    vdbi::ExtractionOptions options;
    options.pointKeys = true;
    const vdbi::InterfaceMesh mesh = vdbi::extractInterfacePatches(refined, options);
    const std::size_t cubes = 24 * 24 * 24;
    ASSERT_EQ(mesh.patches.size(), 1u);
    EXPECT_EQ(mesh.patches[0].a, 0);
    EXPECT_EQ(mesh.patches[0].b, 1);
    EXPECT_EQ(mesh.triangles.size(), 12 * cubes);
    EXPECT_EQ(mesh.points.size(), 8 * cubes);
    const vdbi_test::MeshReport report = vdbi_test::checkMesh(mesh);
    EXPECT_TRUE(report.ok()) << report.summary();
}

// The same mesh, bit for bit, for the serial fallback, one thread and all threads, on a
// volume with thousands of critical elements across many leaves.
TEST_F(TestInterfaceExtraction, testThreadIndependence)
{
    std::vector<std::pair<Coord, int>> v;
    unsigned state = 99;
    for (int x = 0; x < 36; ++x) for (int y = 0; y < 20; ++y) for (int z = 0; z < 20; ++z) {
        state = state * 1664525u + 1013904223u;
        if ((state >> 28) < 9) v.push_back({Coord(x - 18, y, z + 5), int(state >> 29) - 2});
    }
    const auto grid = gridOf(v);
    vdbi::Options serial;
    serial.repair.threaded = false;
    const auto a = vdbi_test::extractRaw(*grid, serial);
    vdbi::Result b;
    tbb::task_arena(1).execute([&] { b = vdbi_test::extractRaw(*grid); });
    const auto c = vdbi_test::extractRaw(*grid);
    ASSERT_GT(a.statistics.criticalEdges, 1000u);
    EXPECT_EQ(vdbi_test::compareMeshes(a.mesh, b.mesh), "");
    EXPECT_EQ(vdbi_test::compareMeshes(a.mesh, c.mesh), "");
}

// Options are checked before any work.
TEST_F(TestInterfaceExtraction, testInvalidOptionsAreRejected)
{
    const auto grid = gridOf({{Coord(0, 0, 0), 1}});
    vdbi::Options o;
    o.edgeLength = -1;
    EXPECT_THROW(vdbi::extractInterfaces(*grid, o), openvdb::ValueError);
    o = vdbi::Options();
    o.repair.constraints = {{1, 1, 2}};
    EXPECT_THROW(vdbi::extractInterfaces(*grid, o), openvdb::ValueError);
    o.repair.constraints = {{1, 2, 2}};
    EXPECT_THROW(vdbi::extractInterfaces(*grid, o), openvdb::ValueError);
    o.repair.constraints = {{1, 2, 3}, {1, 3, 2}};
    EXPECT_THROW(vdbi::extractInterfaces(*grid, o), openvdb::ValueError);
    o.repair.constraints = {{1, 2, 3}, {4, 5, 3}};
    EXPECT_NO_THROW(vdbi::extractInterfaces(*grid, o));
    // Remeshed tiles would not stitch: a region is extracted raw.
    o = vdbi::Options();
    o.region = openvdb::CoordBBox(Coord(0, 0, 0), Coord(7, 7, 7));
    EXPECT_THROW(vdbi::extractInterfaces(*grid, o), openvdb::ValueError);
    o.remesh = false;
    EXPECT_NO_THROW(vdbi::extractInterfaces(*grid, o));
}
