// SPDX-License-Identifier: Apache-2.0
/// @file TestRefinedChecker.cc
/// @brief The independent manifold checker and the reference repair, and the proof that the
/// checker can fail: the negative controls of ALGORITHM.md §6 on all 2x2x2 block classes.

#include "support/BlockEnumeration.h"
#include "support/HandMadeGrids.h"
#include "support/ReferenceFattening.h"
#include "support/RefinedChecker.h"

#include <openvdb/openvdb.h>

#include <gtest/gtest.h>

#include <array>
#include <cstdint>

using openvdb::Coord;
using vdbi::Label;

class TestRefinedChecker : public ::testing::Test
{
protected:
    void SetUp() override { openvdb::initialize(); }
};

namespace {

/// §2 read literally on one label's 2x2x2 mask: an edge at p with two diagonal voxels of L
/// and two others, or two antipodal voxels of L (or six with two antipodal others).
bool
patternRulesSayCritical(std::uint8_t mask)
{
    auto in = [mask](int dx, int dy, int dz) { return (mask >> (dx + 2 * dy + 4 * dz)) & 1; };
    for (int a = 0; a < 3; ++a) {
        for (int side = 0; side < 2; ++side) {
            // The 4 voxels around the grid edge leaving p along +-axis a, in cyclic order.
            int q[4];
            const int order[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int k = 0; k < 4; ++k) {
                int d[3];
                d[a] = side;
                d[(a + 1) % 3] = order[k][0];
                d[(a + 2) % 3] = order[k][1];
                q[k] = in(d[0], d[1], d[2]);
            }
            if (q[0] == q[2] && q[1] == q[3] && q[0] != q[1]) return true;
        }
    }
    int count = 0;
    for (int i = 0; i < 8; ++i) count += (mask >> i) & 1;
    for (int i = 0; i < 4; ++i) {
        const unsigned pair = (1u << i) | (1u << (7 - i));
        if ((count == 2 && mask == pair) || (count == 6 && (0xFFu & ~unsigned(mask)) == pair)) {
            return true;
        }
    }
    return false;
}

/// Runs the reference with @a params on every 2x2x2 class; counts classes with a failure.
struct ControlResult
{
    std::size_t classes = 0;
    std::size_t failingClasses = 0;
    std::size_t failingLabellings = 0; // weighted by orbit size
    std::size_t disagreeWithRules = 0; // unfattened only: failure != has critical elements
    double maxDistance = 0, maxFarDistance = 0;
};

ControlResult
runControl(const vdbi_test::ReferenceParams& params, bool measureDistance)
{
    ControlResult out;
    vdbi_test::CheckOptions options;
    options.computeEuler = false;
    options.maxFailures = 1;
    vdbi_test::forEachBlockClass([&](std::size_t, const vdbi_test::BlockClass& c) {
        const auto grid = vdbi_test::blockGrid(c.labels);
        const vdbi_test::ReferenceRefined r = vdbi_test::referenceFattening(*grid, params);
        const vdbi_test::ManifoldReport report = r.check(options);
        ++out.classes;
        if (!report.ok()) {
            ++out.failingClasses;
            out.failingLabellings += c.orbitSize;
        }
        if (params.edgeK == 0 && params.vertexK == 0 && report.ok() != r.elements.empty()) {
            ++out.disagreeWithRules;
        }
        if (measureDistance) {
            const vdbi_test::DistanceReport d = r.distance();
            out.maxDistance = std::max(out.maxDistance, d.maxDistance);
            out.maxFarDistance = std::max(out.maxFarDistance, d.maxFarDistance);
        }
    });
    return out;
}

vdbi_test::ReferenceParams
params(int s, int edgeK, int vertexK)
{
    vdbi_test::ReferenceParams p;
    p.s = s;
    p.edgeK = edgeK;
    p.vertexK = vertexK;
    return p;
}

} // namespace

