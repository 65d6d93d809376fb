// SPDX-License-Identifier: Apache-2.0
/// @file TestPatchSeparation.cc
/// @brief separatePatches() on hand-made patches, judged by the independent intersection
/// checker (support/MeshIntersections.h): pairs it must resolve, and crossings it must not make.

#include "support/HandMadeMeshes.h"
#include "support/MeshIntersections.h"

#include <vdbi/FaceCentreCoverage.h>
#include <vdbi/GuardedMoves.h>
#include <vdbi/PatchSeparation.h>
#include <vdbi/RawPatchDistance.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <utility>
#include <vector>

using openvdb::Vec3d;
using openvdb::Vec3I;

class TestPatchSeparation : public ::testing::Test
{
};

namespace {

using vdbi_test::intersectingPairs;
using vdbi_test::makeMesh;
using vdbi_test::PatchSpec;

Vec3d
normalOf(const vdbi::InterfaceMesh& mesh, std::size_t t)
{
    const Vec3I& tri = mesh.triangles[t];
    const Vec3d& a = mesh.points[tri[0]];
    return (mesh.points[tri[1]] - a).cross(mesh.points[tri[2]] - a);
}

/// Locked points stay, none moves farther than @a maxMove, no triangle turns over.
void
expectAllowedMoves(const vdbi::InterfaceMesh& before, const vdbi::InterfaceMesh& after,
                   const std::vector<std::uint8_t>& movable, double maxMove)
{
    for (std::size_t v = 0; v < before.points.size(); ++v) {
        if (!movable[v]) EXPECT_EQ(after.points[v], before.points[v]) << "point " << v;
        EXPECT_LE((after.points[v] - before.points[v]).length(), maxMove + 1e-12) << "point " << v;
    }
    for (std::size_t t = 0; t < before.triangles.size(); ++t) {
        EXPECT_GT(normalOf(after, t).dot(normalOf(before, t)), 0.0) << "triangle " << t;
    }
}

vdbi::SeparationSettings
unitSettings()
{
    vdbi::SeparationSettings settings;
    settings.cellSize = 1.0;
    settings.step = 0.1;
    settings.maxMove = 0.4;
    return settings;
}

/// unitSettings() for the pulls: moves up to 2, kept within 0.95 of @a source.
vdbi::SeparationSettings
pullSettings(vdbi::RawPatchDistance& source)
{
    vdbi::SeparationSettings settings = unitSettings();
    settings.maxMove = 2.0;
    settings.source = &source;
    settings.sourceLimit = 0.95;
    return settings;
}

/// Patch (1, 2): a square of two triangles (0, 1, 2) and (0, 2, 3) in the plane z = 0;
/// patch (1, 3): a small triangle (4, 5, 6) standing through the first one, near the diagonal.
vdbi::InterfaceMesh
squareThroughSmallTriangle()
{
    const std::vector<Vec3d> points = {
        Vec3d(0, 0, 0), Vec3d(2, 0, 0), Vec3d(2, 2, 0), Vec3d(0, 2, 0),              // (1, 2)
        Vec3d(1.1, 0.8, -0.02), Vec3d(1.3, 0.8, -0.02), Vec3d(1.2, 0.85, 0.02)};     // (1, 3)
    return makeMesh(points, {{1, 2, {Vec3I(0, 1, 2), Vec3I(0, 2, 3)}}, {1, 3, {Vec3I(4, 5, 6)}}});
}

} // namespace

// Patches (0, 1) and (1, 2) share the curve edge 0-1; their triangles on it lie in one plane
// on the same side of it, folded onto each other (label 1 between them has no thickness).
// Triangles sharing an edge used to be skipped; the pair is pushed open now: the free
// corner of (0, 1) moves away from label 1, that of (1, 2) too, and the fold opens.
TEST_F(TestPatchSeparation, testFoldOnSharedEdgeOpens)
{
    const std::vector<Vec3d> points = {Vec3d(0, 0, 0), Vec3d(2, 0, 0),     // curve samples
                                       Vec3d(1, 1, 0), Vec3d(1.2, 0.9, 0)};
    vdbi::InterfaceMesh mesh = makeMesh(points, {{0, 1, {Vec3I(0, 1, 2)}},
                                                 {1, 2, {Vec3I(0, 1, 3)}}});
    // The checker sees the fold: known-bad input.
    ASSERT_TRUE(vdbi_test::trianglesIntersect(mesh.points, mesh.triangles[0], mesh.triangles[1]));

    const vdbi::InterfaceMesh before = mesh;
    const std::vector<std::uint8_t> movable = {0, 0, 1, 1};
    EXPECT_EQ(vdbi::separatePatches(mesh, movable, unitSettings()), 0u);
    EXPECT_TRUE(intersectingPairs(mesh).empty());
    expectAllowedMoves(before, mesh, movable, 0.4);
    // Both normals point +z; label 1 is above (0, 1) and below (1, 2): each corner went away
    // from it.
    EXPECT_LT(mesh.points[2].z(), 0.0);
    EXPECT_GT(mesh.points[3].z(), 0.0);
}

// A free corner of patch (1, 2) rests exactly on the locked triangle of (0, 1) in the plane
// z = 0, inside it: the triangles touch without crossing (as curve samples and projected
// vertices line up on flat stretches of the reference), and the wedge of label 1 between
// them pinches to a point. The independent checker counts touching; separation must see it
// too and lift the corner away from label 1.
TEST_F(TestPatchSeparation, testTouchingContactOpens)
{
    const std::vector<Vec3d> points = {Vec3d(0, 0, 0), Vec3d(2, 0, 0), Vec3d(0, 2, 0),   // (0, 1)
                                       Vec3d(0.5, 0.5, 0), Vec3d(1.5, 0.5, 1),
                                       Vec3d(0.5, 1.5, 1)};                               // (1, 2)
    vdbi::InterfaceMesh mesh = makeMesh(points, {{0, 1, {Vec3I(0, 1, 2)}},
                                                 {1, 2, {Vec3I(3, 4, 5)}}});
    ASSERT_EQ(intersectingPairs(mesh), (std::set<std::pair<std::uint32_t, std::uint32_t>>{{0, 1}}));

    const vdbi::InterfaceMesh before = mesh;
    const std::vector<std::uint8_t> movable = {0, 0, 0, 1, 0, 0};
    EXPECT_EQ(vdbi::separatePatches(mesh, movable, unitSettings()), 0u);
    EXPECT_TRUE(intersectingPairs(mesh).empty());
    expectAllowedMoves(before, mesh, movable, 0.4);
    // Label 1 lies above (0, 1) and below (1, 2): the corner went up.
    EXPECT_GT(mesh.points[3].z(), 0.0);
}

