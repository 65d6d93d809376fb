// SPDX-License-Identifier: Apache-2.0
/// @file TestRawPatchDistance.cc
/// @brief RawPatchDistance against exact distances on hand-made patches and against a brute
/// force over every triangle on a seeded random staircase.

#include "support/HandMadeMeshes.h"

#include <vdbi/RawPatchDistance.h>
#include <vdbi/ReferenceSurface.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

using openvdb::Vec3d;
using openvdb::Vec3I;

class TestRawPatchDistance : public ::testing::Test
{
};

namespace {

/// Patch (1, 2): the unit square at z = 0; patch (1, 3): the unit square at x = 0.
vdbi::InterfaceMesh
twoSquares()
{
    const std::vector<Vec3d> points = {Vec3d(0, 0, 0), Vec3d(1, 0, 0), Vec3d(1, 1, 0),
                                       Vec3d(0, 1, 0), Vec3d(0, 0, 1), Vec3d(0, 1, 1)};
    return vdbi_test::makeMesh(points, {{1, 2, {Vec3I(0, 1, 2), Vec3I(0, 2, 3)}},
                                        {1, 3, {Vec3I(0, 3, 5), Vec3I(0, 5, 4)}}});
}

} // namespace

// Distances count in voxels along each axis: with voxels 2 high, 0.6 above the square is 0.3.
TEST_F(TestRawPatchDistance, testExactDistancesInVoxels)
{
    const vdbi::InterfaceMesh raw = twoSquares();
    vdbi::RawPatchDistance distance(raw, Vec3d(1, 1, 2), 1.5);

    vdbi::RawPatchDistance::Hit hit = distance.nearest(Vec3d(0.5, 0.5, 0.6), 0);
    EXPECT_NEAR(hit.distance, 0.3, 1e-12);
    EXPECT_TRUE(hit.point.eq(Vec3d(0.5, 0.5, 0.0), 1e-12)) << hit.point;

    // Beside the square: the nearest point is on its edge x = 1.
    hit = distance.nearest(Vec3d(2.0, 0.25, 0.0), 0);
    EXPECT_NEAR(hit.distance, 1.0, 1e-12);
    EXPECT_TRUE(hit.point.eq(Vec3d(1.0, 0.25, 0.0), 1e-12)) << hit.point;

    // Beyond the radius: the radius, at the query.
    hit = distance.nearest(Vec3d(0.5, 0.5, 4.0), 0);
    EXPECT_DOUBLE_EQ(hit.distance, 1.5);
    EXPECT_EQ(hit.point, Vec3d(0.5, 0.5, 4.0));

    // (0.8, 0.5, 0.4): 0.2 voxel above (1, 2), 0.8 voxel from (1, 3); the farther one counts.
    hit = distance.farthest(Vec3d(0.8, 0.5, 0.4), {0, 1});
    EXPECT_NEAR(hit.distance, 0.8, 1e-12);
    EXPECT_TRUE(hit.point.eq(Vec3d(0.0, 0.5, 0.4), 1e-12)) << hit.point;
    EXPECT_NEAR(distance.farthest(Vec3d(0.8, 0.5, 0.4), {0}).distance, 0.2, 1e-12);
}

// A staircase of voxel faces over a random height field, anisotropic voxels: every distance
// under the radius is the brute-force minimum over all triangles, every other is the radius.
TEST_F(TestRawPatchDistance, testMatchesBruteForceOnRandomStaircase)
{
    const Vec3d voxel(1.0, 1.25, 1.5);
    const int n = 12;
    std::mt19937 random(20261205);
    std::uniform_int_distribution<int> height(0, 3);
    std::vector<int> h(n * n);
    for (int& z : h) z = height(random);
    std::vector<Vec3d> points;
    std::vector<Vec3I> triangles;
    auto square = [&](const Vec3d& o, const Vec3d& u, const Vec3d& v) {
        const std::uint32_t first = std::uint32_t(points.size());
        for (const Vec3d& p : {o, o + u, o + u + v, o + v}) {
            points.push_back(Vec3d(p[0] * voxel[0], p[1] * voxel[1], p[2] * voxel[2]));
        }
        triangles.push_back(Vec3I(first, first + 1, first + 2));
        triangles.push_back(Vec3I(first, first + 2, first + 3));
    };
    for (int x = 0; x < n; ++x) {
        for (int y = 0; y < n; ++y) {
            const int z = h[x * n + y];
            square(Vec3d(x, y, z), Vec3d(1, 0, 0), Vec3d(0, 1, 0));
            if (x + 1 < n) {
                const int w = h[(x + 1) * n + y];
                square(Vec3d(x + 1, y, std::min(z, w)), Vec3d(0, 1, 0),
                       Vec3d(0, 0, std::abs(w - z)));
            }
            if (y + 1 < n) {
                const int w = h[x * n + y + 1];
                square(Vec3d(x, y + 1, std::min(z, w)), Vec3d(1, 0, 0),
                       Vec3d(0, 0, std::abs(w - z)));
            }
        }
    }
    vdbi::InterfaceMesh raw = vdbi_test::makeMesh(points, {{1, 2, triangles}});
    const double radius = 1.2;
    vdbi::RawPatchDistance distance(raw, voxel, radius);

    std::uniform_real_distribution<double> along(-1.0, n + 1.0), up(-1.5, 5.0);
    int within = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3d q(along(random), along(random), up(random));
        const Vec3d world(q[0] * voxel[0], q[1] * voxel[1], q[2] * voxel[2]);
        double brute = radius;
        for (const Vec3I& t : triangles) {
            Vec3d bary;
            auto scaled = [&](std::uint32_t v) {
                const Vec3d& p = points[v];
                return Vec3d(p[0] / voxel[0], p[1] / voxel[1], p[2] / voxel[2]);
            };
            const Vec3d nearest =
                vdbi::closestPointOnTriangle(q, scaled(t[0]), scaled(t[1]), scaled(t[2]), bary);
            brute = std::min(brute, (nearest - q).length());
        }
        within += brute < radius;
        EXPECT_NEAR(distance.nearest(world, 0).distance, brute, 1e-9) << "query " << q;
    }
    // Both kinds of query were asked.
    EXPECT_GT(within, 200);
    EXPECT_LT(within, 1800);
}

