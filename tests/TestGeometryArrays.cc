// SPDX-License-Identifier: Apache-2.0
// The arrays the Houdini SOP copies into its geometry, and the SOP's string parameters: what
// the SOP computes is tested here, without Houdini.

#include <vdbi/GeometryArrays.h>

#include <openvdb/Exceptions.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

class TestGeometryArrays : public ::testing::Test {};

namespace {

/// Two patches, sorted by (a, b): (-3, 5) with triangle 0 and (1, 2) with triangles 1 and 2.
vdbi::InterfaceMesh
twoPatchMesh()
{
    vdbi::InterfaceMesh mesh;
    mesh.points = {{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.5, 0.25, -2.0}};
    mesh.triangles = {{0, 1, 2}, {1, 3, 2}, {0, 3, 1}};
    mesh.patches.resize(2);
    mesh.patches[0].a = -3;
    mesh.patches[0].b = 5;
    mesh.patches[0].firstTriangle = 0;
    mesh.patches[0].triangleCount = 1;
    mesh.patches[1].a = 1;
    mesh.patches[1].b = 2;
    mesh.patches[1].firstTriangle = 1;
    mesh.patches[1].triangleCount = 2;
    return mesh;
}

/// The message of the openvdb::ValueError thrown by @a f ("" if none).
template<typename F>
std::string
valueErrorOf(F&& f)
{
    try {
        f();
    } catch (const openvdb::ValueError& e) {
        return e.what();
    }
    return "";
}

bool
contains(const std::string& text, const std::string& part)
{
    return text.find(part) != std::string::npos;
}

} // namespace

TEST_F(TestGeometryArrays, testTwoPatchMesh)
{
    const vdbi::GeometryArrays arrays = vdbi::makeGeometryArrays(twoPatchMesh());

    EXPECT_EQ(arrays.pointCount(), 4u);
    EXPECT_EQ(arrays.primitiveCount(), 3u);
    EXPECT_EQ(arrays.points, (std::vector<float>{
        0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.5f, 0.25f, -2.f}));
    EXPECT_EQ(arrays.vertices, (std::vector<int>{0, 1, 2, 1, 3, 2, 0, 3, 1}));
    EXPECT_EQ(arrays.polyCounts, (std::vector<int>{3, 3, 3}));
    EXPECT_EQ(arrays.labelA, (std::vector<vdbi::Label>{-3, 1, 1}));
    EXPECT_EQ(arrays.labelB, (std::vector<vdbi::Label>{5, 2, 2}));
    EXPECT_EQ(arrays.patch, (std::vector<int>{0, 1, 1}));
    EXPECT_EQ(arrays.patchNames, (std::vector<std::string>{"patch_m3_5", "patch_1_2"}));
}

TEST_F(TestGeometryArrays, testEmptyMesh)
{
    const vdbi::GeometryArrays arrays = vdbi::makeGeometryArrays(vdbi::InterfaceMesh());
    EXPECT_TRUE(arrays.points.empty());
    EXPECT_TRUE(arrays.vertices.empty());
    EXPECT_TRUE(arrays.polyCounts.empty());
    EXPECT_TRUE(arrays.labelA.empty());
    EXPECT_TRUE(arrays.labelB.empty());
    EXPECT_TRUE(arrays.patch.empty());
    EXPECT_TRUE(arrays.patchNames.empty());
}

TEST_F(TestGeometryArrays, testMalformedMeshThrows)
{
    vdbi::InterfaceMesh badIndex = twoPatchMesh();
    badIndex.triangles[2][1] = 4;
    EXPECT_TRUE(contains(valueErrorOf([&] { vdbi::makeGeometryArrays(badIndex); }),
        "triangle 2 refers to point 4 of 4"));

    vdbi::InterfaceMesh badPatch = twoPatchMesh();
    badPatch.patches[1].triangleCount = 3;
    EXPECT_TRUE(contains(valueErrorOf([&] { vdbi::makeGeometryArrays(badPatch); }),
        "patch 1 (1, 2)"));

    vdbi::InterfaceMesh uncovered = twoPatchMesh();
    uncovered.patches[1].triangleCount = 1;
    EXPECT_TRUE(contains(valueErrorOf([&] { vdbi::makeGeometryArrays(uncovered); }),
        "triangle 2 belongs to no patch"));
}