TEST_F(TestRefinedChecker, testLinkCycleTestAgreesWithPatternRules)
{
    // The checker decides manifoldness by the link of a point (one cycle of boundary faces),
    // the §2 rules by patterns. They describe the same property, so they must agree on every
    // one of the 256 masks; and a label's boundary is its complement's boundary, so a mask and
    // its complement must get the same answer.
    int nonManifold = 0;
    for (int m = 0; m < 256; ++m) {
        const auto mask = std::uint8_t(m);
        EXPECT_EQ(vdbi_test::isManifoldMask(mask), !patternRulesSayCritical(mask)) << "mask " << m;
        EXPECT_EQ(vdbi_test::isManifoldMask(mask), vdbi_test::isManifoldMask(std::uint8_t(~m)));
        EXPECT_EQ(vdbi_test::boundaryEulerTimes4(mask),
                  vdbi_test::boundaryEulerTimes4(std::uint8_t(~m)));
        nonManifold += vdbi_test::isManifoldMask(mask) ? 0 : 1;
    }
    // Both definitions reject exactly half of the masks (64 complementary pairs), so neither
    // side of the equality above is trivial.
    EXPECT_EQ(nonManifold, 128);
    // Empty, full, a flat half and a single corner voxel (a 3-cycle: 4 - 2*3 + 3 = 1).
    EXPECT_TRUE(vdbi_test::isManifoldMask(0));
    EXPECT_TRUE(vdbi_test::isManifoldMask(0xFF));
    EXPECT_TRUE(vdbi_test::isManifoldMask(0x0F));
    EXPECT_EQ(vdbi_test::boundaryEulerTimes4(0x0F), 0);
    EXPECT_EQ(vdbi_test::boundaryEulerTimes4(0x01), 1);
    EXPECT_FALSE(vdbi_test::isManifoldMask(0x81)); // antipodal pair
    EXPECT_FALSE(vdbi_test::isManifoldMask(0x7E)); // six with antipodal others
    EXPECT_FALSE(vdbi_test::isManifoldMask(0x09)); // diagonal pair in one layer
}

TEST_F(TestRefinedChecker, testPointSetOfSingleVoxel)
{
    // Without subdivision the checker visits the 8 corners of the voxel and one point inside
    // every coarse edge leaving them: with s = 1 those are the corners' +x/+y/+z neighbours,
    // 8 + 12 = 20 distinct points.
    const auto grid = vdbi_test::singleVoxel();
    const auto none = openvdb::MaskGrid::create(false);
    EXPECT_EQ(vdbi_test::checkPoints(*grid, *none, 1)->activeVoxelCount(), 20);
    // With s = 5: 8 corners s*v plus 8 x 3 edge points s*v + e_a.
    EXPECT_EQ(vdbi_test::checkPoints(*grid, *none, 5)->activeVoxelCount(), 32);
    // A subdivided voxel adds the (s+1)^3 points of its closure.
    none->tree().setValueOn(Coord(0));
    EXPECT_EQ(vdbi_test::checkPoints(*grid, *none, 5)->activeVoxelCount(),
              216 + 32 - 8 - 3 * 4 /* corners and edge points inside the closure */);
}

TEST_F(TestRefinedChecker, testReferenceCriticalElementsOfHandMadeGrids)
{
    // The hand counts of HandMadeGrids.h, derived from §2 on paper, must be what the
    // reference's literal implementation of §2 finds.
    for (const auto& c : vdbi_test::handMadeCases()) {
        SCOPED_TRACE(c.name);
        const auto e = vdbi_test::referenceCriticalElements(*c.grid);
        EXPECT_EQ(e.edges.size(), c.criticalEdges);
        EXPECT_EQ(e.vertices.size(), c.criticalVertices);
        EXPECT_EQ(e.singularVertexCount(), c.singularVertices);
        for (const auto& x : e.edges) EXPECT_EQ(x.label, c.dominant);
        for (const auto& x : e.vertices) EXPECT_EQ(x.label, c.dominant);
    }
    // Where the critical elements are, exactly.
    const auto edge = vdbi_test::referenceCriticalElements(*vdbi_test::twoVoxelsSharingEdge());
    ASSERT_EQ(edge.edges.size(), 1u);
    EXPECT_EQ(edge.edges[0].origin, Coord(1, 1, 0));
    EXPECT_EQ(edge.edges[0].axis, 2);
    ASSERT_EQ(edge.vertices.size(), 2u);
    EXPECT_EQ(edge.vertices[0].point, Coord(1, 1, 0));
    EXPECT_EQ(edge.vertices[1].point, Coord(1, 1, 1));
    const auto vertex = vdbi_test::referenceCriticalElements(*vdbi_test::twoVoxelsSharingVertex());
    ASSERT_EQ(vertex.vertices.size(), 1u);
    EXPECT_EQ(vertex.vertices[0].point, Coord(1, 1, 1));
    EXPECT_TRUE(vertex.vertices[0].isSingular);
    // A priority order changes the dominant label, not the elements.
    const auto prio = vdbi_test::referenceCriticalElements(*vdbi_test::twoVoxelsSharingVertex(),
                                                           vdbi::LabelPriority({1}));
    ASSERT_EQ(prio.vertices.size(), 1u);
    EXPECT_EQ(prio.vertices[0].label, 1);
}