// Curve edge 0-1 of patch (0, 1) runs through a triangle of (1, 2) whose corners are all
// curve samples: no move of an inner vertex can resolve that pair, so separation keeps
// pushing the free corner 2 of (0, 1) away from label 1 (down), up to the limit. A locked
// triangle of a third patch lies 0.25 below corner 2: pushed on, the triangle of (0, 1)
// would go through it. No move may add a pair that meets, so corner 2 stops above it and
// no pair intersects afterwards that did not before.
TEST_F(TestPatchSeparation, testNoPushThroughThirdTriangle)
{
    const std::vector<Vec3d> points = {
        Vec3d(0, 0, 0), Vec3d(2, 0, 0), Vec3d(1, 1, 0),                                // (0, 1)
        Vec3d(1, -0.3, -0.5), Vec3d(1, 0.3, -0.5), Vec3d(1, 0, 0.5),                   // (1, 2)
        Vec3d(0.3, 0.5, -0.25), Vec3d(1.7, 0.5, -0.25), Vec3d(1, 1.6, -0.25)};         // (0, 5)
    vdbi::InterfaceMesh mesh = makeMesh(points, {{0, 1, {Vec3I(0, 1, 2)}},
                                                 {1, 2, {Vec3I(3, 4, 5)}},
                                                 {0, 5, {Vec3I(6, 7, 8)}}});
    const auto pairsBefore = intersectingPairs(mesh);
    ASSERT_EQ(pairsBefore, (std::set<std::pair<std::uint32_t, std::uint32_t>>{{0, 1}}));

    const vdbi::InterfaceMesh before = mesh;
    const std::vector<std::uint8_t> movable = {0, 0, 1, 0, 0, 0, 0, 0, 0};
    vdbi::separatePatches(mesh, movable, unitSettings());
    EXPECT_EQ(intersectingPairs(mesh), pairsBefore);
    expectAllowedMoves(before, mesh, movable, 0.4);
    // It did move, as far as it could.
    EXPECT_LT(mesh.points[2].z(), -0.15);
    EXPECT_GT(mesh.points[2].z(), -0.25);
}

// One patch: a fan of six triangles around a free centre whose locked ring is a hexagon in
// the plane z = 0. The centre lies beyond ring point 0, so the two triangles at that point
// face down and overlap their neighbours (a fold within one patch). Separation used to look
// only at pairs of two patches; the centre now moves to the mean of its ring and the fan
// opens: no pair meets, every triangle faces up.
TEST_F(TestPatchSeparation, testFoldedFanOpens)
{
    std::vector<Vec3d> points = {Vec3d(1.2, 0, 0)};   // the centre
    for (int i = 0; i < 6; ++i) {
        const double angle = i * M_PI / 3.0;
        points.emplace_back(std::cos(angle), std::sin(angle), 0.0);
    }
    std::vector<Vec3I> fan;
    for (int i = 0; i < 6; ++i) fan.emplace_back(0, 1 + i, 1 + (i + 1) % 6);
    vdbi::InterfaceMesh mesh = makeMesh(points, {{0, 1, fan}});
    ASSERT_FALSE(intersectingPairs(mesh).empty());
    ASSERT_LT(normalOf(mesh, 0).z(), 0.0);

    const vdbi::InterfaceMesh before = mesh;
    const std::vector<std::uint8_t> movable = {1, 0, 0, 0, 0, 0, 0};
    vdbi::SeparationSettings settings = unitSettings();
    settings.maxMove = 1.5;
    EXPECT_EQ(vdbi::separatePatches(mesh, movable, settings), 0u);
    EXPECT_TRUE(intersectingPairs(mesh).empty());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        EXPECT_GT(normalOf(mesh, t).z(), 0.0) << "triangle " << t;
    }
    for (std::size_t v = 1; v < points.size(); ++v) EXPECT_EQ(mesh.points[v], before.points[v]);
    EXPECT_LE((mesh.points[0] - before.points[0]).length(), settings.maxMove);
}

// Patches (0, 1) and (2, 3) share no label, so there is no way "away from the shared label".
// Corner 2 of (0, 1) sticks through the locked triangle of (2, 3) in the plane y = 1.5.
// The push needs a shared label and the mean of corner 2's neighbours (the midpoint of the
// opposite edge) would flatten its triangle; half way there the pair no longer meets.
TEST_F(TestPatchSeparation, testPatchesSharingNoLabelSeparate)
{
    const std::vector<Vec3d> points = {
        Vec3d(0, 0, 0), Vec3d(2, 0, 0), Vec3d(1, 1.6, 0),                              // (0, 1)
        Vec3d(0, 1.5, -1), Vec3d(2, 1.5, -1), Vec3d(1, 1.5, 1)};                       // (2, 3)
    vdbi::InterfaceMesh mesh = makeMesh(points, {{0, 1, {Vec3I(0, 1, 2)}},
                                                 {2, 3, {Vec3I(3, 4, 5)}}});
    ASSERT_EQ(intersectingPairs(mesh), (std::set<std::pair<std::uint32_t, std::uint32_t>>{{0, 1}}));

    const vdbi::InterfaceMesh before = mesh;
    const std::vector<std::uint8_t> movable = {0, 0, 1, 0, 0, 0};
    vdbi::SeparationSettings settings = unitSettings();
    settings.maxMove = 1.0;
    EXPECT_EQ(vdbi::separatePatches(mesh, movable, settings), 0u);
    EXPECT_TRUE(intersectingPairs(mesh).empty());
    expectAllowedMoves(before, mesh, movable, settings.maxMove);
}

