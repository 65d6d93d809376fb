// SPDX-License-Identifier: Apache-2.0

#include <vdbi/TriangleCrossing.h>

#include <vdbi/CandidateGrid.h>

#include "support/MeshIntersections.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

class TestTriangleCrossing : public ::testing::Test {};

namespace {

using vdbi::CornerTriangle;
using Point = vdbi::TriMesh::Point;

/// Triangle (a, b, c) of @a points as a CornerTriangle and as the test support's index triple.
CornerTriangle
corner(const vdbi::PointArray& points, const openvdb::Vec3I& t)
{
    auto p = [&](unsigned i) { return Point(points[i][0], points[i][1], points[i][2]); };
    return {p(t[0]), p(t[1]), p(t[2]), int(t[0]), int(t[1]), int(t[2])};
}

/// The turn between the normals of two triangles, in degrees.
double
turnDegrees(const CornerTriangle& s, const CornerTriangle& t)
{
    const double c = (s.normal | t.normal) / (s.normal.norm() * t.normal.norm());
    return std::acos(std::max(-1.0, std::min(1.0, c))) * 180.0 / M_PI;
}

/// A fan around point 0 of @a count triangles whose outer corners go @a turns times around it
/// in the plane z = @a height(k) (point k + 1 at angle 2 pi turns k / count).
struct Fan
{
    vdbi::PointArray points;
    std::vector<CornerTriangle> triangles;
};

Fan
makeFan(int count, int turns, double lift = 0.0, bool closed = true)
{
    Fan fan;
    fan.points.push_back(openvdb::Vec3d(0.0));
    for (int k = 0; k < count; ++k) {
        const double angle = 2.0 * M_PI * turns * k / count;
        fan.points.push_back(openvdb::Vec3d(std::cos(angle), std::sin(angle), lift * (k % 2)));
    }
    const int last = closed ? count : count - 1;
    for (int k = 0; k < last; ++k) {
        const unsigned a = unsigned(k + 1), b = unsigned((k + 1) % count + 1);
        fan.triangles.push_back(corner(fan.points, openvdb::Vec3I(0, a, b)));
    }
    return fan;
}

/// Two triangles on random corners: s = (0, 1, 2) and t sharing @a shared of its corners,
/// all in the plane z = 0 if @a flat (exactly coplanar, as on a flat stretch of the reference
/// surface). @a draw() gives one coordinate.
struct RandomPair
{
    vdbi::PointArray points;
    openvdb::Vec3I s{0, 1, 2}, t{3, 4, 5};
};

template<typename Draw>
RandomPair
randomPair(int shared, bool flat, Draw&& draw)
{
    RandomPair pair;
    pair.points.resize(6);
    for (auto& p : pair.points) {
        const double x = draw(), y = draw();
        p = openvdb::Vec3d(x, y, flat ? 0.0 : draw());
    }
    if (shared >= 1) pair.t = openvdb::Vec3I(0, 4, 5);
    if (shared == 2) pair.t = openvdb::Vec3I(1, 0, 5);
    return pair;
}

} // namespace


TEST_F(TestTriangleCrossing, testHandMadePairs)
{
    const vdbi::PointArray points = {
        {0, 0, 0}, {2, 0, 0}, {1, 1, 0}, {1, -1, 0},    // 0-3: flat pair over edge 0-1
        {1, 0.5, 0}, {1, 0.5, 1}, {3, 3, 3}, {1, 2, 0}, // 4-7
        {0.5, 0.2, -1}, {0.5, 0.2, 1}, {1, 0.5, -1},    // 8-10
        {2, -1, 0}, {0.8, 0.7, 0}};                      // 11-12
    auto t = [&](unsigned a, unsigned b, unsigned c) {
        return corner(points, openvdb::Vec3I(a, b, c));
    };
    // Sharing an edge: flat, folded onto each other, a right angle.
    EXPECT_FALSE(vdbi::trianglesCross(t(0, 1, 2), t(1, 0, 3)));
    EXPECT_TRUE(vdbi::trianglesCross(t(0, 1, 2), t(1, 0, 4)));
    EXPECT_FALSE(vdbi::trianglesCross(t(0, 1, 2), t(1, 0, 5)));
    // Sharing a corner in one plane: overlapping angles, and side by side.
    EXPECT_TRUE(vdbi::trianglesCross(t(0, 1, 2), t(0, 4, 7)));
    EXPECT_FALSE(vdbi::trianglesCross(t(0, 1, 2), t(0, 3, 11)));
    // Sharing a corner: the other's opposite edge pierces it, or passes by.
    EXPECT_TRUE(vdbi::trianglesCross(t(0, 1, 2), t(0, 8, 9)));
    EXPECT_FALSE(vdbi::trianglesCross(t(0, 1, 2), t(0, 5, 6)));
    // Sharing nothing: one plane overlapping (one inside the other), piercing, apart.
    EXPECT_TRUE(vdbi::trianglesCross(t(0, 1, 7), t(4, 2, 12)));
    EXPECT_TRUE(vdbi::trianglesCross(t(0, 1, 2), t(10, 5, 6)));
    EXPECT_FALSE(vdbi::trianglesCross(t(0, 1, 3), t(5, 6, 7)));
    // The same triangle twice.
    EXPECT_TRUE(vdbi::trianglesCross(t(0, 1, 2), t(1, 2, 0)));
}