TEST_F(TestRefinedChecker, testCheckerFailsWithoutFattening)
{
    // Subdivision alone changes nothing: every critical element of the input must show up as
    // failing fine points. Each count is derived by hand: a critical edge fails at its s + 1
    // fine points for both labels that are diagonal around it (and only those); a singular
    // vertex fails at its one fine point for the two labels of the antipodal configuration.
    struct Expect { const char* name; openvdb::Int32Grid::Ptr grid; std::size_t failures; };
    const Expect cases[] = {
        {"twoVoxelsSharingEdge", vdbi_test::twoVoxelsSharingEdge(), 6 * 2},
        {"twoVoxelsSharingVertex", vdbi_test::twoVoxelsSharingVertex(), 2},
        {"antipodalPair2x2x2", vdbi_test::antipodalPair2x2x2(), 2},
        {"antipodalSix", vdbi_test::antipodalSix(), 2},
        {"checkerboard2x2", vdbi_test::checkerboard2x2(), 6 * 2},
        {"activeTileGrid", vdbi_test::activeTileGrid(), 6 * 1}, // only 0 is diagonal there
        {"singleVoxel", vdbi_test::singleVoxel(), 0},
        {"hollowShell", vdbi_test::hollowShell(), 0},
        {"torusRing", vdbi_test::torusRing(), 0},
        {"tJunction3", vdbi_test::tJunction3(), 0},
        {"corner4", vdbi_test::corner4(), 0},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        const auto r = vdbi_test::referenceFattening(*c.grid, params(5, 0, 0));
        const auto report = r.check();
        EXPECT_EQ(report.failureCount, c.failures) << report.summary();
        EXPECT_EQ(r.relabelled, 0u);
    }
    // The failures are where they must be: the shared vertex (5,5,5), labels 0 and 1.
    const auto r =
        vdbi_test::referenceFattening(*vdbi_test::twoVoxelsSharingVertex(), params(5, 0, 0));
    const auto report = r.check();
    ASSERT_EQ(report.failures.size(), 2u);
    EXPECT_EQ(report.failures[0].point, Coord(5, 5, 5));
    EXPECT_EQ(report.failures[0].label, 0);
    EXPECT_EQ(report.failures[1].label, 1);
    EXPECT_EQ(report.failures[1].mask, 0x81);
}

TEST_F(TestRefinedChecker, testReferenceRepairsHandMadeGrids)
{
    // With s = 5, edges N1 and vertices N2 (§3) nothing may fail on any hand-made grid, and
    // the relabelled subvoxels stay within 1/5 voxel (closed cube to closed cube) of an input
    // voxel of their new label: a vertex's N2 box reaches 2 subvoxels from the vertex, and the
    // dominant label owns a voxel at that vertex.
    for (const auto& c : vdbi_test::handMadeCases()) {
        SCOPED_TRACE(c.name);
        const auto r = vdbi_test::referenceFattening(*c.grid);
        const auto report = r.check();
        EXPECT_TRUE(report.ok()) << report.summary();
        const auto d = r.distance();
        EXPECT_TRUE(d.ok());
        EXPECT_LE(d.maxDistance, 0.2 + 1e-12);
        EXPECT_LE(d.maxFarDistance, 0.4 + 1e-12);
        EXPECT_EQ(r.relabelled == 0, r.elements.empty());
    }
}