// Crossing pairs at sites straddling grid cells, on both sides of 0, some of one patch and
// some of two: with nothing movable, one round returns the pairs found, and the grid (pairs
// taken in the lowest cell their boxes share) must find each exactly once, for any cell size.
TEST_F(TestPatchSeparation, testEveryMeetingPairFoundOnce)
{
    std::vector<Vec3d> points;
    PatchSpec between = {0, 1, {}}, other = {1, 2, {}}, within = {2, 3, {}};
    std::size_t sites = 0;
    for (const double x : {-3.4, -0.15, 2.9}) {
        for (const double y : {-2.95, 0.3, 3.55}) {
            for (const double z : {-3.1, 0.05, 3.2}) {
                const std::uint32_t n = std::uint32_t(points.size());
                // A horizontal triangle, and a vertical one through its inside.
                for (const Vec3d& p : {Vec3d(-0.5, -0.5, 0), Vec3d(0.7, -0.5, 0), Vec3d(0, 0.7, 0),
                                       Vec3d(0.1, -0.2, -0.5), Vec3d(0.1, 0.3, -0.5),
                                       Vec3d(0.1, 0, 0.5)}) {
                    points.push_back(Vec3d(x, y, z) + p);
                }
                const Vec3I first(n, n + 1, n + 2), second(n + 3, n + 4, n + 5);
                if (sites++ % 2 == 0) {
                    within.triangles.push_back(first);
                    within.triangles.push_back(second);
                } else {
                    between.triangles.push_back(first);
                    other.triangles.push_back(second);
                }
            }
        }
    }
    const vdbi::InterfaceMesh mesh = makeMesh(points, {between, other, within});
    ASSERT_EQ(intersectingPairs(mesh).size(), sites);

    const std::vector<std::uint8_t> movable(points.size(), 0);
    for (const double cellSize : {0.1, 0.5, 1.0, 3.0}) {
        vdbi::SeparationSettings settings = unitSettings();
        settings.cellSize = cellSize;
        settings.rounds = 1;
        vdbi::InterfaceMesh copy = mesh;
        EXPECT_EQ(vdbi::separatePatches(copy, movable, settings), sites) << "cell " << cellSize;
    }
}

namespace {

/// A hexagon of six triangles around point 0 at @a centre, the others in the plane z = 0.
std::vector<Vec3d>
hexagonPoints(const Vec3d& centre)
{
    std::vector<Vec3d> points = {centre};
    for (int k = 0; k < 6; ++k) {
        const double angle = k * M_PI / 3.0;
        points.emplace_back(std::cos(angle), std::sin(angle), 0.0);
    }
    return points;
}

std::vector<Vec3I>
hexagonFan()
{
    std::vector<Vec3I> fan;
    for (std::uint32_t k = 0; k < 6; ++k) fan.emplace_back(0, 1 + k, 1 + (k + 1) % 6);
    return fan;
}

/// Patch (1, 2): the flat hexagon fan; patch (3, 4): the spike (7, 8, 9) through its first
/// triangle near point 0, from 0.22 below it.
vdbi::InterfaceMesh
spikeThroughHexagon()
{
    std::vector<Vec3d> points = hexagonPoints(Vec3d(0, 0, 0));
    points.insert(points.end(), {Vec3d(0.1, 0.1, -0.22), Vec3d(0.4, 0.35, 1.0),
                                 Vec3d(0.45, 0.15, 1.0)});
    return makeMesh(points, {{1, 2, hexagonFan()}, {3, 4, {Vec3I(7, 8, 9)}}});
}

} // namespace

// Patch (1, 2) is a flat hexagonal fan around its only free point 0, at the mean of its
// ring; a locked spike of patch (3, 4), which shares no label with it (no push), pierces the
// first triangle near point 0 and stands up from 0.22 below it. Neither the mean of the ring nor one step
// of 0.1 along or against the normal (up or down) frees the spike: one step used to be all
// separation tried. Three steps down, a shallow cone passes under the spike's lower corner.
TEST_F(TestPatchSeparation, testSearchAlongNormalFreesDeepCrossing)
{
    vdbi::InterfaceMesh mesh = spikeThroughHexagon();
    ASSERT_EQ(intersectingPairs(mesh),
              (std::set<std::pair<std::uint32_t, std::uint32_t>>{{0, 6}}));

    const vdbi::InterfaceMesh before = mesh;
    std::vector<std::uint8_t> movable(mesh.points.size(), 0);
    movable[0] = 1;
    EXPECT_EQ(vdbi::separatePatches(mesh, movable, unitSettings()), 0u);
    EXPECT_TRUE(intersectingPairs(mesh).empty());
    EXPECT_NEAR(mesh.points[0].z(), -0.3, 1e-12);
    EXPECT_NEAR(mesh.points[0].x(), 0.0, 1e-12);
    EXPECT_NEAR(mesh.points[0].y(), 0.0, 1e-12);
    expectAllowedMoves(before, mesh, movable, unitSettings().maxMove);
}

