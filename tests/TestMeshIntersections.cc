// SPDX-License-Identifier: Apache-2.0
// The geometric checkers of tests/support/MeshIntersections: they must find what is wrong
// (crossing, touching, folded and overlapping triangles; a mesh too far away), and accept
// what is right (triangles meeting only at shared corners and edges), or the remeshing tests
// built on them prove nothing.

#include "support/MeshIntersections.h"

#include <vdbi/Interfaces.h>
#include <vdbi/LabelVolumeReader.h>

#include "support/RawExtraction.h"
#include "support/TestData.h"

#include <gtest/gtest.h>

#include <openvdb/openvdb.h>

#include <cmath>
#include <string>
#include <vector>

using openvdb::Vec3d;
using openvdb::Vec3I;

class TestMeshIntersections : public ::testing::Test
{
protected:
    static void SetUpTestSuite() { openvdb::initialize(); }
};

namespace {

/// A mesh of one patch per triangle group: @a groups[i] triangles go to patch (0, i + 1).
vdbi::InterfaceMesh
meshOf(vdbi::PointArray points, vdbi::TriangleArray triangles,
       const std::vector<std::size_t>& groups)
{
    vdbi::InterfaceMesh mesh;
    mesh.points = std::move(points);
    mesh.triangles = std::move(triangles);
    std::size_t first = 0;
    for (std::size_t i = 0; i < groups.size(); ++i) {
        vdbi::InterfacePatch patch;
        patch.a = 0;
        patch.b = vdbi::Label(i + 1);
        patch.firstTriangle = first;
        patch.triangleCount = groups[i];
        first += groups[i];
        mesh.patches.push_back(patch);
    }
    return mesh;
}

bool
intersect(const vdbi::PointArray& points, const Vec3I& s, const Vec3I& t)
{
    // The answer may not depend on the order of the triangles or of their corners.
    const bool result = vdbi_test::trianglesIntersect(points, s, t);
    EXPECT_EQ(result, vdbi_test::trianglesIntersect(points, t, s));
    EXPECT_EQ(result, vdbi_test::trianglesIntersect(points, Vec3I(s[1], s[2], s[0]), t));
    EXPECT_EQ(result, vdbi_test::trianglesIntersect(points, s, Vec3I(t[2], t[0], t[1])));
    return result;
}

} // namespace

TEST_F(TestMeshIntersections, testDisjointTriangles)
{
    const vdbi::PointArray p = {
        {0, 0, 0}, {2, 0, 0}, {0, 2, 0},           // s in z = 0
        {0.5, 0.5, -1}, {0.5, 0.5, 1}, {3, 3, 0},   // t pierces s at (0.5, 0.5, 0)
        {0.5, 0.5, 0.1}, {0.5, 0.5, 1},             // t' above s
        {2, 0, 0.0}, {1, 1, 0}, {3, 3, 3},          // (1, 1, 0) lies on s's edge
        {0.2, 0.2, 0}, {3, 0.2, 0}, {0.2, 3, 0}};   // coplanar, overlapping
    EXPECT_TRUE(intersect(p, Vec3I(0, 1, 2), Vec3I(3, 4, 5)));
    EXPECT_FALSE(intersect(p, Vec3I(0, 1, 2), Vec3I(6, 7, 5)));
    // Touching without a shared corner counts: a point on an edge, coplanar overlap.
    EXPECT_TRUE(intersect(p, Vec3I(0, 2, 1), Vec3I(9, 10, 7)));
    EXPECT_TRUE(intersect(p, Vec3I(0, 1, 2), Vec3I(11, 12, 13)));
    // Coplanar and apart.
    const vdbi::PointArray q = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 2, 0}, {3, 2, 0}, {2, 3, 0}};
    EXPECT_FALSE(intersect(q, Vec3I(0, 1, 2), Vec3I(3, 4, 5)));
}

