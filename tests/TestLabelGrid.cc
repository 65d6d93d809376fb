// SPDX-License-Identifier: Apache-2.0
/// @file TestLabelGrid.cc
/// @brief collectLabels and voxelizedLabels see tiles of every level of the tree (root,
/// upper and lower internal nodes), active or not, and voxels, with exact expected results.

#include <vdbi/LabelGrid.h>

#include <gtest/gtest.h>

#include <vector>

namespace {

using openvdb::Coord;
using vdbi::Label;

class TestLabelGrid : public ::testing::Test
{
protected:
    void SetUp() override { openvdb::initialize(); }
};

/// Background 7; an inactive lower-node tile (8^3) of 3 at the origin, an active upper-node
/// tile (128^3) of -5 at x = 128, one voxel of 9 at (-1, 0, 0).
openvdb::Int32Grid::Ptr
gridWithInternalTiles()
{
    auto grid = openvdb::Int32Grid::create(7);
    grid->tree().addTile(/*level=*/1, Coord(0), 3, /*active=*/false);
    grid->tree().addTile(/*level=*/2, Coord(128, 0, 0), -5, /*active=*/true);
    grid->tree().setValueOn(Coord(-1, 0, 0), 9);
    return grid;
}

} // namespace

TEST_F(TestLabelGrid, testCollectLabelsSeesTilesOfEveryLevel)
{
    auto grid = gridWithInternalTiles();
    EXPECT_EQ(vdbi::collectLabels(*grid), (std::vector<Label>{-5, 3, 7, 9}));
    EXPECT_EQ(vdbi::collectLabels(*grid, /*threaded=*/false), (std::vector<Label>{-5, 3, 7, 9}));
    // A root tile (4096^3) of 11, far away.
    grid->tree().addTile(/*level=*/3, Coord(-8192, 0, 0), 11, /*active=*/true);
    EXPECT_EQ(vdbi::collectLabels(*grid), (std::vector<Label>{-5, 3, 7, 9, 11}));
    // Only the background.
    EXPECT_EQ(vdbi::collectLabels(*openvdb::Int32Grid::create(-2)), (std::vector<Label>{-2}));
}

TEST_F(TestLabelGrid, testVoxelizedLabelsReplacesLabelledTiles)
{
    const auto grid = gridWithInternalTiles();
    const openvdb::Int32Grid::ConstPtr voxels = vdbi::voxelizedLabels(*grid);
    EXPECT_NE(&voxels->tree(), &grid->tree());
    EXPECT_EQ(voxels->tree().activeTileCount(), 0u);
    EXPECT_EQ(voxels->tree().activeLeafVoxelCount(), 128u * 128 * 128 + 1);
    // Values and active states kept, now in leaves.
    const auto acc = voxels->getConstAccessor();
    EXPECT_EQ(acc.getValue(Coord(5, 6, 7)), 3);
    EXPECT_FALSE(acc.isValueOn(Coord(5, 6, 7)));
    EXPECT_EQ(acc.getValueDepth(Coord(5, 6, 7)), openvdb::Int32Tree::DEPTH - 1);
    EXPECT_EQ(acc.getValue(Coord(255, 127, 0)), -5);
    EXPECT_TRUE(acc.isValueOn(Coord(255, 127, 0)));
    EXPECT_EQ(acc.getValueDepth(Coord(255, 127, 0)), openvdb::Int32Tree::DEPTH - 1);
    EXPECT_EQ(acc.getValue(Coord(-1, 0, 0)), 9);
    EXPECT_EQ(acc.getValue(Coord(8, 0, 0)), 7);
    // Nothing to replace: the same tree, shared.
    auto plain = openvdb::Int32Grid::create(7);
    plain->tree().setValueOn(Coord(1, 2, 3), 1);
    plain->tree().addTile(/*level=*/1, Coord(64, 0, 0), 7, /*active=*/true);
    EXPECT_EQ(&vdbi::voxelizedLabels(*plain)->tree(), &plain->tree());
}