// Patch (1, 2) is a square of two triangles whose corners are all curve samples; a small
// locked triangle of (1, 3) stands through the first one, near the diagonal. Separation has
// nothing to move. splitMeetingTriangles() splits the diagonal, the only inner edge, at its
// midpoint (point 7); separateAround() pushes that point away from label 1 (up, along the
// square's normal) and the tent it raises passes over the small triangle.
TEST_F(TestPatchSeparation, testSplitFreesLockedTriangles)
{
    vdbi::InterfaceMesh mesh = squareThroughSmallTriangle();
    const vdbi::PointArray points = mesh.points;
    ASSERT_EQ(intersectingPairs(mesh),
              (std::set<std::pair<std::uint32_t, std::uint32_t>>{{0, 2}}));
    std::vector<std::uint8_t> movable(points.size(), 0);
    const vdbi::SeparationSettings settings = unitSettings();
    vdbi::TrianglePairs meeting;
    EXPECT_EQ(vdbi::separatePatches(mesh, movable, settings, nullptr, &meeting), 1u);
    ASSERT_EQ(meeting, (vdbi::TrianglePairs{{0, 2}}));
    ASSERT_EQ(intersectingPairs(mesh).size(), 1u);

    vdbi::PointArray start = mesh.points;
    EXPECT_EQ(vdbi::splitMeetingTriangles(mesh, movable, start, meeting), 1u);
    ASSERT_EQ(mesh.points.size(), 8u);
    EXPECT_EQ(mesh.points[7], Vec3d(1, 1, 0));
    EXPECT_EQ(start[7], Vec3d(1, 1, 0));
    EXPECT_EQ(movable[7], 1);
    EXPECT_EQ(mesh.patches[0].triangleCount, 4u);
    EXPECT_EQ(mesh.patches[1].firstTriangle, 4u);
    EXPECT_EQ(mesh.triangles[4], Vec3I(4, 5, 6));

    vdbi::separateAround(mesh, movable, start, settings, 7);
    EXPECT_TRUE(intersectingPairs(mesh).empty());
    for (std::size_t v = 0; v < 7; ++v) EXPECT_EQ(mesh.points[v], points[v]) << "point " << v;
    EXPECT_GT(mesh.points[7].z(), 0.0);
    EXPECT_LE((mesh.points[7] - start[7]).length(), settings.maxMove + 1e-12);
    for (std::size_t t = 0; t < 4; ++t) EXPECT_GT(normalOf(mesh, t).z(), 0.0) << "triangle " << t;
}

// The square and small triangle above, but with two free corners (1 and 2) in the meeting
// triangle: separation is left to deal with it, a split there makes short edges and sharp
// triangles for little gain. Nothing is split, nothing changes.
TEST_F(TestPatchSeparation, testSplitLeavesTrianglesWithTwoFreeCorners)
{
    vdbi::InterfaceMesh mesh = squareThroughSmallTriangle();
    const vdbi::PointArray points = mesh.points;
    const vdbi::InterfaceMesh before = mesh;
    std::vector<std::uint8_t> movable = {0, 1, 1, 0, 0, 0, 0};
    vdbi::PointArray start = mesh.points;
    EXPECT_EQ(vdbi::splitMeetingTriangles(mesh, movable, start, {{0, 2}}), 0u);
    EXPECT_EQ(mesh.points, before.points);
    EXPECT_EQ(mesh.triangles, before.triangles);
    EXPECT_EQ(movable.size(), points.size());

    // With one free corner (1) it is split as before.
    movable[2] = 0;
    EXPECT_EQ(vdbi::splitMeetingTriangles(mesh, movable, start, {{0, 2}}), 1u);
    EXPECT_EQ(mesh.points.size(), points.size() + 1);
}

// Patch (1, 2) is one triangle with a locked corner 0 and free corners 1 and 2; a locked
// triangle of patch (3, 4), which shares no label with it (no push), stands through it near
// its edge (1, 2), in the plane x = 1.75. Whatever one free corner does within 0.4, the
// triangle still reaches the plane across the standing one: the other corner holds it.
// Both corners moving together 0.3 towards the locked one clear it.
TEST_F(TestPatchSeparation, testCornersMoveTogether)
{
    const std::vector<Vec3d> points = {
        Vec3d(0, 0, 0), Vec3d(2, -1, 0), Vec3d(2, 1, 0),                           // (1, 2)
        Vec3d(1.75, -0.2, -1), Vec3d(1.75, 0.2, -1), Vec3d(1.75, 0, 1)};           // (3, 4)
    vdbi::InterfaceMesh mesh =
        makeMesh(points, {{1, 2, {Vec3I(0, 1, 2)}}, {3, 4, {Vec3I(3, 4, 5)}}});
    ASSERT_EQ(intersectingPairs(mesh),
              (std::set<std::pair<std::uint32_t, std::uint32_t>>{{0, 1}}));

    const vdbi::InterfaceMesh before = mesh;
    const std::vector<std::uint8_t> movable = {0, 1, 1, 0, 0, 0};
    EXPECT_EQ(vdbi::separatePatches(mesh, movable, unitSettings()), 0u);
    EXPECT_TRUE(intersectingPairs(mesh).empty());
    // Together: one offset for both.
    EXPECT_LT((mesh.points[1] - before.points[1] - (mesh.points[2] - before.points[2])).length(),
              1e-12);
    expectAllowedMoves(before, mesh, movable, unitSettings().maxMove);
}