TEST_F(TestRefinedChecker, testEulerCharacteristicFromFineLabels)
{
    // The checker sums each point's share of V - E + F of every label's boundary surface.
    // Known surfaces: a cube (2), a torus (0), two nested spheres (4); two cubes sharing only a
    // corner form a pinched complex with V - E + F = 15 - 24 + 12 = 3; after repair the 0 voxels
    // separate them (two spheres, 4), and in antipodalSix the 0 voxels tunnel through the
    // vertex, which turns the ball of six voxels into a solid torus (0).
    auto euler = [](const openvdb::Int32Grid::Ptr& g, int s, int ek, int vk, Label l) {
        return vdbi_test::referenceFattening(*g, params(s, ek, vk)).check().euler(l);
    };
    EXPECT_EQ(euler(vdbi_test::singleVoxel(), 1, 0, 0, 1), 2);
    EXPECT_EQ(euler(vdbi_test::singleVoxel(), 1, 0, 0, 0), 2);
    EXPECT_EQ(euler(vdbi_test::torusRing(), 1, 0, 0, 1), 0);
    EXPECT_EQ(euler(vdbi_test::hollowShell(), 1, 0, 0, 1), 4);
    EXPECT_EQ(euler(vdbi_test::hollowShellFilled(), 1, 0, 0, 2), 2);
    EXPECT_EQ(euler(vdbi_test::twoVoxelsSharingVertex(), 1, 0, 0, 1), 3);
    EXPECT_EQ(euler(vdbi_test::twoVoxelsSharingVertex(), 5, 0, 0, 1), 3);
    EXPECT_EQ(euler(vdbi_test::twoVoxelsSharingVertex(), 5, 1, 2, 1), 4);
    EXPECT_EQ(euler(vdbi_test::twoVoxelsSharingEdge(), 5, 1, 2, 1), 4);
    EXPECT_EQ(euler(vdbi_test::antipodalSix(), 5, 1, 2, 1), 0);
    EXPECT_EQ(euler(vdbi_test::antipodalSix(), 5, 1, 2, 0), 0);
}

TEST_F(TestRefinedChecker, testDistanceCheckFails)
{
    // A checker that cannot fail proves nothing. Make label 1 dominant at the shared vertex of
    // two voxels, so that the fattened box grows label 1 into background voxels: N2 keeps every
    // relabelled subvoxel within 1/5 of a voxel of label 1; N4 reaches 3 subvoxels = 3/5 away.
    const auto grid = vdbi_test::twoVoxelsSharingVertex();
    vdbi_test::ReferenceParams p = params(5, 1, 2);
    p.priority = vdbi::LabelPriority({1});
    const auto good = vdbi_test::referenceFattening(*grid, p).distance();
    EXPECT_TRUE(good.ok());
    EXPECT_GT(good.relabelled, 0u);
    EXPECT_DOUBLE_EQ(good.maxDistance, 0.2);
    EXPECT_DOUBLE_EQ(good.maxFarDistance, 0.4);
    p.vertexK = 4;
    const auto bad = vdbi_test::referenceFattening(*grid, p).distance();
    EXPECT_FALSE(bad.ok());
    EXPECT_DOUBLE_EQ(bad.maxDistance, 0.6);
    EXPECT_FALSE(bad.examples.empty());
}

