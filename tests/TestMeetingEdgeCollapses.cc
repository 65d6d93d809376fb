// SPDX-License-Identifier: Apache-2.0
/// @file TestMeetingEdgeCollapses.cc
/// @brief collapseMeetingEdges() on a hand-made knot, judged by the independent intersection
/// checker (support/MeshIntersections.h) and by the triangles it leaves.

#include "support/HandMadeMeshes.h"
#include "support/MeshIntersections.h"

#include <vdbi/MeetingEdgeCollapses.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

using openvdb::Vec3d;
using openvdb::Vec3I;

namespace {

using vdbi_test::intersectingPairs;

/// Patch (1, 2): a tent, a fan of six triangles from a free centre (point 12) at z = 2 down
/// to a hexagon of free points 6-11 at z = 0, in a flat ring out to a hexagon of fixed points
/// 0-5 (its boundary, as curve samples are); patch (3, 4): a large flat triangle (points
/// 13-15) at z = 1 that the six tent triangles cross. No move of the centre within reach
/// frees them: only taking the centre out does.
vdbi::InterfaceMesh
tentThroughTriangle()
{
    std::vector<Vec3d> points;
    for (const double radius : {2.0, 1.0}) {
        for (int k = 0; k < 6; ++k) {
            const double angle = k * M_PI / 3.0;
            points.emplace_back(radius * std::cos(angle), radius * std::sin(angle), 0.0);
        }
    }
    points.emplace_back(0.0, 0.0, 2.0);
    points.insert(points.end(), {Vec3d(-1.5, -1.2, 1), Vec3d(1.5, -1.2, 1), Vec3d(0, 1.5, 1)});
    std::vector<Vec3I> patch;
    for (unsigned k = 0; k < 6; ++k) patch.emplace_back(12, 6 + k, 6 + (k + 1) % 6);
    for (unsigned k = 0; k < 6; ++k) {
        const unsigned next = (k + 1) % 6;
        patch.emplace_back(k, next, 6 + next);
        patch.emplace_back(k, 6 + next, 6 + k);
    }
    return vdbi_test::makeMesh(points, {{1, 2, patch}, {3, 4, {Vec3I(13, 14, 15)}}});
}

/// Points 6-12 free, or none.
std::vector<std::uint8_t>
tentMovable(bool free)
{
    std::vector<std::uint8_t> movable(16, 0);
    for (int i = 6; i < 13; ++i) movable[i] = free;
    return movable;
}

/// Does every edge of @a mesh have at most two triangles, running along it in opposite ways?
bool
isOrientedManifold(const vdbi::InterfaceMesh& mesh)
{
    std::map<std::pair<unsigned, unsigned>, int> edges;
    for (const Vec3I& t : mesh.triangles) {
        for (int i = 0; i < 3; ++i) {
            if (++edges[{t[i], t[(i + 1) % 3]}] > 1) return false;
        }
    }
    return true;
}

vdbi::TrianglePairs
pairsOf(const vdbi::InterfaceMesh& mesh)
{
    const auto pairs = intersectingPairs(mesh);
    return vdbi::TrianglePairs(pairs.begin(), pairs.end());
}

} // namespace

TEST(TestMeetingEdgeCollapses, testCollapseUntiesTheKnot)
{
    vdbi::InterfaceMesh mesh = tentThroughTriangle();
    const vdbi::TrianglePairs before = pairsOf(mesh);
    ASSERT_EQ(before.size(), 6u);
    vdbi::TrianglePairs left = before;
    EXPECT_EQ(vdbi::collapseMeetingEdges(mesh, tentMovable(true), 1.0, false, before, &left),
              1u);
    EXPECT_TRUE(intersectingPairs(mesh).empty());
    EXPECT_TRUE(left.empty());
    // The centre went into a point of the inner hexagon: two triangles fewer, the points
    // after the centre one down, and none moved but the one the centre went into.
    ASSERT_EQ(mesh.patches.size(), 2u);
    EXPECT_EQ(mesh.patches[0].firstTriangle, 0u);
    EXPECT_EQ(mesh.patches[0].triangleCount, 16u);
    EXPECT_EQ(mesh.patches[1].firstTriangle, 16u);
    EXPECT_EQ(mesh.patches[1].triangleCount, 1u);
    EXPECT_EQ(mesh.triangles[16], Vec3I(12, 13, 14));
    ASSERT_EQ(mesh.points.size(), 15u);
    const vdbi::InterfaceMesh original = tentThroughTriangle();
    int moved = 0;
    for (std::size_t i = 0; i < 12; ++i) moved += mesh.points[i] != original.points[i];
    EXPECT_LE(moved, 1);
    for (std::size_t i = 12; i < 15; ++i) EXPECT_EQ(mesh.points[i], original.points[i + 1]);
    // Still an oriented 2-manifold, flat and facing up as the ring did; the boundary stays.
    EXPECT_TRUE(isOrientedManifold(mesh));
    for (std::size_t f = 0; f < 16; ++f) {
        const Vec3I& t = mesh.triangles[f];
        const Vec3d n = (mesh.points[t[1]] - mesh.points[t[0]])
                            .cross(mesh.points[t[2]] - mesh.points[t[0]]);
        EXPECT_GT(n[2], 0.0) << "triangle " << f;
        for (int i = 0; i < 3; ++i) EXPECT_EQ(mesh.points[t[i]][2], 0.0);
    }
}

