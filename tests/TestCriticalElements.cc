// SPDX-License-Identifier: Apache-2.0

#include <vdbi/CriticalElements.h>
#include <vdbi/LabelGrid.h>

#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <utility>
#include <vector>

using openvdb::Coord;

class TestCriticalElements : public ::testing::Test {};

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

// A single voxel's boundary is a cube: a 2-manifold, nothing critical.
TEST_F(TestCriticalElements, testSingleVoxel)
{
    const auto e = vdbi::findCriticalElements(*gridOf({{Coord(3, -2, 7), 1}}));
    EXPECT_TRUE(e.empty());
}

// Two voxels sharing only the edge from (1,1,0) along z: that edge is critical for 1 and for
// the background (its two other voxels); the background 0 dominates. Its two end points are
// critical; neither block is an antipodal configuration.
TEST_F(TestCriticalElements, testTwoVoxelsSharingAnEdge)
{
    const auto e = vdbi::findCriticalElements(*gridOf({{Coord(0, 0, 0), 1}, {Coord(1, 1, 0), 1}}));
    ASSERT_EQ(e.edges.size(), 1u);
    EXPECT_EQ(e.edges[0].origin, Coord(1, 1, 0));
    EXPECT_EQ(e.edges[0].axis, 2);
    EXPECT_EQ(e.edges[0].label, 0);
    ASSERT_EQ(e.vertices.size(), 2u);
    EXPECT_EQ(e.vertices[0].point, Coord(1, 1, 0));
    EXPECT_EQ(e.vertices[1].point, Coord(1, 1, 1));
    EXPECT_EQ(e.singularVertexCount(), 0u);
    EXPECT_TRUE(e.faces.empty());
}

// Two voxels sharing only a vertex: the antipodal configuration (§2 rule 2), no edge.
TEST_F(TestCriticalElements, testTwoVoxelsSharingAVertex)
{
    const auto e = vdbi::findCriticalElements(*gridOf({{Coord(0, 0, 0), 1}, {Coord(1, 1, 1), 1}}));
    EXPECT_TRUE(e.edges.empty());
    ASSERT_EQ(e.vertices.size(), 1u);
    EXPECT_EQ(e.vertices[0].point, Coord(1, 1, 1));
    EXPECT_TRUE(e.vertices[0].isSingular);
    EXPECT_EQ(e.vertices[0].label, 0);
}

// A 2x2x2 block with an antipodal pair of 1 and six voxels of 2: the centre is critical for
// 1 (two antipodal voxels) and for 2 (six, with two antipodal others); 1 dominates. No face
// of any block there is diagonal, so no edge is critical.
TEST_F(TestCriticalElements, testAntipodalPairInABlock)
{
    std::vector<std::pair<Coord, int>> v;
    for (int n = 0; n < 8; ++n) {
        const Coord c(n & 1, (n >> 1) & 1, (n >> 2) & 1);
        v.push_back({c, (n == 0 || n == 7) ? 1 : 2});
    }
    const auto e = vdbi::findCriticalElements(*gridOf(v));
    EXPECT_TRUE(e.edges.empty());
    ASSERT_EQ(e.vertices.size(), 1u);
    EXPECT_EQ(e.vertices[0].point, Coord(1, 1, 1));
    EXPECT_EQ(e.vertices[0].label, 1);
    EXPECT_EQ(e.singularVertexCount(), 1u);
}

// A 2x2 checkerboard of labels 1 and 2 (one layer): the central edge is critical for both,
// 1 dominates; its end points are critical.
TEST_F(TestCriticalElements, testCheckerboard)
{
    const auto grid = gridOf({{Coord(0, 0, 0), 1}, {Coord(1, 0, 0), 2},
                              {Coord(1, 1, 0), 1}, {Coord(0, 1, 0), 2}});
    const auto e = vdbi::findCriticalElements(*grid);
    ASSERT_EQ(e.edges.size(), 1u);
    EXPECT_EQ(e.edges[0].label, 1);
    EXPECT_EQ(e.vertices.size(), 2u);
    for (const auto& v : e.vertices) EXPECT_EQ(v.label, 1);

    // A user priority that puts 2 first makes 2 dominant.
    vdbi::RepairOptions options;
    options.priority = vdbi::LabelPriority({2});
    const auto p = vdbi::findCriticalElements(*grid, options);
    ASSERT_EQ(p.edges.size(), 1u);
    EXPECT_EQ(p.edges[0].label, 2);
}

