// SPDX-License-Identifier: Apache-2.0
/// @file TestFaceCentreCoverage.cc
/// @brief findFarFaceCentres() on hand-made patches with known distances, and against a brute
/// force over every triangle on a seeded random mesh.

#include "support/HandMadeMeshes.h"

#include <vdbi/FaceCentreCoverage.h>
#include <vdbi/RawPatchDistance.h>
#include <vdbi/ReferenceSurface.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

using openvdb::Vec3d;
using openvdb::Vec3I;

class TestFaceCentreCoverage : public ::testing::Test
{
};

namespace {

/// The two triangles of the unit voxel face [x, x + 1] x [0, 1] at z = 0, as the extraction
/// makes them (legs along the axes), appended to @a points and @a triangles.
void
addFace(double x, std::vector<Vec3d>& points, std::vector<Vec3I>& triangles)
{
    const std::uint32_t first = std::uint32_t(points.size());
    points.insert(points.end(), {Vec3d(x, 0, 0), Vec3d(x + 1, 0, 0), Vec3d(x + 1, 1, 0),
                                 Vec3d(x, 1, 0)});
    triangles.insert(triangles.end(), {Vec3I(first, first + 1, first + 2),
                                       Vec3I(first, first + 2, first + 3)});
}

/// A seeded random staircase of unit voxel faces, @a side x @a side, each a step of -1, 0
/// or 1 voxel up from the one before, appended as addFace() does.
void
addRandomStaircase(int side, std::mt19937& random, std::vector<Vec3d>& points,
                   std::vector<Vec3I>& triangles)
{
    std::uniform_int_distribution<int> step(-1, 1);
    int z = 0;
    for (int x = 0; x < side; ++x) {
        for (int y = 0; y < side; ++y) {
            z += step(random);
            const std::uint32_t first = std::uint32_t(points.size());
            points.insert(points.end(), {Vec3d(x, y, z), Vec3d(x + 1, y, z),
                                         Vec3d(x + 1, y + 1, z), Vec3d(x, y + 1, z)});
            triangles.insert(triangles.end(), {Vec3I(first, first + 1, first + 2),
                                               Vec3I(first, first + 2, first + 3)});
        }
    }
}

} // namespace

// Raw patch (1, 2): the voxel faces at x in [0, 1] and [2, 3]; remeshed: the unit square
// [0, 1] x [0, 1] half a voxel above. The first centre is 0.5 voxel from it; the second,
// (2.5, 0.5, 0), is sqrt(1.5^2 + 0.5^2) = 1.58 from its edge x = 1: the only far one,
// reported once for its two triangles. A triangle of patch (1, 3) right over it does not
// count. With voxels 2 high and everything twice as high in world space: the same.
TEST_F(TestFaceCentreCoverage, testFindsTheFarCentreOnce)
{
    for (const double height : {1.0, 2.0}) {
        std::vector<Vec3d> rawPoints;
        std::vector<Vec3I> rawFaces;
        addFace(0.0, rawPoints, rawFaces);
        addFace(2.0, rawPoints, rawFaces);
        rawPoints.insert(rawPoints.end(), {Vec3d(2, 0, 0), Vec3d(3, 0, 0), Vec3d(2.5, 1, 0)});
        const vdbi::InterfaceMesh raw =
            vdbi_test::makeMesh(rawPoints, {{1, 2, rawFaces}, {1, 3, {Vec3I(8, 9, 10)}}});
        const std::vector<Vec3d> points = {
            Vec3d(0, 0, 0.5 * height), Vec3d(1, 0, 0.5 * height), Vec3d(1, 1, 0.5 * height),
            Vec3d(0, 1, 0.5 * height), Vec3d(2, 0, 0.2 * height), Vec3d(3, 0, 0.2 * height),
            Vec3d(2.5, 1, 0.2 * height)};
        const vdbi::InterfaceMesh mesh = vdbi_test::makeMesh(
            points, {{1, 2, {Vec3I(0, 1, 2), Vec3I(0, 2, 3)}}, {1, 3, {Vec3I(4, 5, 6)}}});
        for (const bool threaded : {false, true}) {
            const std::vector<vdbi::FaceCentre> far =
                vdbi::findFarFaceCentres(raw, mesh, Vec3d(1, 1, height), 0.95, threaded);
            ASSERT_EQ(far.size(), 1u) << height;
            EXPECT_EQ(far[0].patch, 0u);
            EXPECT_EQ(far[0].point, Vec3d(2.5, 0.5, 0.0));
            // Within 1.6 voxels, none.
            EXPECT_TRUE(vdbi::findFarFaceCentres(raw, mesh, Vec3d(1, 1, height), 1.6, threaded)
                            .empty());
        }
    }
}

