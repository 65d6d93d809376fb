// SPDX-License-Identifier: Apache-2.0
/// @file TestMeetingEdgeCollapses.cc
/// @brief collapseMeetingEdges() on a hand-made knot, judged by the independent intersection
/// checker (support/MeshIntersections.h) and by the triangles it leaves; and
/// collapseMeetingAndShortEdges() on hand-made short edges, with each of its guards.

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

namespace {

/// The fixed hexagon of radius 2 in the plane z = 0 (points 0-5, counterclockwise from
/// (2, 0, 0)), and @a inner free points after them.
std::vector<Vec3d>
hexagonWith(const std::vector<Vec3d>& inner)
{
    std::vector<Vec3d> points;
    for (int k = 0; k < 6; ++k) {
        const double angle = k * M_PI / 3.0;
        points.emplace_back(2.0 * std::cos(angle), 2.0 * std::sin(angle), 0.0);
    }
    points.insert(points.end(), inner.begin(), inner.end());
    return points;
}

/// Settings for the hand-made meshes: short under 0.5, long over @a longLength.
vdbi::ShortEdgeCollapseSettings
shortEdgeSettings(double longLength)
{
    vdbi::ShortEdgeCollapseSettings settings;
    settings.shortLength = 0.5;
    settings.longLength = longLength;
    settings.cellSize = 1.0;
    settings.threaded = false;
    return settings;
}

/// The lengths of the edges of @a mesh, each once.
std::vector<double>
edgeLengths(const vdbi::InterfaceMesh& mesh)
{
    std::map<std::pair<unsigned, unsigned>, double> edges;
    for (const Vec3I& t : mesh.triangles) {
        for (int i = 0; i < 3; ++i) {
            const unsigned a = std::min(t[i], t[(i + 1) % 3]), b = std::max(t[i], t[(i + 1) % 3]);
            edges[{a, b}] = (mesh.points[a] - mesh.points[b]).length();
        }
    }
    std::vector<double> lengths;
    for (const auto& edge : edges) lengths.push_back(edge.second);
    return lengths;
}

} // namespace

// The hexagon filled around two free points 0.2 apart at its centre: the short edge between
// them collapses, both going to its midpoint (the best fan: six triangles of 60 degrees), if
// the edges to the hexagon (2.0 then) may be that long; and not if they may not or the two
// points are fixed.
TEST(TestMeetingEdgeCollapses, testShortEdgeCollapsesToTheBestFan)
{
    const unsigned a = 6, b = 7;   // (-0.1, 0, 0) and (0.1, 0, 0)
    const std::vector<Vec3I> fill = {Vec3I(b, 0, 1), Vec3I(b, 5, 0), Vec3I(b, 1, a),
                                     Vec3I(a, 1, 2), Vec3I(a, 2, 3), Vec3I(a, 3, 4),
                                     Vec3I(a, 4, b), Vec3I(b, 4, 5)};
    auto makeHexagon = [&] {
        return vdbi_test::makeMesh(hexagonWith({Vec3d(-0.1, 0, 0), Vec3d(0.1, 0, 0)}),
                                   {{1, 2, fill}});
    };
    std::vector<std::uint8_t> movable = {0, 0, 0, 0, 0, 0, 1, 1};

    vdbi::InterfaceMesh mesh = makeHexagon();
    EXPECT_EQ(vdbi::collapseMeetingAndShortEdges(mesh, movable, shortEdgeSettings(2.5), {}), 1u);
    ASSERT_EQ(mesh.points.size(), 7u);
    EXPECT_EQ(mesh.points[6], Vec3d(0, 0, 0));
    ASSERT_EQ(mesh.triangles.size(), 6u);
    EXPECT_EQ(mesh.patches[0].triangleCount, 6u);
    EXPECT_TRUE(isOrientedManifold(mesh));
    for (const Vec3I& t : mesh.triangles) {
        const Vec3d n = (mesh.points[t[1]] - mesh.points[t[0]])
                            .cross(mesh.points[t[2]] - mesh.points[t[0]]);
        EXPECT_GT(n[2], 0.0);
    }
    for (const double length : edgeLengths(mesh)) EXPECT_NEAR(length, 2.0, 1e-12);

    // Edges of 2.0 not allowed: nothing changes.
    mesh = makeHexagon();
    EXPECT_EQ(vdbi::collapseMeetingAndShortEdges(mesh, movable, shortEdgeSettings(1.9), {}), 0u);
    EXPECT_EQ(mesh.triangles, makeHexagon().triangles);
    EXPECT_EQ(mesh.points, makeHexagon().points);

    // Both fixed (curve samples): nothing changes.
    mesh = makeHexagon();
    movable[a] = movable[b] = 0;
    EXPECT_EQ(vdbi::collapseMeetingAndShortEdges(mesh, movable, shortEdgeSettings(2.5), {}), 0u);
    EXPECT_EQ(mesh.triangles, makeHexagon().triangles);
}