// Triangles of flat remeshed patches (monu16 and monu1 at one voxel): their corners are in
// one plane up to rounding, so the volumes of four of them have any sign. The checker took
// the first pair, which do not even share a bounding box, for crossing, and a version that
// tested the remaining volumes more loosely the second one: both are apart.
TEST_F(TestMeshIntersections, testNearlyCoplanar)
{
    const vdbi::PointArray p = {
        {96.843365005307703, 26.567028527655978, 83.981178276115656},
        {96.019449764108856, 26.533668388499567, 83.378895117403772},
        {96.843365005307703, 26.567028527655978, 82.981178276115699},
        {96.019449764108842, 26.533668388499567, 84.378895117403772},
        {96.843365005307703, 26.567028527655978, 84.981178276115685},
        {96.019449764108856, 26.533668388499567, 85.378895117403758}};
    EXPECT_FALSE(intersect(p, Vec3I(0, 1, 2), Vec3I(3, 4, 5)));
    vdbi::PointArray q = {
        {72.419710747860918, 68.437501048506022, -0.50000000006619305},
        {73.455289250738701, 67.937498942017669, -0.50000000003549994},
        {73.455289251767056, 68.937498905464281, -0.49999999920777966},
        {71.455289251066333, 67.937498942900234, -0.50000000004902634},
        {71.455289251275431, 66.93749894268413, -0.50000000001010747},
        {72.419710748527706, 67.437501060393203, -0.50000000002090328}};
    EXPECT_FALSE(intersect(q, Vec3I(0, 1, 2), Vec3I(3, 4, 5)));
    // The second triangle moved within the plane onto the first: they overlap.
    for (int i = 3; i < 6; ++i) q[i] += Vec3d(1.2, 1.0, 0.0);
    EXPECT_TRUE(intersect(q, Vec3I(0, 1, 2), Vec3I(3, 4, 5)));
}

TEST_F(TestMeshIntersections, testSharedCorner)
{
    const vdbi::PointArray p = {
        {0, 0, 0}, {2, 0, 0}, {0, 2, 0},       // s in z = 0 at corner 0
        {1, 1, 0}, {1, 1, 1},                  // t: along the diagonal into s, and up
        {-1, 0, 0.5}, {0, -1, 0.5},            // t': away from s
        {2, 1, 0}, {-1, 3, 0},                 // coplanar overlap at corner 0
        {-2, 0.5, 0}, {-0.5, -2, 0}};          // coplanar, apart
    EXPECT_TRUE(intersect(p, Vec3I(0, 1, 2), Vec3I(0, 3, 4)));
    EXPECT_FALSE(intersect(p, Vec3I(0, 1, 2), Vec3I(0, 5, 6)));
    EXPECT_TRUE(intersect(p, Vec3I(0, 1, 2), Vec3I(0, 7, 8)));
    EXPECT_FALSE(intersect(p, Vec3I(0, 1, 2), Vec3I(0, 9, 10)));
    // Piercing away from the shared corner: the opposite edge of t crosses s.
    const vdbi::PointArray q = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {1, 0.5, -1}, {0.5, 1, 1}};
    EXPECT_TRUE(intersect(q, Vec3I(0, 1, 2), Vec3I(0, 3, 4)));
}

TEST_F(TestMeshIntersections, testSharedEdge)
{
    const vdbi::PointArray p = {
        {0, 0, 0}, {1, 0, 0},       // the edge
        {0.5, 1, 0},                // s
        {0.5, -1, 0},               // t on the other side: a flat pair
        {0.3, 2, 0},                // t folded onto s
        {0.5, 1, 1}};               // t bent up
    EXPECT_FALSE(intersect(p, Vec3I(0, 1, 2), Vec3I(1, 0, 3)));
    EXPECT_TRUE(intersect(p, Vec3I(0, 1, 2), Vec3I(1, 0, 4)));
    EXPECT_FALSE(intersect(p, Vec3I(0, 1, 2), Vec3I(1, 0, 5)));
    // The same three corners twice.
    EXPECT_TRUE(intersect(p, Vec3I(0, 1, 2), Vec3I(2, 1, 0)));
}