TEST(TestMeetingEdgeCollapses, testFixedPointsStay)
{
    // Every point fixed (curve samples, say): no collapse, nothing changes, all pairs left.
    vdbi::InterfaceMesh mesh = tentThroughTriangle();
    const vdbi::TrianglePairs before = pairsOf(mesh);
    vdbi::TrianglePairs left;
    EXPECT_EQ(vdbi::collapseMeetingEdges(mesh, tentMovable(false), 1.0, false, before, &left),
              0u);
    EXPECT_EQ(mesh.triangles, tentThroughTriangle().triangles);
    EXPECT_EQ(mesh.points, tentThroughTriangle().points);
    EXPECT_EQ(left, before);
}

TEST(TestMeetingEdgeCollapses, testNarrowsRatherThanFlattens)
{
    // Seven small triangles of patch (3, 4) lie in the plane of the hexagon, inside it, under
    // the tent: laying the tent flat would meet them, seven pairs for six, and is not done.
    // Narrowing the tent (an inner hexagon point into the next) frees pairs and is.
    vdbi::InterfaceMesh mesh = tentThroughTriangle();
    for (int k = 0; k < 7; ++k) {
        const double angle = (k + 0.5) * M_PI / 3.0, radius = k < 6 ? 0.5 : 0.0;
        const Vec3d c(radius * std::cos(angle), radius * std::sin(angle), 0.0);
        const unsigned first = unsigned(mesh.points.size());
        mesh.points.insert(mesh.points.end(), {c + Vec3d(-0.05, -0.05, 0),
                                               c + Vec3d(0.05, -0.05, 0), c + Vec3d(0, 0.05, 0)});
        mesh.triangles.push_back(Vec3I(first, first + 1, first + 2));
    }
    mesh.patches[1].triangleCount = 8;
    const vdbi::TrianglePairs before = pairsOf(mesh);
    ASSERT_EQ(before.size(), 6u);
    std::vector<std::uint8_t> movable = tentMovable(true);
    movable.resize(mesh.points.size(), 0);
    vdbi::TrianglePairs left;
    EXPECT_GT(vdbi::collapseMeetingEdges(mesh, movable, 1.0, false, before, &left), 0u);
    // Fewer pairs, as the independent checker finds them; the apex still up.
    EXPECT_EQ(left, pairsOf(mesh));
    EXPECT_LT(left.size(), before.size());
    EXPECT_NE(std::find(mesh.points.begin(), mesh.points.end(), Vec3d(0, 0, 2)),
              mesh.points.end());
    EXPECT_TRUE(isOrientedManifold(mesh));
}

TEST(TestMeetingEdgeCollapses, testNoCollapseThatMeetsMore)
{
    // A three-sided tent over a triangle of fixed points, its free apex crossing a flat
    // triangle of patch (3, 4) at z = 1: the only collapse, of the apex into a corner, lays
    // it flat onto the base and frees the three pairs. With four small triangles of patch
    // (5, 6) lying in the base, it would meet four instead: it is not made.
    auto makeTent = [](int small) {
        std::vector<Vec3d> points = {Vec3d(2, 0, 0), Vec3d(-1, 1.8, 0), Vec3d(-1, -1.8, 0),
                                     Vec3d(0, 0, 2), Vec3d(-1.5, -1.2, 1), Vec3d(1.5, -1.2, 1),
                                     Vec3d(0, 1.5, 1)};
        std::vector<Vec3I> flat;
        for (int k = 0; k < small; ++k) {
            const Vec3d c = k == 0 ? Vec3d(0.0) : points[k - 1] * 0.5;
            const unsigned first = unsigned(points.size());
            points.insert(points.end(), {c + Vec3d(-0.05, -0.05, 0), c + Vec3d(0.05, -0.05, 0),
                                         c + Vec3d(0, 0.05, 0)});
            flat.push_back(Vec3I(first, first + 1, first + 2));
        }
        std::vector<vdbi_test::PatchSpec> patches = {
            {1, 2, {Vec3I(3, 0, 1), Vec3I(3, 1, 2), Vec3I(3, 2, 0)}},
            {3, 4, {Vec3I(4, 5, 6)}}};
        if (small > 0) patches.push_back({5, 6, flat});
        return vdbi_test::makeMesh(points, patches);
    };
    vdbi::InterfaceMesh tent = makeTent(0);
    std::vector<std::uint8_t> movable(tent.points.size(), 0);
    movable[3] = 1;
    ASSERT_EQ(pairsOf(tent).size(), 3u);
    EXPECT_EQ(vdbi::collapseMeetingEdges(tent, movable, 1.0, false, pairsOf(tent)), 1u);
    EXPECT_TRUE(pairsOf(tent).empty());
    EXPECT_EQ(tent.patches[0].triangleCount, 1u);

    vdbi::InterfaceMesh covered = makeTent(4);
    movable.resize(covered.points.size(), 0);
    const vdbi::TrianglePairs before = pairsOf(covered);
    ASSERT_EQ(before.size(), 3u);
    vdbi::TrianglePairs left;
    EXPECT_EQ(vdbi::collapseMeetingEdges(covered, movable, 1.0, false, before, &left), 0u);
    EXPECT_EQ(covered.triangles, makeTent(4).triangles);
    EXPECT_EQ(left, before);
}

TEST(TestMeetingEdgeCollapses, testNothingToDo)
{
    vdbi::InterfaceMesh mesh = tentThroughTriangle();
    vdbi::TrianglePairs left = {{0, 6}};
    EXPECT_EQ(vdbi::collapseMeetingEdges(mesh, tentMovable(true), 1.0, true, {}, &left), 0u);
    EXPECT_TRUE(left.empty());
    EXPECT_EQ(mesh.triangles, tentThroughTriangle().triangles);
}