// A wedge of label 3 in the frog at one voxel (the triangles within 0.8 voxel of
// (237.2, 256.9, 122.2) before separation, in voxels from there). Patch (3, 10) runs along
// the curve 0-4 as a strip of slivers: its free points 13, 14 and 15 lie 0.01-0.05 voxel
// across the curve line, on the side of patch (0, 3), so four of its triangles cross (0, 3)'s
// triangle on the curve. Any one of them, or the corners of one triangle, moving alone turns
// a sliver between them over; moving all the free corners of the meeting triangles of the
// strip together keeps the slivers as they are and frees every pair.
TEST_F(TestPatchSeparation, testMeetingTrianglesMoveTogether)
{
    const std::vector<Vec3d> points = {
        Vec3d(-0.356947, -0.141453, 0.051984), Vec3d(-0.742125, -0.905417, -0.610333),
        Vec3d(-1.369809, -0.394006, 0.020378), Vec3d(0.269188, 0.254680, -0.911328),
        Vec3d(0.278127, 0.214230, 0.050148),   Vec3d(1.001325, 0.605211, 0.076223),
        Vec3d(-0.227434, -0.368521, -0.928134), Vec3d(-0.704977, 0.584798, 0.257262),
        Vec3d(0.524464, -0.800079, 0.376695),  Vec3d(1.264068, -0.320868, -0.406021),
        Vec3d(-0.666718, 0.063396, 0.794999),  Vec3d(-1.025935, -0.714408, 0.354290),
        Vec3d(-0.192612, 0.302344, 0.040904),  Vec3d(-0.061621, 0.010658, 0.049684),
        Vec3d(0.072122, 0.036001, 0.050118),   Vec3d(0.034017, 0.030343, 0.049735),
        Vec3d(0.223605, 1.070243, 0.167492)};
    const std::vector<std::uint8_t> movable = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 0};
    vdbi::InterfaceMesh mesh = makeMesh(points, {
        {0, 3, {Vec3I(0, 1, 2), Vec3I(3, 4, 5), Vec3I(6, 4, 3), Vec3I(6, 0, 4), Vec3I(1, 0, 6),
                Vec3I(7, 0, 2)}},
        {0, 10, {Vec3I(8, 4, 0), Vec3I(9, 5, 4), Vec3I(10, 0, 7), Vec3I(4, 8, 9),
                 Vec3I(8, 0, 11), Vec3I(10, 11, 0)}},
        {3, 10, {Vec3I(7, 0, 12), Vec3I(13, 12, 0), Vec3I(13, 0, 4), Vec3I(14, 13, 4),
                 Vec3I(12, 14, 4), Vec3I(12, 15, 14), Vec3I(4, 5, 16), Vec3I(4, 16, 12),
                 Vec3I(13, 15, 12), Vec3I(14, 15, 13), Vec3I(12, 16, 7)}}});
    ASSERT_EQ(intersectingPairs(mesh),
              (std::set<std::pair<std::uint32_t, std::uint32_t>>{{3, 13}, {3, 16}, {3, 17}, {3, 20}}));

    const vdbi::InterfaceMesh before = mesh;
    vdbi::TrianglePairs left;
    vdbi::separatePatches(mesh, movable, unitSettings(), nullptr, &left);
    EXPECT_TRUE(intersectingPairs(mesh).empty());
    // What the library still counts: slivers 15 and 16 folded onto each other at their shared
    // edge (14, 4), which they meet along only.
    EXPECT_EQ(left, (vdbi::TrianglePairs{{15, 16}}));
    expectAllowedMoves(before, mesh, movable, unitSettings().maxMove);
    // Together: the three points across the curve by one offset.
    for (const std::uint32_t v : {14u, 15u}) {
        EXPECT_LT((mesh.points[v] - before.points[v] - (mesh.points[13] - before.points[13])).length(),
                  1e-12);
    }
}

// A second separation given the pairs the first left (known) moves exactly as one that
// searches the whole mesh for them; known pairs are what it starts from: none known, nothing
// moves although a pair meets.
TEST_F(TestPatchSeparation, testKnownPairsReplaceTheSearch)
{
    // The free triangle of (1, 3) through the square: moves of 0.01 do not free it.
    vdbi::InterfaceMesh mesh = squareThroughSmallTriangle();
    const std::vector<std::uint8_t> movable = {0, 0, 0, 0, 1, 1, 1};
    vdbi::SeparationSettings near = unitSettings();
    near.maxMove = 0.01;
    near.step = 0.01;
    vdbi::TrianglePairs left;
    ASSERT_GT(vdbi::separatePatches(mesh, movable, near, nullptr, &left), 0u);
    ASSERT_EQ(left.size(), intersectingPairs(mesh).size());

    vdbi::InterfaceMesh searched = mesh, seeded = mesh, unseeded = mesh;
    vdbi::TrianglePairs leftSearched, leftSeeded;
    const std::size_t count = vdbi::separatePatches(searched, movable, unitSettings(),
                                                    nullptr, &leftSearched);
    EXPECT_EQ(vdbi::separatePatches(seeded, movable, unitSettings(), nullptr, &leftSeeded,
                                    &left), count);
    EXPECT_EQ(leftSeeded, leftSearched);
    EXPECT_EQ(std::vector<Vec3d>(seeded.points.begin(), seeded.points.end()),
              std::vector<Vec3d>(searched.points.begin(), searched.points.end()));
    EXPECT_NE(seeded.points[6], mesh.points[6]);   // it did move

    const vdbi::TrianglePairs none;
    EXPECT_EQ(vdbi::separatePatches(unseeded, movable, unitSettings(), nullptr, nullptr, &none),
              0u);
    EXPECT_EQ(std::vector<Vec3d>(unseeded.points.begin(), unseeded.points.end()),
              std::vector<Vec3d>(mesh.points.begin(), mesh.points.end()));
}


// testSearchAlongNormalFreesDeepCrossing with the flat hexagon as the fan's source: the move
// to z = -0.3 that frees the spike is made under a limit of 0.35 voxel from the source, not
// under 0.25, where no move frees the pair and the centre stays.
TEST_F(TestPatchSeparation, testMovesStayNearTheSource)
{
    const vdbi::InterfaceMesh raw = spikeThroughHexagon();
    vdbi::RawPatchDistance source(raw, Vec3d(1.0), 1.0);
    std::vector<std::uint8_t> movable(raw.points.size(), 0);
    movable[0] = 1;
    for (const double limit : {0.35, 0.25}) {
        vdbi::InterfaceMesh mesh = raw;
        vdbi::SeparationSettings settings = unitSettings();
        settings.source = &source;
        settings.sourceLimit = limit;
        const bool freed = limit > 0.3;
        EXPECT_EQ(vdbi::separatePatches(mesh, movable, settings), freed ? 0u : 1u);
        EXPECT_EQ(intersectingPairs(mesh).size(), freed ? 0u : 1u);
        EXPECT_TRUE(mesh.points[0].eq(Vec3d(0, 0, freed ? -0.3 : 0.0), 1e-12))
            << mesh.points[0] << " under " << limit;
    }
}