TEST_F(TestTriangleCrossing, testAgreesWithIndependentCheck)
{
    // Random pairs sharing 0, 1 or 2 corners, half of them in one plane: the answer equals the test support's, but for folds by more than 175 degrees that the
    // support calls apart because they are not exactly flat.
    std::mt19937 rng(20261202);
    std::uniform_real_distribution<double> coordinate(-3.0, 3.0);
    std::size_t crossing = 0, apart = 0, tolerated = 0;
    for (int trial = 0; trial < 60000; ++trial) {
        const bool flat = trial % 2 == 0;
        const int shared = trial / 2 % 3;
        const auto [points, s, t] = randomPair(shared, flat, [&] { return coordinate(rng); });
        const CornerTriangle cs = corner(points, s), ct = corner(points, t);
        if (cs.normal.sqrnorm() == 0.0 || ct.normal.sqrnorm() == 0.0) continue;   // degenerate
        const bool expected = vdbi_test::trianglesIntersect(points, s, t);
        const bool found = vdbi::trianglesCross(cs, ct);
        if (found != expected && shared == 2 && found && turnDegrees(cs, ct) > 175.0) {
            ++tolerated;
            continue;
        }
        ASSERT_EQ(found, expected) << "trial " << trial << ", " << shared << " shared, "
                                   << (flat ? "flat" : "not flat");
        ++(found ? crossing : apart);
    }
    // Both answers are common (a test that cannot fail would not show it).
    EXPECT_GT(crossing, 5000u);
    EXPECT_GT(apart, 5000u);
    EXPECT_LT(tolerated, 1000u);   // about 2 % of the pairs sharing an edge
}

TEST_F(TestTriangleCrossing, testTouchAgreesWithIndependentCheck)
{
    // Random pairs on a coarse integer lattice, so that corners land on the other triangle's
    // edges and planes and edges run along each other: the independent check counts touching
    // as meeting, and so must trianglesTouch(); trianglesCross() must not.
    std::mt19937 rng(20261203);
    std::uniform_int_distribution<int> coordinate(-2, 2);
    std::size_t touching = 0, crossing = 0, apart = 0, tolerated = 0;
    for (int trial = 0; trial < 60000; ++trial) {
        const bool flat = trial % 2 == 0;
        const int shared = trial / 2 % 3;
        const auto [points, s, t] =
            randomPair(shared, flat, [&] { return double(coordinate(rng)); });
        const CornerTriangle cs = corner(points, s), ct = corner(points, t);
        if (cs.normal.sqrnorm() == 0.0 || ct.normal.sqrnorm() == 0.0) continue;   // degenerate
        const bool expected = vdbi_test::trianglesIntersect(points, s, t);
        const bool found = vdbi::trianglesTouch(cs, ct);
        const bool crosses = vdbi::trianglesCross(cs, ct);
        if (found != expected && shared == 2 && found && turnDegrees(cs, ct) > 175.0) {
            ++tolerated;
            continue;
        }
        ASSERT_EQ(found, expected) << "trial " << trial << ", " << shared << " shared, "
                                   << (flat ? "flat" : "not flat");
        ASSERT_TRUE(found || !crosses) << "trial " << trial;
        ++(crosses ? crossing : found ? touching : apart);
    }
    // Touching without crossing is common here, as are the other answers.
    EXPECT_GT(touching, 2000u);
    EXPECT_GT(crossing, 2000u);
    EXPECT_GT(apart, 2000u);
    EXPECT_LT(tolerated, 1000u);
}