// A change keeps the source covered if every voxel face centre and triangle centroid it passed
// within the limit of still is, by the changed triangles or (asked only then) by another.
// Voxels 2 high: the square's centre (1/2, 1/2, 0), once for its two halves, and their
// centroids (2/3, 1/3, 0) and (1/3, 2/3, 0); a triangle over it lifted in voxel units.
TEST_F(TestRawPatchDistance, testKeepsCovered)
{
    const vdbi::InterfaceMesh raw = twoSquares();
    vdbi::RawPatchDistance distance(raw, Vec3d(1, 1, 2), 1.5);
    auto over = [](double z) {
        return std::vector<vdbi::RawPatchDistance::Corners>{
            {{Vec3d(-1, -1, z), Vec3d(3, -1, z), Vec3d(-1, 3, z)}}};
    };
    int asked = 0;
    auto elsewhere = [&asked](bool answer) {
        return [&asked, answer](const Vec3d&) {
            ++asked;
            return answer;
        };
    };
    // Lifted from 0 to 0.5 voxel: still within 0.95.
    EXPECT_TRUE(distance.keepsCovered(0, over(0.0), over(0.5), 0.95, elsewhere(false)));
    EXPECT_EQ(asked, 0);
    // To 1.2: all three lost, unless another triangle covers them.
    EXPECT_FALSE(distance.keepsCovered(0, over(0.0), over(1.2), 0.95, elsewhere(false)));
    EXPECT_EQ(asked, 1);
    asked = 0;
    EXPECT_TRUE(distance.keepsCovered(0, over(0.0), over(1.2), 0.95, elsewhere(true)));
    EXPECT_EQ(asked, 3);
    // From 1.0 to 1.2: not within the limit before either, so nothing to keep.
    asked = 0;
    EXPECT_TRUE(distance.keepsCovered(0, over(1.0), over(1.2), 0.95, elsewhere(false)));
    EXPECT_EQ(asked, 0);
    // Patch 1, the square at x = 0, half a voxel high (no voxel face: the centroids of its
    // halves stand for it): its centroid (0, 1/3, 1/6) was 1/6 voxel under the
    // triangle; lifted to 1.2, the change loses it under a limit of 0.4.
    EXPECT_FALSE(distance.keepsCovered(1, over(0.0), over(1.2), 0.4, elsewhere(false)));
    EXPECT_EQ(asked, 1);
}

// The face centre is what the output promises to stay near: a change that leaves a triangle
// near each centroid of the square's halves but none near its centre loses the centre.
TEST_F(TestRawPatchDistance, testKeepsTheFaceCentreNotTheCentroids)
{
    const vdbi::InterfaceMesh raw = twoSquares();
    vdbi::RawPatchDistance distance(raw, Vec3d(1, 1, 2), 1.5);
    const std::vector<vdbi::RawPatchDistance::Corners> square = {
        {{Vec3d(0, 0, 0), Vec3d(1, 0, 0), Vec3d(1, 1, 0)}},
        {{Vec3d(0, 0, 0), Vec3d(1, 1, 0), Vec3d(0, 1, 0)}}};
    // Small triangles around the centroids (2/3, 1/3) and (1/3, 2/3), about 0.2 from the
    // centre.
    auto around = [](double x, double y) {
        return vdbi::RawPatchDistance::Corners{
            {Vec3d(x - 0.05, y - 0.05, 0), Vec3d(x + 0.05, y - 0.05, 0), Vec3d(x, y + 0.05, 0)}};
    };
    const std::vector<vdbi::RawPatchDistance::Corners> nearCentroids = {
        around(2.0 / 3, 1.0 / 3), around(1.0 / 3, 2.0 / 3)};
    auto nowhere = [](const Vec3d&) { return false; };
    EXPECT_FALSE(distance.keepsCovered(0, square, nearCentroids, 0.1, nowhere));
    // With one around the centre as well, it is kept.
    std::vector<vdbi::RawPatchDistance::Corners> withCentre = nearCentroids;
    withCentre.push_back(around(0.5, 0.5));
    EXPECT_TRUE(distance.keepsCovered(0, square, withCentre, 0.1, nowhere));
}

