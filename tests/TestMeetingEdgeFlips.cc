// SPDX-License-Identifier: Apache-2.0
/// @file TestMeetingEdgeFlips.cc
/// @brief flipMeetingEdges() on hand-made patches, judged by the independent intersection
/// checker (support/MeshIntersections.h), and by the triangles it leaves.

#include "support/HandMadeMeshes.h"
#include "support/MeshIntersections.h"

#include <vdbi/MeetingEdgeFlips.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <utility>
#include <vector>

using openvdb::Vec3d;
using openvdb::Vec3I;

namespace {

using vdbi_test::intersectingPairs;

/// Every point of @a mesh: the flips search the whole mesh.
std::vector<std::uint32_t>
allPoints(const vdbi::InterfaceMesh& mesh)
{
    std::vector<std::uint32_t> points(mesh.points.size());
    for (std::size_t i = 0; i < points.size(); ++i) points[i] = std::uint32_t(i);
    return points;
}

/// Patch (1, 2): a ridge of two triangles (0, 1, 2) and (1, 0, 3) along its edge 0-1 at
/// z = 1, down to corners 2 and 3 at z = 0; patch (3, 4): a flat triangle at z = 0.8 across
/// the ridge, which crosses both. With the other diagonal 2-3 the pair is a valley, under it.
vdbi::InterfaceMesh
ridgeUnderTriangle()
{
    return vdbi_test::makeMesh(
        {Vec3d(0, 0, 1), Vec3d(2, 2, 1), Vec3d(2, 0, 0), Vec3d(0, 2, 0), Vec3d(1.4, 0.8, 0.8),
         Vec3d(0.8, 1.4, 0.8), Vec3d(0.8, 0.8, 0.8)},
        {{1, 2, {Vec3I(0, 1, 2), Vec3I(1, 0, 3)}}, {3, 4, {Vec3I(4, 5, 6)}}});
}

} // namespace

TEST(TestMeetingEdgeFlips, testFlipGoesRound)
{
    vdbi::InterfaceMesh mesh = ridgeUnderTriangle();
    ASSERT_EQ(intersectingPairs(mesh),
              (std::set<std::pair<std::uint32_t, std::uint32_t>>{{0, 2}, {1, 2}}));
    const std::vector<std::uint8_t> movable = {0, 0, 1, 1, 0, 0, 0};
    vdbi::TrianglePairs left = {{0, 1}};
    EXPECT_EQ(vdbi::flipMeetingEdges(mesh, movable, 1.0, false, allPoints(mesh), &left), 1u);
    EXPECT_TRUE(intersectingPairs(mesh).empty());
    EXPECT_TRUE(left.empty());
    // The same points, the other diagonal, both triangles still facing down.
    EXPECT_EQ(mesh.triangles[0], Vec3I(0, 3, 2));
    EXPECT_EQ(mesh.triangles[1], Vec3I(3, 1, 2));
    EXPECT_EQ(mesh.points, ridgeUnderTriangle().points);
}

// The ridge's source has a small triangle on its crest, centroid (1, 1, 1): the flip to the
// valley would leave it 2 / sqrt(6) = 0.82 from the patch. Under a limit of 0.9 from the
// source the flip is made; under 0.5 it is not, and both pairs still meet.
TEST(TestMeetingEdgeFlips, testFlipKeepsTheSourceCovered)
{
    const vdbi::InterfaceMesh source = vdbi_test::makeMesh(
        {Vec3d(0.9, 0.9, 1), Vec3d(1.2, 0.9, 1), Vec3d(0.9, 1.2, 1), Vec3d(5, 5, 5),
         Vec3d(6, 5, 5), Vec3d(5, 6, 5)},
        {{1, 2, {Vec3I(0, 1, 2)}}, {3, 4, {Vec3I(3, 4, 5)}}});
    vdbi::RawPatchDistance distance(source, Vec3d(1.0), 1.5);
    const std::vector<std::uint8_t> movable = {0, 0, 1, 1, 0, 0, 0};
    for (const double limit : {0.9, 0.5}) {
        vdbi::InterfaceMesh mesh = ridgeUnderTriangle();
        vdbi::TrianglePairs left;
        const bool flipped = limit > 0.82;
        EXPECT_EQ(vdbi::flipMeetingEdges(mesh, movable, 1.0, false, allPoints(mesh), &left,
                                         &distance, limit),
                  flipped ? 1u : 0u);
        const vdbi::TrianglePairs expected =
            flipped ? vdbi::TrianglePairs{} : vdbi::TrianglePairs{{0, 2}, {1, 2}};
        EXPECT_EQ(left, expected) << "limit " << limit;
    }
}