// A free point 0.25 from hexagon point 0, joined to points 5, 0, 1 and 2 and to a free centre:
// its collapse into point 0 makes the new inner edge (0, 2) between two fixed points, which
// only the patch that may have it makes (mayJoinFixed: the chord owner). The fan it leaves
// has no angle under 30 degrees.
TEST(TestMeetingEdgeCollapses, testShortEdgeJoinsFixedPointsOnlyWhereAllowed)
{
    const unsigned a = 6, c = 7;   // (1.75, 0, 0) and the centre
    const std::vector<Vec3I> fill = {Vec3I(a, 0, 1), Vec3I(a, 5, 0), Vec3I(a, 1, 2),
                                     Vec3I(a, 2, c), Vec3I(a, c, 5), Vec3I(c, 2, 3),
                                     Vec3I(c, 3, 4), Vec3I(c, 4, 5)};
    auto makeHexagon = [&] {
        return vdbi_test::makeMesh(hexagonWith({Vec3d(1.75, 0, 0), Vec3d(0, 0, 0)}),
                                   {{1, 2, fill}});
    };
    const std::vector<std::uint8_t> movable = {0, 0, 0, 0, 0, 0, 1, 1};
    std::vector<std::vector<std::uint32_t>> asked;
    vdbi::ShortEdgeCollapseSettings settings = shortEdgeSettings(4.0);
    settings.mayJoinFixed = [&](std::uint32_t patch, std::uint32_t u, std::uint32_t v) {
        asked.push_back({patch, u, v});
        return false;
    };

    vdbi::InterfaceMesh mesh = makeHexagon();
    EXPECT_EQ(vdbi::collapseMeetingAndShortEdges(mesh, movable, settings, {}), 0u);
    EXPECT_EQ(mesh.triangles, makeHexagon().triangles);
    ASSERT_FALSE(asked.empty());
    EXPECT_EQ(asked.front(), (std::vector<std::uint32_t>{0, 0, 2}));

    settings.mayJoinFixed = [](std::uint32_t, std::uint32_t, std::uint32_t) { return true; };
    EXPECT_EQ(vdbi::collapseMeetingAndShortEdges(mesh, movable, settings, {}), 1u);
    ASSERT_EQ(mesh.points.size(), 7u);   // the centre is point 6 now
    EXPECT_EQ(mesh.points[6], Vec3d(0, 0, 0));
    EXPECT_TRUE(isOrientedManifold(mesh));
    std::vector<Vec3I> sorted;
    for (Vec3I t : mesh.triangles) {
        std::sort(t.asPointer(), t.asPointer() + 3);
        sorted.push_back(t);
    }
    for (const Vec3I& t : {Vec3I(0, 1, 2), Vec3I(0, 2, 6), Vec3I(0, 5, 6)}) {
        EXPECT_NE(std::find(sorted.begin(), sorted.end(), t), sorted.end()) << t;
    }
    for (const Vec3I& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            const Vec3d e1 = mesh.points[t[(k + 1) % 3]] - mesh.points[t[k]];
            const Vec3d e2 = mesh.points[t[(k + 2) % 3]] - mesh.points[t[k]];
            EXPECT_GE(std::acos(e1.dot(e2) / (e1.length() * e2.length())) * 180.0 / M_PI,
                      30.0 - 1e-9);
        }
    }
}

// Two patches on one loop of three fixed points, a lens: each has a free centre 0.33 from
// corner 0, above and below. Collapsing a centre leaves the patch as the triangle of the
// loop; only one of them may: two would be the same triangle (which meets itself).
TEST(TestMeetingEdgeCollapses, testLoopOfThreeBecomesOneTriangleOnce)
{
    const std::vector<Vec3d> points = {Vec3d(0, 0, 0), Vec3d(2, 0, 0), Vec3d(0, 2, 0),
                                       Vec3d(0.1, 0.1, 0.3), Vec3d(0.1, 0.1, -0.3)};
    vdbi::InterfaceMesh mesh = vdbi_test::makeMesh(
        points, {{1, 2, {Vec3I(3, 0, 1), Vec3I(3, 1, 2), Vec3I(3, 2, 0)}},
                 {2, 3, {Vec3I(4, 1, 0), Vec3I(4, 2, 1), Vec3I(4, 0, 2)}}});
    ASSERT_TRUE(pairsOf(mesh).empty());
    const std::vector<std::uint8_t> movable = {0, 0, 0, 1, 1};
    EXPECT_EQ(vdbi::collapseMeetingAndShortEdges(mesh, movable, shortEdgeSettings(3.0), {}), 1u);
    ASSERT_EQ(mesh.patches.size(), 2u);
    EXPECT_EQ(mesh.patches[0].triangleCount + mesh.patches[1].triangleCount, 4u);
    EXPECT_EQ(std::min(mesh.patches[0].triangleCount, mesh.patches[1].triangleCount), 1u);
    EXPECT_EQ(mesh.points.size(), 4u);
    EXPECT_TRUE(pairsOf(mesh).empty());
}