// A triangle in both lists keeps the points near it: only those near the others are asked
// about. The square's halves as they are; the second then lifted by 1.2 voxels.
TEST_F(TestRawPatchDistance, testKeepsWhatUnchangedTrianglesCover)
{
    const vdbi::InterfaceMesh raw = twoSquares();
    vdbi::RawPatchDistance distance(raw, Vec3d(1, 1, 2), 1.5);
    using Corners = vdbi::RawPatchDistance::Corners;
    auto half = [](int k, double z) {
        return k == 0 ? Corners{{Vec3d(0, 0, z), Vec3d(1, 0, z), Vec3d(1, 1, z)}}
                      : Corners{{Vec3d(0, 0, z), Vec3d(1, 1, z), Vec3d(0, 1, z)}};
    };
    int asked = 0;
    auto nowhere = [&asked](const Vec3d&) {
        ++asked;
        return false;
    };
    const std::vector<Corners> square = {half(0, 0.0), half(1, 0.0)};
    // Nothing changed: nothing to ask about.
    EXPECT_TRUE(distance.keepsCovered(0, square, square, 0.1, nowhere));
    EXPECT_EQ(asked, 0);
    // The first half stays: it keeps the centre (on its edge) and its own centroid, not the
    // other half's centroid (1/3, 2/3), 0.24 from it.
    const std::vector<Corners> firstStays = {half(0, 0.0), half(1, 1.2)};
    EXPECT_FALSE(distance.keepsCovered(0, square, firstStays, 0.1, nowhere));
    EXPECT_EQ(asked, 1);
    // Under a limit of 0.3 the first half reaches that centroid too.
    asked = 0;
    EXPECT_TRUE(distance.keepsCovered(0, square, firstStays, 0.3, nowhere));
    EXPECT_EQ(asked, 0);
}

// The centre of the voxel face a raw triangle belongs to: the two halves of a face, the fan
// triangles of a face with split sides (odd and even subdivisions), voxels of 1 x 1 x 1.5.
TEST_F(TestRawPatchDistance, testVoxelFaceCentre)
{
    using vdbi::voxelFaceCentre;
    auto expectNear = [](const Vec3d& got, const Vec3d& expected) {
        EXPECT_NEAR((got - expected).length(), 0.0, 1e-12) << got << " vs " << expected;
    };
    // Both halves of the face x = 2 over [3, 4] x [5, 6], in either order of corners.
    expectNear(voxelFaceCentre({2, 3, 5}, {2, 4, 5}, {2, 4, 6}), {2, 3.5, 5.5});
    expectNear(voxelFaceCentre({2, 3, 5}, {2, 4, 6}, {2, 3, 6}), {2, 3.5, 5.5});
    expectNear(voxelFaceCentre({2, 4, 6}, {2, 3, 5}, {2, 3, 6}), {2, 3.5, 5.5});
    // In the plane y = 1, in voxel units of a 1.5-voxel z: the same in scaled coordinates.
    const double z0 = 4.5 / 1.5, z1 = 6.0 / 1.5;
    expectNear(voxelFaceCentre({0, 1, z0}, {1, 1, z0}, {1, 1, z1}), {0.5, 1, 0.5 * (z0 + z1)});
    // A fan from the centre (2, 3.5, 5.5): a whole side, and a piece of a side split in 3.
    expectNear(voxelFaceCentre({2, 3.5, 5.5}, {2, 3, 5}, {2, 4, 5}), {2, 3.5, 5.5});
    expectNear(voxelFaceCentre({2, 4, 5 + 1.0 / 3}, {2, 3.5, 5.5}, {2, 4, 5 + 2.0 / 3}),
               {2, 3.5, 5.5});
    // Split in 4, the piece from the side's midpoint: a side along an axis from the centre,
    // unequal to the other; not a face's half, so its centroid (a point of the face).
    expectNear(voxelFaceCentre({2, 3.5, 5.5}, {2, 3.5, 5}, {2, 3.75, 5}),
               Vec3d(6, 10.75, 15.5) / 3.0);
}