// As above, under a limit of 0.35, with a small source triangle 0.3 above the centre: the
// centre would stay within the limit of the flat source at z = -0.3, but leave that
// triangle's centroid about 0.55 from the fan. No move that keeps it covered frees the pair.
TEST_F(TestPatchSeparation, testMovesKeepTheSourceCovered)
{
    const vdbi::InterfaceMesh start = spikeThroughHexagon();
    std::vector<Vec3d> points(start.points.begin(), start.points.end());
    points.insert(points.end(), {Vec3d(-0.05, -0.05, 0.3), Vec3d(0.1, -0.05, 0.3),
                                 Vec3d(-0.05, 0.1, 0.3)});
    std::vector<Vec3I> fan = hexagonFan();
    fan.emplace_back(10, 11, 12);
    const vdbi::InterfaceMesh raw = makeMesh(points, {{1, 2, fan}, {3, 4, {Vec3I(7, 8, 9)}}});
    vdbi::RawPatchDistance source(raw, Vec3d(1.0), 1.0);
    std::vector<std::uint8_t> movable(start.points.size(), 0);
    movable[0] = 1;
    vdbi::InterfaceMesh mesh = start;
    vdbi::SeparationSettings settings = unitSettings();
    settings.source = &source;
    settings.sourceLimit = 0.35;
    EXPECT_EQ(vdbi::separatePatches(mesh, movable, settings), 1u);
    EXPECT_EQ(intersectingPairs(mesh).size(), 1u);
    EXPECT_EQ(mesh.points, start.points);
}

// The hexagon's centre lies 1.5 above its source, the flat hexagon: pulled down the way to
// its nearest source point, by eighths, it stops at the first within 0.95 of it, 0.9375.
TEST_F(TestPatchSeparation, testPullTowardsSource)
{
    vdbi::InterfaceMesh mesh = makeMesh(hexagonPoints(Vec3d(0, 0, 1.5)), {{1, 2, hexagonFan()}});
    const vdbi::InterfaceMesh raw = makeMesh(hexagonPoints(Vec3d(0, 0, 0)),
                                             {{1, 2, hexagonFan()}});
    vdbi::RawPatchDistance source(raw, Vec3d(1.0), 2.0);
    vdbi::SeparationSettings settings = pullSettings(source);
    std::vector<std::uint8_t> movable(7, 0);
    movable[0] = 1;
    EXPECT_EQ(vdbi::pullTowardsSource(mesh, movable, settings, {0}), 1u);
    EXPECT_TRUE(mesh.points[0].eq(Vec3d(0, 0, 0.9375), 1e-12)) << mesh.points[0];
    // Within the limit now: a second pull leaves it.
    EXPECT_EQ(vdbi::pullTowardsSource(mesh, movable, settings, {0}), 0u);
}

// As above, with a locked triangle of another patch level at z = 0.6 around the axis: at
// 0.9375 and at 0.75 the fan would pass through it, so the centre goes on to 0.5625, under it.
TEST_F(TestPatchSeparation, testPullAddsNoMeetingPair)
{
    std::vector<Vec3d> points = hexagonPoints(Vec3d(0, 0, 1.5));
    points.insert(points.end(), {Vec3d(0.5, 0, 0.6), Vec3d(-0.25, 0.45, 0.6),
                                 Vec3d(-0.25, -0.45, 0.6)});
    vdbi::InterfaceMesh mesh = makeMesh(points, {{1, 2, hexagonFan()}, {3, 4, {Vec3I(7, 8, 9)}}});
    ASSERT_TRUE(intersectingPairs(mesh).empty());
    std::vector<Vec3d> rawPoints = hexagonPoints(Vec3d(0, 0, 0));
    rawPoints.insert(rawPoints.end(), points.begin() + 7, points.end());
    const vdbi::InterfaceMesh raw =
        makeMesh(rawPoints, {{1, 2, hexagonFan()}, {3, 4, {Vec3I(7, 8, 9)}}});
    vdbi::RawPatchDistance source(raw, Vec3d(1.0), 2.0);
    vdbi::SeparationSettings settings = pullSettings(source);
    std::vector<std::uint8_t> movable(points.size(), 0);
    movable[0] = 1;
    EXPECT_EQ(vdbi::pullTowardsSource(mesh, movable, settings, {0}), 1u);
    EXPECT_TRUE(mesh.points[0].eq(Vec3d(0, 0, 0.5625), 1e-12)) << mesh.points[0];
    EXPECT_TRUE(intersectingPairs(mesh).empty());
}

// A locked triangle (0, 1, 2) of patch (1, 2), with a neighbour across each edge, has a small
// locked triangle of (1, 3) standing through it. Its longest edge (0, 1) is split, at
// (2, 0, 0); with a source (the voxel faces) lying only around the midpoint of (1, 2), that
// edge's midpoint is within the limit and the other not: (1, 2) is split instead, at
// (2.5, 1, 0). A far midpoint moved by separation would stay far.
TEST_F(TestPatchSeparation, testSplitPrefersMidpointsNearTheSource)
{
    const std::vector<Vec3d> points = {
        Vec3d(0, 0, 0), Vec3d(4, 0, 0), Vec3d(1, 2, 0), Vec3d(2, -1, 0), Vec3d(3, 2, 0),
        Vec3d(-1, 1, 0),                                                               // (1, 2)
        Vec3d(1.5, 0.6, -0.5), Vec3d(1.9, 0.6, -0.5), Vec3d(1.7, 0.7, 0.5)};          // (1, 3)
    const std::vector<PatchSpec> patches = {
        {1, 2, {Vec3I(0, 1, 2), Vec3I(1, 0, 3), Vec3I(2, 1, 4), Vec3I(0, 2, 5)}},
        {1, 3, {Vec3I(6, 7, 8)}}};
    const vdbi::InterfaceMesh raw = makeMesh(
        {Vec3d(2.3, 0.9, 0), Vec3d(2.7, 0.9, 0), Vec3d(2.5, 1.2, 0), points[6], points[7],
         points[8]},
        {{1, 2, {Vec3I(0, 1, 2)}}, {1, 3, {Vec3I(3, 4, 5)}}});
    vdbi::RawPatchDistance source(raw, Vec3d(1.0), 1.0);
    for (const bool withSource : {false, true}) {
        vdbi::InterfaceMesh mesh = makeMesh(points, patches);
        ASSERT_EQ(intersectingPairs(mesh),
                  (std::set<std::pair<std::uint32_t, std::uint32_t>>{{0, 4}}));
        std::vector<std::uint8_t> movable(points.size(), 0);
        vdbi::PointArray start = mesh.points;
        EXPECT_EQ(vdbi::splitMeetingTriangles(mesh, movable, start, {{0, 4}},
                                              withSource ? &source : nullptr, 0.5), 1u);
        ASSERT_EQ(mesh.points.size(), points.size() + 1);
        EXPECT_EQ(mesh.points.back(), withSource ? Vec3d(2.5, 1, 0) : Vec3d(2, 0, 0));
    }
}