TEST_F(TestGeometryArrays, testPatchNames)
{
    EXPECT_EQ(vdbi::patchName(0, 1), "patch_0_1");
    EXPECT_EQ(vdbi::patchName(12, 345), "patch_12_345");
    EXPECT_EQ(vdbi::patchName(-3, 5), "patch_m3_5");
    EXPECT_EQ(vdbi::patchName(-7, -2), "patch_m7_m2");
    const vdbi::Label lowest = std::numeric_limits<vdbi::Label>::min();
    const vdbi::Label highest = std::numeric_limits<vdbi::Label>::max();
    EXPECT_EQ(vdbi::patchName(lowest, highest), "patch_m2147483648_2147483647");
    // The "m" spelling keeps names of distinct pairs distinct.
    EXPECT_NE(vdbi::patchName(-1, 2), vdbi::patchName(1, 2));
}

TEST_F(TestGeometryArrays, testParseConstraints)
{
    const std::vector<vdbi::SeparationConstraint> c = vdbi::parseConstraints("1 2 3; 4 5 6");
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(c[0].a, 1);
    EXPECT_EQ(c[0].b, 2);
    EXPECT_EQ(c[0].separator, 3);
    EXPECT_EQ(c[1].a, 4);
    EXPECT_EQ(c[1].b, 5);
    EXPECT_EQ(c[1].separator, 6);

    // Commas, tabs, line breaks, signs, empty constraints.
    const auto d = vdbi::parseConstraints(" -1,\t2 , +0 ;;\n 7 8 9;");
    ASSERT_EQ(d.size(), 2u);
    EXPECT_EQ(d[0].a, -1);
    EXPECT_EQ(d[0].b, 2);
    EXPECT_EQ(d[0].separator, 0);
    EXPECT_EQ(d[1].a, 7);
    EXPECT_EQ(d[1].separator, 9);

    EXPECT_TRUE(vdbi::parseConstraints("").empty());
    EXPECT_TRUE(vdbi::parseConstraints("  ;  ").empty());
}

TEST_F(TestGeometryArrays, testParseConstraintErrors)
{
    std::string message = valueErrorOf([] { vdbi::parseConstraints("1 2 3; 4 x 6"); });
    EXPECT_TRUE(contains(message, "'x' is not an integer label")) << message;
    EXPECT_TRUE(contains(message, "\"4 x 6\"")) << message;

    message = valueErrorOf([] { vdbi::parseConstraints("1 2"); });
    EXPECT_TRUE(contains(message, "constraint \"1 2\" has 2 labels")) << message;

    message = valueErrorOf([] { vdbi::parseConstraints("1 2 3 4"); });
    EXPECT_TRUE(contains(message, "has 4 labels")) << message;

    message = valueErrorOf([] { vdbi::parseConstraints("1 2 99999999999"); });
    EXPECT_TRUE(contains(message, "'99999999999' is out of the range")) << message;

    message = valueErrorOf([] { vdbi::parseConstraints("1 2 3.5"); });
    EXPECT_TRUE(contains(message, "'3.5'")) << message;

    message = valueErrorOf([] { vdbi::parseConstraints("1 2 +-3"); });
    EXPECT_TRUE(contains(message, "'+-3'")) << message;
}

TEST_F(TestGeometryArrays, testParseLabels)
{
    EXPECT_EQ(vdbi::parseLabels("3 1 2"), (std::vector<vdbi::Label>{3, 1, 2}));
    EXPECT_EQ(vdbi::parseLabels("3, 1,2"), (std::vector<vdbi::Label>{3, 1, 2}));
    EXPECT_EQ(vdbi::parseLabels(" -4\t+5\n"), (std::vector<vdbi::Label>{-4, 5}));
    EXPECT_TRUE(vdbi::parseLabels("").empty());
    EXPECT_TRUE(vdbi::parseLabels(" , ").empty());

    std::string message = valueErrorOf([] { vdbi::parseLabels("1 two 3"); });
    EXPECT_TRUE(contains(message, "'two' is not an integer label")) << message;
    message = valueErrorOf([] { vdbi::parseLabels("1;2"); });
    EXPECT_TRUE(contains(message, "'1;2'")) << message;
    message = valueErrorOf([] { vdbi::parseLabels("-2147483649"); });
    EXPECT_TRUE(contains(message, "'-2147483649' is out of the range")) << message;
    EXPECT_EQ(vdbi::parseLabels("-2147483648"),
        (std::vector<vdbi::Label>{std::numeric_limits<vdbi::Label>::min()}));
}