// A flat fan around a vertex, then the same with one triangle folded over its neighbour,
// then two patches, one crossing the other.
TEST_F(TestMeshIntersections, testMeshes)
{
    vdbi::PointArray points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
    const vdbi::TriangleArray fan = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
    EXPECT_TRUE(vdbi_test::findSelfIntersections(meshOf(points, fan, {4}), 0.5).empty());
    points[2] = Vec3d(-0.5, -0.3, 0.0);   // (0, 1, 2) now lies on (0, 4, 1)
    const auto folded = vdbi_test::findSelfIntersections(meshOf(points, fan, {4}), 0.5);
    EXPECT_FALSE(folded.empty());
    points[2] = Vec3d(-0.5, -0.3, 0.3);   // lifted: (0, 1, 2) and (0, 4, 1) meet at their edge
    EXPECT_TRUE(vdbi_test::findSelfIntersections(meshOf(points, {fan[0], fan[3]}, {2}), 0.5)
                    .empty());

    const vdbi::PointArray two = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {4, 4, 0},
                                    {1, 1, -1}, {2, 1, 1}, {1, 2, 1}};
    const vdbi::TriangleArray tris = {{0, 1, 2}, {1, 3, 2}, {4, 5, 6}};
    const auto mesh = meshOf(two, tris, {2, 1});
    const auto found = vdbi_test::findSelfIntersections(mesh, 0.7);
    ASSERT_EQ(found.size(), 1u);
    EXPECT_EQ(found[0].first, 0u);
    EXPECT_EQ(found[0].second, 2u);
    const std::string text = vdbi_test::describeIntersections(mesh, found);
    EXPECT_NE(text.find("(0, 2)"), std::string::npos) << text;
    EXPECT_EQ(vdbi_test::describeIntersections(mesh, {}), "");
}

// The raw extraction (voxel faces, fine faces around the repaired places) meets itself only
// at shared corners and edges: exact coordinates, many coplanar neighbours.
TEST_F(TestMeshIntersections, testRawExtraction)
{
    const auto grid = vdbi::readLabelVolume(vdbi_test::dataPath("chr_knight.vox"));
    const auto mesh = vdbi_test::extractRaw(*grid).mesh;
    const auto found = vdbi_test::findSelfIntersections(mesh, 1.0);
    EXPECT_TRUE(found.empty()) << vdbi_test::describeIntersections(mesh, found);
}

// Closeness of a square to itself moved by known amounts, in voxels of 1 x 1 x 2.
TEST_F(TestMeshIntersections, testCloseness)
{
    const vdbi::TriangleArray tris = {{0, 1, 2}, {1, 3, 2}};
    auto square = [&](double z) {
        return meshOf({{0, 0, z}, {4, 0, z}, {0, 4, z}, {4, 4, z}}, tris, {2});
    };
    const Vec3d voxel(1, 1, 2);
    const auto raw = square(0.0);
    auto c = vdbi_test::measureCloseness(raw, square(1.0), voxel);
    EXPECT_NEAR(c.vertexToRaw, 0.5, 1e-12);
    EXPECT_NEAR(c.rawToOutput, 0.5, 1e-12);
    EXPECT_NEAR(c.faceCentreToOutput, 0.5, 1e-12);
    c = vdbi_test::measureCloseness(raw, square(7.0), voxel);   // 3.5 voxels
    EXPECT_GT(c.vertexToRaw, 2.0);
    EXPECT_GT(c.rawToOutput, 2.0);
    EXPECT_GT(c.faceCentreToOutput, 2.0);
    // A smaller square inside: its vertices are on the raw one, but the centroid (8/3, 8/3)
    // of the raw triangle (1, 3, 2) is far from its corner (1.5, 1.5).
    const auto inner = meshOf({{0.5, 0.5, 0}, {1.5, 0.5, 0}, {0.5, 1.5, 0}, {1.5, 1.5, 0}},
                              tris, {2});
    c = vdbi_test::measureCloseness(raw, inner, voxel);
    EXPECT_NEAR(c.vertexToRaw, 0.0, 1e-12);
    EXPECT_NEAR(c.rawToOutput, std::sqrt(2.0) * (8.0 / 3.0 - 1.5), 1e-12);
    // The face centre (2, 2) lies sqrt(2) * 0.5 from that corner.
    EXPECT_NEAR(c.faceCentreToOutput, std::sqrt(0.5), 1e-12);
}