namespace {

/// Patch (1, 2): a tent of six triangles around free apex 0 at height @a apex over a locked
/// hexagon of radius 2 at z = 0; its source, the unit voxel face around the origin at z = 0.
vdbi::InterfaceMesh
tentOverFace(double apex, vdbi::InterfaceMesh& raw)
{
    std::vector<Vec3d> points = {Vec3d(0, 0, apex)};
    for (int k = 0; k < 6; ++k) {
        const double angle = k * M_PI / 3.0;
        points.emplace_back(2.0 * std::cos(angle), 2.0 * std::sin(angle), 0.0);
    }
    raw = makeMesh({Vec3d(-0.5, -0.5, 0), Vec3d(0.5, -0.5, 0), Vec3d(0.5, 0.5, 0),
                    Vec3d(-0.5, 0.5, 0)},
                   {{1, 2, {Vec3I(0, 1, 2), Vec3I(0, 2, 3)}}});
    return makeMesh(points, {{1, 2, hexagonFan()}});
}

} // namespace

// The voxel face's centre, the origin, lies 3 * sqrt(3) / sqrt(12) = 1.5 from the tent of
// height 3. The apex goes down towards it by eighths of the way: at height 1.125 (five
// eighths) the tent comes within sqrt(3) * 1.125 / sqrt(3 + 1.125^2) = 0.943 of it, under
// the limit 0.95; at 1.5 (four eighths) it stays 1.134 away.
TEST_F(TestPatchSeparation, testPullTowardsFaceCentres)
{
    vdbi::InterfaceMesh raw;
    vdbi::InterfaceMesh mesh = tentOverFace(3.0, raw);
    const std::vector<vdbi::FaceCentre> far =
        vdbi::findFarFaceCentres(raw, mesh, Vec3d(1.0), 0.95);
    ASSERT_EQ(far.size(), 1u);
    EXPECT_EQ(far[0].point, Vec3d(0, 0, 0));
    vdbi::RawPatchDistance source(raw, Vec3d(1.0), 4.0);
    vdbi::SeparationSettings settings = pullSettings(source);
    std::vector<std::uint8_t> movable(7, 0);
    movable[0] = 1;
    EXPECT_EQ(vdbi::pullTowardsFaceCentres(mesh, movable, settings, far), 0u);
    EXPECT_TRUE(mesh.points[0].eq(Vec3d(0, 0, 1.125), 1e-12)) << mesh.points[0];
    EXPECT_TRUE(vdbi::findFarFaceCentres(raw, mesh, Vec3d(1.0), 0.95).empty());
    // Within the limit now: a second pull moves nothing.
    EXPECT_EQ(vdbi::pullTowardsFaceCentres(mesh, movable, settings, far), 0u);
    EXPECT_TRUE(mesh.points[0].eq(Vec3d(0, 0, 1.125), 1e-12)) << mesh.points[0];
    // Not farther than maxMove: the apex cannot get there.
    vdbi::InterfaceMesh high = tentOverFace(3.0, raw);
    settings.maxMove = 1.5;
    EXPECT_EQ(vdbi::pullTowardsFaceCentres(high, movable, settings, far), 1u);
    EXPECT_EQ(high.points[0], Vec3d(0, 0, 3.0));
}

// As above, with a locked triangle of patch (3, 4) level at z = 0.6 inside the tent, its
// corners 1.2 from the axis: with the apex at 1.125 the tent's sides would pass through it,
// so the centre stays far and nothing moves.
TEST_F(TestPatchSeparation, testPullToFaceCentreAddsNoMeetingPair)
{
    vdbi::InterfaceMesh raw;
    vdbi::InterfaceMesh tent = tentOverFace(3.0, raw);
    std::vector<Vec3d> points(tent.points.begin(), tent.points.end());
    points.insert(points.end(), {Vec3d(1.2, 0, 0.6), Vec3d(-0.6, 1.04, 0.6),
                                 Vec3d(-0.6, -1.04, 0.6)});
    vdbi::InterfaceMesh mesh = makeMesh(points, {{1, 2, hexagonFan()}, {3, 4, {Vec3I(7, 8, 9)}}});
    ASSERT_TRUE(intersectingPairs(mesh).empty());
    const std::vector<vdbi::FaceCentre> far =
        vdbi::findFarFaceCentres(raw, mesh, Vec3d(1.0), 0.95);
    ASSERT_EQ(far.size(), 1u);
    vdbi::RawPatchDistance source(raw, Vec3d(1.0), 4.0);
    vdbi::SeparationSettings settings = pullSettings(source);
    std::vector<std::uint8_t> movable(points.size(), 0);
    movable[0] = 1;
    EXPECT_EQ(vdbi::pullTowardsFaceCentres(mesh, movable, settings, far), 1u);
    EXPECT_TRUE(std::equal(points.begin(), points.end(), mesh.points.begin()));
    EXPECT_TRUE(intersectingPairs(mesh).empty());
}


namespace {

/// A jittered plane of n x n points, spacing 1, its border fixed: every inner point's fan
/// has sharp triangles somewhere.
vdbi::InterfaceMesh
jitteredPlane(int n, std::vector<std::uint8_t>& movable)
{
    std::vector<Vec3d> points;
    movable.clear();
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const bool border = x == 0 || y == 0 || x == n - 1 || y == n - 1;
            // A fixed pattern, not random: the same mesh on every machine.
            const double dx = border ? 0.0 : 0.35 * std::sin(1.7 * x + 2.3 * y);
            const double dy = border ? 0.0 : 0.35 * std::cos(2.9 * x - 1.1 * y);
            points.emplace_back(x + dx, y + dy, 0.05 * std::sin(0.5 * x));
            movable.push_back(border ? 0 : 1);
        }
    }
    std::vector<Vec3I> triangles;
    for (int y = 0; y + 1 < n; ++y) {
        for (int x = 0; x + 1 < n; ++x) {
            const unsigned a = y * n + x, b = a + 1, c = a + n, d = c + 1;
            triangles.emplace_back(a, b, d);
            triangles.emplace_back(a, d, c);
        }
    }
    return makeMesh(points, {{0, 1, triangles}});
}