// trianglesMeet() answers the same in either order. Each test takes the first triangle's
// plane, and a nearly coplanar pair was decided differently: separation and the flips then
// disagreed on which pairs meet. This pair from monu1 at 4 voxels lies in y = 10.5 to
// rounding, side by side, sharing a corner, their lower edges on one line.
TEST_F(TestTriangleCrossing, testMeetIsSymmetric)
{
    const vdbi::PointArray points = {
        {39.5, 10.500000000000002, 2.3633507177842565},
        {41.0, 10.5, 3.9316753588921283},
        {43.500000000000007, 10.500000000000002, 2.3633507177842565},
        {46.0, 10.5, 3.9316753588921283},
        {47.5, 10.500000000000002, 2.3633507177842565}};
    const openvdb::Vec3I s(0, 1, 2), t(3, 4, 2);
    EXPECT_EQ(vdbi::trianglesMeet(points, s, t), vdbi::trianglesMeet(points, t, s));
    const openvdb::Vec3I sTurned(1, 2, 0), tTurned(2, 3, 4);
    EXPECT_EQ(vdbi::trianglesMeet(points, sTurned, tTurned),
              vdbi::trianglesMeet(points, tTurned, sTurned));
}

TEST_F(TestTriangleCrossing, testFindMeetingPairs)
{
    // A closed tetrahedron (triangles 0-3) shares edges and corners only, and triangle 4 lies
    // far away: no pair. Triangle 5, in the plane z = 0.25, cuts through the tetrahedron.
    vdbi::InterfaceMesh mesh;
    mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1},
                   {5, 5, 5}, {6, 5, 5}, {5, 6, 5},
                   {-1, -1, 0.25}, {2, -1, 0.25}, {-1, 2, 0.25}};
    mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {4, 5, 6}};
    EXPECT_TRUE(vdbi::findMeetingPairs(mesh, 1.0, false).empty());
    mesh.triangles.emplace_back(7, 8, 9);
    // It crosses the three side faces and misses the base (z = 0).
    const vdbi::TrianglePairs expected = {{1, 5}, {2, 5}, {3, 5}};
    EXPECT_EQ(vdbi::findMeetingPairs(mesh, 1.0, false), expected);
    EXPECT_EQ(vdbi::findMeetingPairs(mesh, 0.3, true), expected); // other cells, threads

    // Seeded random triangles: the grid finds exactly the pairs that testing every pair
    // finds, for any cell size.
    std::mt19937 rng(20261206);
    std::uniform_real_distribution<double> where(0.0, 6.0), offset(-0.8, 0.8);
    vdbi::InterfaceMesh cloud;
    for (int t = 0; t < 300; ++t) {
        const openvdb::Vec3d c(where(rng), where(rng), where(rng));
        const auto first = std::uint32_t(cloud.points.size());
        for (int k = 0; k < 3; ++k) {
            cloud.points.push_back(c + openvdb::Vec3d(offset(rng), offset(rng), offset(rng)));
        }
        cloud.triangles.emplace_back(first, first + 1, first + 2);
    }
    vdbi::TrianglePairs all;
    for (std::uint32_t f = 0; f < cloud.triangles.size(); ++f) {
        for (std::uint32_t g = f + 1; g < cloud.triangles.size(); ++g) {
            if (vdbi::trianglesMeet(cloud.points, cloud.triangles[f], cloud.triangles[g])) {
                all.emplace_back(f, g);
            }
        }
    }
    ASSERT_GT(all.size(), 10u);
    for (const double cell : {0.25, 1.0, 4.0}) {
        EXPECT_EQ(vdbi::findMeetingPairs(cloud, cell, true), all) << "cells " << cell;
    }
}

TEST_F(TestTriangleCrossing, testCountCrossings)
{
    // A flat fan has none; lifting every other corner far above the plane folds nothing
    // either; a fan winding twice around its centre crosses itself.
    EXPECT_EQ(vdbi::countCrossings(makeFan(6, 1).triangles, {}), 0);
    EXPECT_EQ(vdbi::countCrossings(makeFan(6, 1, 0.5).triangles, {}), 0);
    const Fan twice = makeFan(7, 2);
    EXPECT_GT(vdbi::countCrossings(twice.triangles, {}), 0);
    // Only pairs with a suspect triangle are counted, each once.
    std::vector<char> none(twice.triangles.size(), 0), all(twice.triangles.size(), 1);
    EXPECT_EQ(vdbi::countCrossings(twice.triangles, {}, &none), 0);
    EXPECT_EQ(vdbi::countCrossings(twice.triangles, {}, &all),
              vdbi::countCrossings(twice.triangles, {}));
}