// A hollow 3x3x3 shell (with an empty or a labelled cavity) is a pair of nested spheres.
TEST_F(TestCriticalElements, testHollowShell)
{
    for (int cavity : {0, 2}) {
        std::vector<std::pair<Coord, int>> v;
        for (int x = 0; x < 3; ++x) for (int y = 0; y < 3; ++y) for (int z = 0; z < 3; ++z) {
            v.push_back({Coord(x, y, z), (x == 1 && y == 1 && z == 1) ? cavity : 1});
        }
        EXPECT_TRUE(vdbi::findCriticalElements(*gridOf(v)).empty()) << "cavity " << cavity;
    }
}

// Critical elements far from the origin and at negative coordinates, across leaf borders:
// the owner of an element is the block of its min corner, whichever leaf the voxels are in.
TEST_F(TestCriticalElements, testAcrossLeafBorders)
{
    for (const Coord& base : {Coord(7, 7, 7), Coord(-1, -1, -1), Coord(-8, 15, 1000001)}) {
        const auto e = vdbi::findCriticalElements(*gridOf(
            {{base, 1}, {base.offsetBy(1, 1, 0), 1}, {base.offsetBy(0, 0, 1), 1}}));
        // (base) and (base+(1,1,0)) share the edge at base+(1,1,0) along z; base+(0,0,1)
        // touches base+(1,1,0) at the point base+(1,1,1) only through that same edge's end.
        ASSERT_EQ(e.edges.size(), 1u) << base;
        EXPECT_EQ(e.edges[0].origin, base.offsetBy(1, 1, 0));
        EXPECT_EQ(e.vertices.size(), 2u) << base;
    }
}

// An active tile is taken as its voxels: a tile of 1 beside a voxel of 2 along an edge.
TEST_F(TestCriticalElements, testTilesAreVoxelized)
{
    auto grid = openvdb::Int32Grid::create(0);
    grid->tree().addTile(1, Coord(0), 1, true); // the 8^3 leaf-sized tile at the origin
    grid->tree().setValueOn(Coord(8, 8, 3), 1);
    const auto voxels = vdbi::voxelizedLabels(*grid);
    EXPECT_EQ(voxels->tree().activeTileCount(), 0u);
    const auto e = vdbi::findCriticalElements(*voxels);
    ASSERT_EQ(e.edges.size(), 1u);
    EXPECT_EQ(e.edges[0].origin, Coord(8, 8, 3));
    EXPECT_EQ(vdbi::collectLabels(*grid), (std::vector<vdbi::Label>{0, 1}));
}

// The list is the same for the serial fallback, one thread and all threads.
TEST_F(TestCriticalElements, testThreadIndependence)
{
    std::vector<std::pair<Coord, int>> v;
    unsigned state = 12345;
    for (int x = 0; x < 40; ++x) for (int y = 0; y < 40; ++y) for (int z = 0; z < 40; ++z) {
        state = state * 1664525u + 1013904223u;
        if ((state >> 28) < 6) v.push_back({Coord(x, y, z), int(state >> 29)});
    }
    const auto grid = gridOf(v);
    vdbi::RepairOptions serial;
    serial.threaded = false;
    const auto a = vdbi::findCriticalElements(*grid, serial);
    vdbi::CriticalElements b;
    tbb::task_arena(1).execute([&] { b = vdbi::findCriticalElements(*grid); });
    vdbi::CriticalElements c = vdbi::findCriticalElements(*grid);
    ASSERT_GT(a.edges.size(), 100u);
    for (const vdbi::CriticalElements* x : {&b, &c}) {
        ASSERT_EQ(a.edges.size(), x->edges.size());
        ASSERT_EQ(a.vertices.size(), x->vertices.size());
        for (std::size_t i = 0; i < a.edges.size(); ++i) {
            EXPECT_EQ(a.edges[i].origin, x->edges[i].origin);
            EXPECT_EQ(a.edges[i].label, x->edges[i].label);
        }
        for (std::size_t i = 0; i < a.vertices.size(); ++i) {
            EXPECT_EQ(a.vertices[i].point, x->vertices[i].point);
            EXPECT_EQ(a.vertices[i].label, x->vertices[i].label);
        }
    }
}