TEST(TestMeetingEdgeFlips, testNoDiagonalBetweenLockedPoints)
{
    // Another patch on the same curves could make the edge 2-3 too.
    vdbi::InterfaceMesh mesh = ridgeUnderTriangle();
    const std::vector<std::uint8_t> movable = {1, 1, 0, 0, 0, 0, 0};
    vdbi::TrianglePairs left;
    EXPECT_EQ(vdbi::flipMeetingEdges(mesh, movable, 1.0, false, allPoints(mesh), &left), 0u);
    EXPECT_EQ(mesh.triangles, ridgeUnderTriangle().triangles);
    // Both pairs still meet.
    EXPECT_EQ(left, (vdbi::TrianglePairs{{0, 2}, {1, 2}}));
}

TEST(TestMeetingEdgeFlips, testNoFlipOfCurveSegment)
{
    // Triangle 1 in a patch of its own, (1, 3): edge 0-1 is a segment of the curve between
    // the two patches, never flipped.
    vdbi::InterfaceMesh mesh = ridgeUnderTriangle();
    vdbi::InterfacePatch side = mesh.patches[0];
    mesh.patches[0].triangleCount = 1;
    side.b = 3;
    side.firstTriangle = 1;
    side.triangleCount = 1;
    mesh.patches.insert(mesh.patches.begin() + 1, side);
    ASSERT_EQ(intersectingPairs(mesh).size(), 2u);
    const std::vector<std::uint8_t> movable = {0, 0, 1, 1, 0, 0, 0};
    EXPECT_EQ(vdbi::flipMeetingEdges(mesh, movable, 1.0, false, allPoints(mesh)), 0u);
    EXPECT_EQ(mesh.triangles, ridgeUnderTriangle().triangles);
}

TEST(TestMeetingEdgeFlips, testNoFlipThatMeetsMore)
{
    // The flat triangle low, at z = 0.15: the valley would cross it, the ridge does not.
    vdbi::InterfaceMesh mesh = ridgeUnderTriangle();
    for (int i = 4; i < 7; ++i) mesh.points[i][2] = 0.15;
    // A second triangle of patch (3, 4) crossing the ridge near corner 0 keeps triangles 0
    // and 1 meeting one.
    ASSERT_TRUE(intersectingPairs(mesh).empty());
    mesh.points.push_back(Vec3d(0.2, 0.2, 1.5));
    mesh.points.push_back(Vec3d(0.5, 0.1, 0.5));
    mesh.points.push_back(Vec3d(0.1, 0.5, 0.5));
    mesh.triangles.push_back(Vec3I(7, 8, 9));
    mesh.patches[1].triangleCount = 2;
    ASSERT_FALSE(intersectingPairs(mesh).empty());
    const std::vector<std::uint8_t> movable = {0, 0, 1, 1, 0, 0, 0, 0, 0, 0};
    const vdbi::TriangleArray before = mesh.triangles;
    vdbi::TrianglePairs left;
    EXPECT_EQ(vdbi::flipMeetingEdges(mesh, movable, 1.0, false, allPoints(mesh), &left), 0u);
    EXPECT_EQ(mesh.triangles, before);
    // The pairs the independent checker finds, and no other.
    const auto pairs = intersectingPairs(mesh);
    EXPECT_EQ(left, vdbi::TrianglePairs(pairs.begin(), pairs.end()));
}