TEST_F(TestTriangleCrossing, testLooksUnfolded)
{
    std::vector<char> suspect;
    const std::vector<CornerTriangle> none;
    const double cos120 = std::cos(120.0 * M_PI / 180.0);
    // Flat and gently lifted fans look unfolded.
    EXPECT_TRUE(vdbi::looksUnfolded(makeFan(6, 1).triangles, none, {}, 0, cos120, suspect));
    EXPECT_TRUE(vdbi::looksUnfolded(makeFan(8, 1, 0.3).triangles, none, {}, 0, cos120,
                                    suspect));
    // An open fan (a boundary vertex) of under a full turn too; over a full turn it does not.
    EXPECT_TRUE(vdbi::looksUnfolded(makeFan(6, 1, 0.0, false).triangles, none, {}, 0, cos120,
                                    suspect));
    EXPECT_FALSE(vdbi::looksUnfolded(makeFan(9, 2, 0.0, false).triangles, none, {}, 0, cos120,
                                     suspect));
    // A fan going around twice, every turn between neighbours zero: all suspect.
    const Fan twice = makeFan(7, 2);
    EXPECT_FALSE(vdbi::looksUnfolded(twice.triangles, none, {}, 0, cos120, suspect));
    EXPECT_EQ(std::count(suspect.begin(), suspect.end(), 1), 7);
    // A neighbour across an outer edge folded back onto a triangle makes that one suspect.
    Fan flat = makeFan(6, 1);
    const CornerTriangle& t = flat.triangles[2];
    const Point inside = (t.p[0] + t.p[1] + t.p[2]) / 3.0;
    const std::vector<CornerTriangle> outer = {
        CornerTriangle(t.p[2], t.p[1], inside, t.id[2], t.id[1], 99)};
    EXPECT_FALSE(vdbi::looksUnfolded(flat.triangles, outer, {2}, 0, cos120, suspect));
    EXPECT_EQ(suspect, std::vector<char>({0, 0, 1, 0, 0, 0}));
}

TEST_F(TestTriangleCrossing, testEmbeddedFans)
{
    // Random fans around point 0, their triangles in random order: corners at growing angles
    // over half a turn to two and a half, at random radii and heights. Whenever
    // looksUnfolded() calls one embedded, the test support finds no two of its triangles
    // crossing, and counting only the pairs sharing an edge gives the full count.
    std::mt19937 rng(20261203);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const std::vector<CornerTriangle> none;
    const double cos120 = std::cos(120.0 * M_PI / 180.0);
    int embeddedFans = 0, crossingFans = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const int count = 3 + trial % 10;
        const bool closed = trial % 3 != 0;
        const double total = 2.0 * M_PI * (0.5 + 2.0 * unit(rng));
        const double height = trial % 4 == 0 ? 0.0 : 1.5 * unit(rng);
        Fan fan;
        fan.points.push_back(openvdb::Vec3d(0.0));
        for (int k = 0; k < count; ++k) {
            const double angle = total * (k + 0.8 * unit(rng)) / count;
            const double radius = 0.5 + unit(rng);
            fan.points.push_back(openvdb::Vec3d(radius * std::cos(angle),
                                                radius * std::sin(angle),
                                                height * (2.0 * unit(rng) - 1.0)));
        }
        for (int k = 0; k < (closed ? count : count - 1); ++k) {
            const unsigned a = unsigned(k + 1), b = unsigned((k + 1) % count + 1);
            fan.triangles.push_back(corner(fan.points, openvdb::Vec3I(0, a, b)));
        }
        std::shuffle(fan.triangles.begin(), fan.triangles.end(), rng);
        std::vector<char> suspect;
        bool embedded = false;
        vdbi::looksUnfolded(fan.triangles, none, {}, 0, cos120, suspect, &embedded);
        const std::vector<char> all(fan.triangles.size(), 1);
        const int crossings = vdbi::countCrossings(fan.triangles, {}, &all);
        crossingFans += crossings > 0;
        if (!embedded) continue;
        ++embeddedFans;
        EXPECT_EQ(vdbi::countCrossings(fan.triangles, {}, &all, true), crossings);
        for (const CornerTriangle& s : fan.triangles) {
            for (const CornerTriangle& t : fan.triangles) {
                const openvdb::Vec3I is(s.id[0], s.id[1], s.id[2]), it(t.id[0], t.id[1], t.id[2]);
                if (&s == &t || s.hasCorner(t.id[1]) || s.hasCorner(t.id[2])) continue;
                ASSERT_FALSE(vdbi_test::trianglesIntersect(fan.points, is, it))
                    << "trial " << trial;
            }
        }
    }
    // Both kinds are common; and the shortcut is wrong for fans that are not embedded.
    EXPECT_GT(embeddedFans, 500);
    EXPECT_GT(crossingFans, 500);
    const Fan twice = makeFan(7, 2);
    const std::vector<char> all(twice.triangles.size(), 1);
    EXPECT_LT(vdbi::countCrossings(twice.triangles, {}, &all, true),
              vdbi::countCrossings(twice.triangles, {}, &all));
}
