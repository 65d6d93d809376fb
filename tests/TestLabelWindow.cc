// SPDX-License-Identifier: Apache-2.0
/// @file TestLabelWindow.cc
/// @brief The blocks the leaf passes visit: blockOrigins() and withPositiveNeighbours() give
/// every leaf origin and its neighbours at +8 along any combination of axes, sorted and
/// distinct, exactly as sorting all eight copies of every origin would.

#include <vdbi/LabelWindow.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace {

using openvdb::Coord;

class TestLabelWindow : public ::testing::Test
{
protected:
    void SetUp() override { openvdb::initialize(); }
};

/// The reference: all eight copies of every origin, sorted, duplicates removed.
std::vector<Coord>
sortedCopies(const std::vector<Coord>& leafOrigins)
{
    std::vector<Coord> all;
    for (const Coord& o : leafOrigins) {
        for (int n = 0; n < 8; ++n) {
            all.push_back(o.offsetBy((n & 1) ? vdbi::BLOCK_DIM : 0,
                (n & 2) ? vdbi::BLOCK_DIM : 0, (n & 4) ? vdbi::BLOCK_DIM : 0));
        }
    }
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    return all;
}

} // namespace

TEST_F(TestLabelWindow, testWithPositiveNeighboursMatchesSortedCopies)
{
    // Clustered origins on both sides of 0, so that many neighbours coincide.
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> cell(-5, 5);
    std::vector<Coord> leaves;
    for (int n = 0; n < 300; ++n) {
        leaves.emplace_back(8 * cell(rng), 8 * cell(rng), 8 * cell(rng));
    }
    std::sort(leaves.begin(), leaves.end());
    leaves.erase(std::unique(leaves.begin(), leaves.end()), leaves.end());
    EXPECT_EQ(vdbi::withPositiveNeighbours(leaves), sortedCopies(leaves));
    EXPECT_TRUE(vdbi::withPositiveNeighbours({}).empty());
}

TEST_F(TestLabelWindow, testBlockOriginsOfTwoLeaves)
{
    openvdb::Int32Tree tree(0);
    tree.setValueOn(Coord(-3, 9, 17), 5); // leaf at (-8, 8, 16)
    tree.setValueOn(Coord(1, 9, 17), 6);  // leaf at (0, 8, 16): 4 neighbours in common
    const std::vector<Coord> origins = vdbi::blockOrigins(tree, /*threaded=*/false);
    EXPECT_EQ(origins.size(), 12u);
    EXPECT_EQ(origins, sortedCopies({Coord(-8, 8, 16), Coord(0, 8, 16)}));
    EXPECT_EQ(vdbi::blockOrigins(tree, /*threaded=*/true), origins);
}