// A seeded random staircase of voxel faces (one patch) and a random set of triangles near
// it: the far centres are exactly those that testing every triangle finds, for several
// limits (the grid's cells are two limits wide).
TEST_F(TestFaceCentreCoverage, testMatchesBruteForce)
{
    std::mt19937 random(20261206);
    std::uniform_real_distribution<double> jitter(-1.5, 1.5);
    std::vector<Vec3d> rawPoints;
    std::vector<Vec3I> rawFaces;
    addRandomStaircase(20, random, rawPoints, rawFaces);
    std::vector<Vec3d> points;
    std::vector<Vec3I> triangles;
    for (int k = 0; k < 300; ++k) {
        const Vec3d& anchor = rawPoints[std::size_t(k) * 4 % rawPoints.size()];
        const std::uint32_t first = std::uint32_t(points.size());
        for (int i = 0; i < 3; ++i) {
            points.push_back(anchor + Vec3d(jitter(random), jitter(random), jitter(random)));
        }
        triangles.emplace_back(first, first + 1, first + 2);
    }
    const vdbi::InterfaceMesh raw = vdbi_test::makeMesh(rawPoints, {{1, 2, rawFaces}});
    const vdbi::InterfaceMesh mesh = vdbi_test::makeMesh(points, {{1, 2, triangles}});
    for (const double limit : {0.3, 0.95, 2.5}) {
        std::vector<Vec3d> expected;
        for (std::size_t t = 0; t < rawFaces.size(); t += 2) {
            const Vec3I& f = rawFaces[t];
            const Vec3d centre = 0.5 * (rawPoints[f[0]] + rawPoints[f[2]]);
            bool near = false;
            for (const Vec3I& g : triangles) {
                Vec3d bary;
                near = near || (vdbi::closestPointOnTriangle(centre, points[g[0]], points[g[1]],
                                                             points[g[2]], bary) - centre)
                                   .length() <= limit;
            }
            if (!near) expected.push_back(centre);
        }
        const std::vector<vdbi::FaceCentre> far =
            vdbi::findFarFaceCentres(raw, mesh, Vec3d(1.0), limit);
        std::vector<Vec3d> found;
        for (const vdbi::FaceCentre& c : far) found.push_back(c.point);
        EXPECT_EQ(found, expected) << limit;
        EXPECT_GT(expected.size(), 0u) << limit;
        EXPECT_LT(expected.size(), rawFaces.size() / 2) << limit;
    }
}

// A patch large enough to be searched in several tasks (over 32768 raw triangles, in
// parallel or not) finds exactly the centres that its two halves find as patches of their
// own, each searched in one task.
TEST_F(TestFaceCentreCoverage, testLargePatchEqualsItsHalves)
{
    std::mt19937 random(20261207);
    std::uniform_real_distribution<double> jitter(-1.5, 1.5);
    std::vector<Vec3d> rawPoints;
    std::vector<Vec3I> rawFaces;
    addRandomStaircase(150, random, rawPoints, rawFaces);   // 45,000 raw triangles
    std::vector<Vec3d> points;
    std::vector<Vec3I> triangles;
    for (std::size_t face = 0; face < rawFaces.size() / 2; ++face) {
        const Vec3d& anchor = rawPoints[4 * face];
        const std::uint32_t first = std::uint32_t(points.size());
        for (int i = 0; i < 3; ++i) {
            points.push_back(anchor + Vec3d(jitter(random), jitter(random), jitter(random)));
        }
        triangles.emplace_back(first, first + 1, first + 2);
    }
    const std::size_t half = rawFaces.size() / 2;   // even: no face is cut in two
    const std::vector<Vec3I> firstHalf(rawFaces.begin(), rawFaces.begin() + half);
    const std::vector<Vec3I> secondHalf(rawFaces.begin() + half, rawFaces.end());
    const vdbi::InterfaceMesh whole = vdbi_test::makeMesh(rawPoints, {{1, 2, rawFaces}});
    const vdbi::InterfaceMesh halves =
        vdbi_test::makeMesh(rawPoints, {{1, 2, firstHalf}, {1, 3, secondHalf}});
    const vdbi::InterfaceMesh mesh = vdbi_test::makeMesh(points, {{1, 2, triangles}});
    const vdbi::InterfaceMesh twice =
        vdbi_test::makeMesh(points, {{1, 2, triangles}, {1, 3, triangles}});
    auto pointsOf = [](const std::vector<vdbi::FaceCentre>& far) {
        std::vector<Vec3d> found;
        for (const vdbi::FaceCentre& c : far) found.push_back(c.point);
        return found;
    };
    for (const double limit : {0.5, 0.95}) {
        const std::vector<Vec3d> expected =
            pointsOf(vdbi::findFarFaceCentres(halves, twice, Vec3d(1.0), limit, false));
        EXPECT_GT(expected.size(), 100u) << limit;
        EXPECT_LT(expected.size(), half / 2) << limit;   // of the 22,500 faces
        for (const bool threaded : {false, true}) {
            EXPECT_EQ(pointsOf(vdbi::findFarFaceCentres(whole, mesh, Vec3d(1.0), limit,
                                                        threaded)),
                      expected) << limit << " " << threaded;
        }
    }
}