TEST_F(TestRefinedChecker, testArbitraryFineLabelFunction)
{
    // The checker works on any fine label function: two fine voxels touching along an edge
    // fail (at the edge's 2 end points, for both labels), a fine 3x3x3 cube passes.
    auto edgeTouch = [](const Coord& f) -> Label {
        return (f == Coord(0, 0, 0) || f == Coord(1, 1, 0)) ? 7 : 0;
    };
    auto points = openvdb::MaskGrid::create(false);
    points->tree().sparseFill(openvdb::CoordBBox(Coord(-1), Coord(3)), true, true);
    const auto bad = vdbi_test::checkManifold(vdbi_test::FineLabelFn(edgeTouch), *points);
    EXPECT_EQ(bad.failureCount, 4u) << bad.summary();
    EXPECT_EQ(bad.pointsChecked, 125u);
    auto cube = [](const Coord& f) -> Label {
        const bool inside = f.x() >= 0 && f.y() >= 0 && f.z() >= 0 && f.x() < 3 && f.y() < 3
            && f.z() < 3;
        return inside ? -4 : 0;
    };
    const auto good = vdbi_test::checkManifold(vdbi_test::FineLabelFn(cube), *points);
    EXPECT_TRUE(good.ok()) << good.summary();
    EXPECT_EQ(good.euler(-4), 2);
}

TEST_F(TestRefinedChecker, testBlockClassCount)
{
    // Ordered set partitions of 8 voxels: the Fubini number 545,835; with and without the
    // background: 1,091,670 labellings in 23,982 classes under the 48 cube symmetries (§6).
    EXPECT_EQ(vdbi_test::cubeSymmetries().size(), 48u);
    EXPECT_EQ(vdbi_test::orderedSetPartitions8().size(), 545835u);
    std::size_t labellings = 0;
    for (const auto& c : vdbi_test::blockClasses()) labellings += c.orbitSize;
    EXPECT_EQ(labellings, 1091670u);
    EXPECT_EQ(vdbi_test::blockClasses().size(), 23982u);
    // 3^12 volumes of 2x2x3 voxels with labels 0..2 under the 16 symmetries of the box.
    std::size_t volumes = 0;
    for (const auto& c : vdbi_test::box223Classes()) volumes += c.orbitSize;
    EXPECT_EQ(volumes, 531441u);
    EXPECT_EQ(vdbi_test::box223Classes().size(), 36639u);
}

TEST_F(TestRefinedChecker, testNegativeControlsOnBlockClasses)
{
    // ALGORITHM.md §6: without fattening 16,346 of 23,982 classes fail (exactly those with a
    // critical element: the checker agrees with §2); edges N1 + vertices N1 leave 440 failing
    // classes, and so does s = 3; s = 5 with N1/N2 leaves none. Were the checker unable to
    // fail, the first three counts would be 0.
    const ControlResult none = runControl(params(5, 0, 0), false);
    EXPECT_EQ(none.classes, 23982u);
    EXPECT_EQ(none.failingClasses, 16346u);
    EXPECT_EQ(none.disagreeWithRules, 0u);
    EXPECT_EQ(runControl(params(5, 1, 1), false).failingClasses, 440u);
    EXPECT_EQ(runControl(params(3, 1, 2), false).failingClasses, 440u);
    const ControlResult good = runControl(params(5, 1, 2), true);
    EXPECT_EQ(good.failingClasses, 0u);
    EXPECT_LE(good.maxDistance, 0.4);
    std::cout << "      no fattening: " << none.failingClasses << " of " << none.classes
              << " classes fail (" << none.failingLabellings << " labellings); s=5 N1/N2: "
              << good.failingClasses << ", max distance " << good.maxDistance
              << ", farthest point " << good.maxFarDistance << std::endl;
}

TEST_F(TestRefinedChecker, testLongMoreNegativeControlsOnBlockClasses)
{
    // The other settings of §6: edges only 2,640, vertices only 14,104, s = 4 440, s = 6 with
    // N2/N3 440, and s = 7 with N2/N3 (the constrained setting) 0 failing classes.
    EXPECT_EQ(runControl(params(5, 1, 0), false).failingClasses, 2640u);
    EXPECT_EQ(runControl(params(5, 0, 2), false).failingClasses, 14104u);
    EXPECT_EQ(runControl(params(4, 1, 2), false).failingClasses, 440u);
    EXPECT_EQ(runControl(params(6, 2, 3), false).failingClasses, 440u);
    EXPECT_EQ(runControl(params(7, 2, 3), false).failingClasses, 0u);
}