/// GuardedMoves with the grid cells of a point's fan in sight.
class BlockProbe : public vdbi::GuardedMoves
{
public:
    using GuardedMoves::GuardedMoves;

    void fanCells(std::uint32_t v, openvdb::Vec3i& low, openvdb::Vec3i& high) const
    {
        low = openvdb::Vec3i(std::numeric_limits<int>::max());
        high = openvdb::Vec3i(std::numeric_limits<int>::min());
        for (std::uint32_t i = mStart[v]; i < mStart[v + 1]; ++i) {
            openvdb::Vec3i lo, hi;
            mGrid.cellRange(mAround[i], lo, hi);
            low = openvdb::math::minComponent(low, lo);
            high = openvdb::math::maxComponent(high, hi);
        }
    }
};

/// The pairs of points in different blocks of one colour whose fans' cells, one of them
/// widened by a cell (what the guards look at without a source), overlap: moves that could
/// see each other.
std::size_t
blocksThatSeeEachOther(const BlockProbe& probe, const vdbi::GuardedMoves::IndependentBlocks& b)
{
    std::size_t count = 0;
    for (int colour = 0; colour < 8; ++colour) {
        for (std::size_t i = b.colourStart[colour]; i < b.colourStart[colour + 1]; ++i) {
            for (std::size_t j = i + 1; j < b.colourStart[colour + 1]; ++j) {
                for (std::size_t p = b.blockStart[i]; p < b.blockStart[i + 1]; ++p) {
                    for (std::size_t q = b.blockStart[j]; q < b.blockStart[j + 1]; ++q) {
                        openvdb::Vec3i lv, hv, lw, hw;
                        probe.fanCells(b.points[p], lv, hv);
                        probe.fanCells(b.points[q], lw, hw);
                        bool apart = false;
                        for (int k = 0; k < 3; ++k) {
                            apart = apart || lw[k] > hv[k] + 1 || lv[k] > hw[k] + 1;
                        }
                        count += !apart;
                    }
                }
            }
        }
    }
    return count;
}

} // namespace

// independentBlocks() on a plane of 40 x 40 points: every movable point once, ascending in
// its block; several blocks per colour; no two points in different blocks of a colour whose
// guards could see each other's fans. The check finds such pairs in a bad partition (every
// point its own block, all of one colour).
TEST_F(TestPatchSeparation, testIndependentBlocksKeepMovesApart)
{
    std::vector<std::uint8_t> movable;
    vdbi::InterfaceMesh mesh = jitteredPlane(40, movable);
    const vdbi::SeparationSettings settings = unitSettings();
    const BlockProbe probe(mesh, movable, settings, nullptr);
    std::vector<std::uint32_t> all(mesh.points.size());
    for (std::uint32_t v = 0; v < all.size(); ++v) all[v] = v;
    const vdbi::GuardedMoves::IndependentBlocks blocks = probe.independentBlocks(all);

    ASSERT_EQ(blocks.colourStart.size(), 9u);
    EXPECT_EQ(blocks.colourStart.front(), 0u);
    EXPECT_EQ(blocks.colourStart.back(), blocks.blockStart.size() - 1);
    EXPECT_TRUE(std::is_sorted(blocks.colourStart.begin(), blocks.colourStart.end()));
    std::vector<int> seen(mesh.points.size(), 0);
    for (std::size_t b = 0; b + 1 < blocks.blockStart.size(); ++b) {
        EXPECT_LT(blocks.blockStart[b], blocks.blockStart[b + 1]) << "block " << b;
        EXPECT_TRUE(std::is_sorted(blocks.points.begin() + blocks.blockStart[b],
                                   blocks.points.begin() + blocks.blockStart[b + 1]));
    }
    for (const std::uint32_t v : blocks.points) ++seen[v];
    for (std::uint32_t v = 0; v < seen.size(); ++v) EXPECT_EQ(seen[v], movable[v]) << v;
    std::size_t busiest = 0;
    for (int c = 0; c < 8; ++c) {
        busiest = std::max(busiest, blocks.colourStart[c + 1] - blocks.colourStart[c]);
    }
    EXPECT_GE(busiest, 4u);
    EXPECT_EQ(blocksThatSeeEachOther(probe, blocks), 0u);

    vdbi::GuardedMoves::IndependentBlocks bad;
    for (std::size_t i = 0; i < blocks.points.size(); ++i) {
        bad.points.push_back(blocks.points[i]);
        bad.blockStart.push_back(i);
    }
    bad.blockStart.push_back(bad.points.size());
    bad.colourStart.assign(9, bad.points.size());
    bad.colourStart[0] = 0;
    EXPECT_GT(blocksThatSeeEachOther(probe, bad), 0u);
}

// shapeSharpFans() moves many points of the jittered plane, the same way on one thread and
// on several, and every move is allowed.
TEST_F(TestPatchSeparation, testShapeSharpFansSameOnAnyThreads)
{
    std::vector<std::uint8_t> movable;
    const vdbi::InterfaceMesh start = jitteredPlane(40, movable);
    std::vector<std::uint32_t> all(start.points.size());
    for (std::uint32_t v = 0; v < all.size(); ++v) all[v] = v;
    vdbi::SeparationSettings settings = unitSettings();
    settings.threaded = false;
    vdbi::InterfaceMesh serial = start;
    const std::size_t moved = vdbi::shapeSharpFans(serial, movable, settings, all);
    EXPECT_GT(moved, 100u);
    expectAllowedMoves(start, serial, movable, settings.maxMove);
    EXPECT_TRUE(intersectingPairs(serial).empty());

    settings.threaded = true;
    vdbi::InterfaceMesh threaded = start;
    EXPECT_EQ(vdbi::shapeSharpFans(threaded, movable, settings, all), moved);
    EXPECT_EQ(threaded.points, serial.points);
}
