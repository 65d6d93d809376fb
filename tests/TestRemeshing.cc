// SPDX-License-Identifier: Apache-2.0

#include "support/MeshChecker.h"
#include "support/TestData.h"

#include <vdbi/Exceptions.h>
#include <vdbi/FeatureCurves.h>
#include <vdbi/Interfaces.h>
#include <vdbi/LabelVolumeReader.h>
#include <vdbi/PatchMeshes.h>
#include <vdbi/ReferenceSurface.h>
#include <vdbi/Remeshing.h>

#include <gtest/gtest.h>

#include <openvdb/Exceptions.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

using openvdb::Coord;
using openvdb::Vec3d;

class TestRemeshing : public ::testing::Test
{
protected:
    static void SetUpTestSuite() { openvdb::initialize(); }
};

namespace {

// ---------------------------------------------------------------------------------------
// Volumes

/// Label 1 inside a ball of radius r1, label 2 in the shell up to r2, background 0 outside.
openvdb::Int32Grid::Ptr
nestedBalls(double r1, double r2)
{
    auto grid = openvdb::Int32Grid::create(0);
    auto acc = grid->getAccessor();
    const int n = int(std::ceil(r2)) + 1;
    for (int x = -n; x <= n; ++x) for (int y = -n; y <= n; ++y) for (int z = -n; z <= n; ++z) {
        const double r = std::sqrt(double(x * x + y * y + z * z));
        if (r <= r1) acc.setValueOn(Coord(x, y, z), 1);
        else if (r <= r2) acc.setValueOn(Coord(x, y, z), 2);
    }
    return grid;
}

/// Two boxes of labels 1 and 2 side by side, touching along a face, in background 0.
openvdb::Int32Grid::Ptr
touchingBoxes()
{
    auto grid = openvdb::Int32Grid::create(0);
    grid->tree().fill(openvdb::CoordBBox(Coord(0, 0, 0), Coord(7, 5, 6)), 1, true);
    grid->tree().fill(openvdb::CoordBBox(Coord(8, 1, 0), Coord(13, 6, 4)), 2, true);
    return grid;
}

/// Blobs of labels 1..labels: every voxel takes the label of its nearest random centre if
/// that is close enough, else background; thin necks and tiny pieces included.
openvdb::Int32Grid::Ptr
randomBlobs(unsigned seed, int size, int labels, int centres)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(2.0, size - 2.0), rad(1.5, size / 3.0);
    std::vector<std::tuple<Vec3d, double, int>> blobs;
    for (int i = 0; i < centres; ++i) {
        blobs.emplace_back(Vec3d(pos(rng), pos(rng), pos(rng)), rad(rng), 1 + i % labels);
    }
    auto grid = openvdb::Int32Grid::create(0);
    auto acc = grid->getAccessor();
    for (int x = 0; x < size; ++x) for (int y = 0; y < size; ++y) for (int z = 0; z < size; ++z) {
        double best = 1e30;
        int label = 0;
        for (const auto& [c, r, l] : blobs) {
            const double d = (Vec3d(x, y, z) - c).length() / r;
            if (d < 1.0 && d < best) {
                best = d;
                label = l;
            }
        }
        if (label) acc.setValueOn(Coord(x, y, z), label);
    }
    return grid;
}

vdbi::InterfaceMesh
extract(const openvdb::Int32Grid& grid)
{
    return vdbi::extractInterfaces(grid).mesh;
}

vdbi::InterfaceMesh
remesh(const vdbi::InterfaceMesh& raw, double edgeLength, bool threaded = true, int iterations = 10)
{
    vdbi::RemeshOptions options;
    options.edgeLength = edgeLength;
    options.iterations = iterations;
    options.threaded = threaded;
    return vdbi::remeshPatches(raw, options);
}

// ---------------------------------------------------------------------------------------
// Independent checks of the guarantees

using Edge = std::pair<std::uint32_t, std::uint32_t>;

Edge
undirected(std::uint32_t u, std::uint32_t v)
{
    return u < v ? Edge(u, v) : Edge(v, u);
}

/// Every patch a consistently oriented 2-manifold (with boundary); every boundary edge of a
/// patch a boundary edge of another patch; the patches of every label one closed, oriented
/// surface (each edge in exactly two of its triangles, used in opposite directions).
::testing::AssertionResult
isConsistentAndManifold(const vdbi::InterfaceMesh& mesh)
{
    std::map<Edge, int> boundaryUse;   // how many patches have the edge as boundary edge
    std::map<vdbi::Label, std::map<Edge, std::vector<int>>> labelEdges;
    for (std::size_t p = 0; p < mesh.patches.size(); ++p) {
        const auto& patch = mesh.patches[p];
        if (patch.triangleCount == 0) {
            return ::testing::AssertionFailure() << "patch " << p << " is empty";
        }
        std::set<Edge> directed;
        std::map<Edge, int> count;
        for (std::size_t t = patch.firstTriangle; t < patch.firstTriangle + patch.triangleCount;
             ++t) {
            const auto& tri = mesh.triangles[t];
            for (int i = 0; i < 3; ++i) {
                if (tri[i] >= mesh.points.size()) {
                    return ::testing::AssertionFailure() << "index out of range";
                }
            }
            if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
                return ::testing::AssertionFailure() << "degenerate triangle " << t;
            }
            for (int i = 0; i < 3; ++i) {
                const std::uint32_t u = tri[i], v = tri[(i + 1) % 3];
                if (!directed.insert(Edge(u, v)).second) {
                    return ::testing::AssertionFailure() << "patch (" << patch.a << ", "
                        << patch.b << "): directed edge " << u << "->" << v << " twice";
                }
                ++count[undirected(u, v)];
                // Orientation per label: as given for label a, reversed for label b.
                labelEdges[patch.a][undirected(u, v)].push_back(u < v ? 1 : -1);
                labelEdges[patch.b][undirected(u, v)].push_back(u < v ? -1 : 1);
            }
        }
        for (const auto& [e, c] : count) {
            if (c > 2) {
                return ::testing::AssertionFailure() << "patch (" << patch.a << ", " << patch.b
                    << "): edge in " << c << " triangles";
            }
            if (c == 1) ++boundaryUse[e];
        }
    }
    for (const auto& [e, c] : boundaryUse) {
        if (c < 2) {
            return ::testing::AssertionFailure() << "boundary edge (" << e.first << ", "
                << e.second << ") of only one patch";
        }
    }
    for (const auto& [label, edges] : labelEdges) {
        for (const auto& [e, uses] : edges) {
            if (uses.size() != 2 || uses[0] + uses[1] != 0) {
                return ::testing::AssertionFailure() << "label " << label << ": edge ("
                    << e.first << ", " << e.second << ") in " << uses.size()
                    << " triangles of its surface, or not in opposite directions";
            }
        }
    }
    return ::testing::AssertionSuccess();
}

bool
sameMesh(const vdbi::InterfaceMesh& a, const vdbi::InterfaceMesh& b)
{
    if (a.points != b.points || a.triangles != b.triangles) return false;
    if (a.patches.size() != b.patches.size()) return false;
    for (std::size_t p = 0; p < a.patches.size(); ++p) {
        const auto &x = a.patches[p], &y = b.patches[p];
        if (x.a != y.a || x.b != y.b || x.firstTriangle != y.firstTriangle
            || x.triangleCount != y.triangleCount) return false;
    }
    return true;
}

/// Distance from @a q to the triangles [first, first + count) of @a mesh, brute force.
double
distanceToPatch(const vdbi::InterfaceMesh& mesh, const vdbi::InterfacePatch& patch,
                const Vec3d& q)
{
    double best = 1e300;
    for (std::size_t t = patch.firstTriangle; t < patch.firstTriangle + patch.triangleCount; ++t) {
        const auto& tri = mesh.triangles[t];
        Vec3d bary;
        const Vec3d c = vdbi::closestPointOnTriangle(q, mesh.points[tri[0]], mesh.points[tri[1]],
                                                     mesh.points[tri[2]], bary);
        best = std::min(best, (c - q).lengthSqr());
    }
    return std::sqrt(best);
}

/// Largest distance, over all patches, of remeshed vertices to the raw patch and of raw face
/// centres to the remeshed patch.
std::pair<double, double>
hausdorffParts(const vdbi::InterfaceMesh& raw, const vdbi::InterfaceMesh& out)
{
    double toRaw = 0.0, toOut = 0.0;
    for (std::size_t p = 0; p < raw.patches.size(); ++p) {
        const auto &rp = raw.patches[p], &op = out.patches[p];
        std::set<std::uint32_t> vertices;
        for (std::size_t t = op.firstTriangle; t < op.firstTriangle + op.triangleCount; ++t) {
            for (int i = 0; i < 3; ++i) vertices.insert(out.triangles[t][i]);
        }
        for (std::uint32_t v : vertices) {
            toRaw = std::max(toRaw, distanceToPatch(raw, rp, out.points[v]));
        }
        for (std::size_t t = rp.firstTriangle; t < rp.firstTriangle + rp.triangleCount; ++t) {
            const auto& tri = raw.triangles[t];
            const Vec3d c = (raw.points[tri[0]] + raw.points[tri[1]] + raw.points[tri[2]]) / 3.0;
            toOut = std::max(toOut, distanceToPatch(out, op, c));
        }
    }
    return {toRaw, toOut};
}

struct Quality
{
    double inRange = 0.0;          ///< fraction of edges within [0.5, 1.5] x target
    double minAngle = 0.0, angleP1 = 0.0, angleMedian = 0.0;   ///< smallest triangle angles
    double radiusRatioP1 = 0.0;    ///< 1st percentile of 2 r_in / r_circ (1 = equilateral)
};

Quality
measureQuality(const vdbi::InterfaceMesh& mesh, double target)
{
    Quality q;
    std::set<Edge> edges;
    std::vector<double> angles, ratios;
    for (const auto& t : mesh.triangles) {
        const Vec3d p[3] = {mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]};
        double smallest = 180.0;
        double len[3];
        for (int i = 0; i < 3; ++i) {
            edges.insert(undirected(t[i], t[(i + 1) % 3]));
            const Vec3d a = p[(i + 1) % 3] - p[i], b = p[(i + 2) % 3] - p[i];
            const double cosine = a.dot(b) / std::max(1e-300, a.length() * b.length());
            smallest = std::min(smallest, std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / M_PI);
            len[i] = (p[(i + 1) % 3] - p[i]).length();
        }
        angles.push_back(smallest);
        const double s = 0.5 * (len[0] + len[1] + len[2]);
        const double area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
        const double rIn = area / s, rCirc = len[0] * len[1] * len[2] / std::max(1e-300, 4 * area);
        ratios.push_back(area > 0 ? 2 * rIn / rCirc : 0.0);
    }
    std::size_t good = 0;
    for (const Edge& e : edges) {
        const double l = (mesh.points[e.first] - mesh.points[e.second]).length();
        if (l >= 0.5 * target && l <= 1.5 * target) ++good;
    }
    q.inRange = edges.empty() ? 0.0 : double(good) / double(edges.size());
    if (!angles.empty()) {
        std::sort(angles.begin(), angles.end());
        std::sort(ratios.begin(), ratios.end());
        q.minAngle = angles.front();
        q.angleP1 = angles[angles.size() / 100];
        q.angleMedian = angles[angles.size() / 2];
        q.radiusRatioP1 = ratios[ratios.size() / 100];
    }
    return q;
}

void
printQuality(const char* name, const vdbi::InterfaceMesh& raw, const vdbi::InterfaceMesh& out,
             double target)
{
    const Quality q = measureQuality(out, target);
    std::printf("[ %s ] %zu -> %zu triangles, edges in [0.5,1.5]x target: %.2f %%, min angle "
                "%.1f, 1st pct %.1f, median %.1f deg, radius ratio 1st pct %.2f\n",
                name, raw.triangles.size(), out.triangles.size(), 100 * q.inRange, q.minAngle,
                q.angleP1, q.angleMedian, q.radiusRatioP1);
}

/// The independent checker (tests/support/MeshChecker) agrees, and remeshing changed no
/// label's topology: every label surface is closed, with the Euler characteristic it had.
void
expectSameTopology(const vdbi::InterfaceMesh& raw, const vdbi::InterfaceMesh& out,
                   const std::string& name)
{
    const vdbi_test::MeshReport before = vdbi_test::checkMesh(raw);
    const vdbi_test::MeshReport after = vdbi_test::checkMesh(out, false);
    EXPECT_TRUE(after.ok()) << name << ": " << after.summary();
    ASSERT_EQ(after.labels.size(), before.labels.size()) << name;
    for (const auto& [label, report] : before.labels) {
        const auto it = after.labels.find(label);
        ASSERT_NE(it, after.labels.end()) << name << ": label " << label;
        EXPECT_TRUE(it->second.closed()) << name << ": label " << label;
        EXPECT_EQ(it->second.euler, report.euler) << name << ": label " << label;
    }
}

/// The whole check for one volume at one target length (in voxels; the test grids have
/// unit voxels): guarantees, same patches, closeness both ways (within @a maxDistance
/// voxels), quality printed.
void
checkRemeshing(const char* name, const vdbi::InterfaceMesh& raw, double target,
               bool measureDistances = true, double maxDistance = 1.0)
{
    const vdbi::InterfaceMesh out = remesh(raw, target);
    ASSERT_TRUE(isConsistentAndManifold(raw));
    EXPECT_TRUE(isConsistentAndManifold(out)) << name;
    ASSERT_EQ(out.patches.size(), raw.patches.size());
    for (std::size_t p = 0; p < raw.patches.size(); ++p) {
        EXPECT_EQ(out.patches[p].a, raw.patches[p].a);
        EXPECT_EQ(out.patches[p].b, raw.patches[p].b);
        EXPECT_GT(out.patches[p].triangleCount, 0u);
    }
    EXPECT_TRUE(out.pointKeys.empty());
    EXPECT_EQ(out.keyScale, 0);
    // OpenMesh accepts every patch: no complex edge or vertex.
    EXPECT_NO_THROW(vdbi::toPatchMeshes(out));
    expectSameTopology(raw, out, name);
    if (measureDistances) {
        const auto [toRaw, toOut] = hausdorffParts(raw, out);
        std::printf("[ %s ] target %.2f: remeshed->raw %.3f, raw->remeshed %.3f voxels\n", name,
                    target, toRaw, toOut);
        EXPECT_LE(toRaw, maxDistance) << name;
        EXPECT_LE(toOut, maxDistance) << name;
    }
    printQuality(name, raw, out, target);
}

} // namespace

// ---------------------------------------------------------------------------------------

// The closest point on a triangle agrees with dense sampling of the triangle.
TEST_F(TestRemeshing, testClosestPointOnTriangle)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int trial = 0; trial < 200; ++trial) {
        const Vec3d a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
        const Vec3d q(u(rng), u(rng), u(rng));
        Vec3d bary;
        const Vec3d p = vdbi::closestPointOnTriangle(q, a, b, c, bary);
        EXPECT_NEAR((a * bary[0] + b * bary[1] + c * bary[2] - p).length(), 0.0, 1e-9);
        double best = 1e300;
        const int n = 200;
        for (int i = 0; i <= n; ++i) for (int j = 0; i + j <= n; ++j) {
            const Vec3d s = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
            best = std::min(best, (s - q).length());
        }
        EXPECT_LE((p - q).length(), best + 1e-12);
        EXPECT_GE((p - q).length(), best - 0.03);
    }
}

// Two touching boxes: the 1|2 patch is bounded by one closed curve where it meets the
// background, so every junction has feature valence other than 2 or is a loop start;
// resampling gives every curve at least one segment and closed curves at least three.
TEST_F(TestRemeshing, testFeatureCurvesOfTouchingBoxes)
{
    const auto raw = extract(*touchingBoxes());
    ASSERT_EQ(raw.patches.size(), 3u);   // (0,1), (0,2), (1,2)
    auto curves = vdbi::findFeatureCurves(raw);
    ASSERT_FALSE(curves.curves.empty());
    std::size_t edgeCount = 0;
    for (std::size_t c = 0; c < curves.curves.size(); ++c) {
        const auto& curve = curves.curves[c];
        // The contact face of the boxes is bounded by curves shared by all three patches.
        EXPECT_EQ(curve.patches, (std::vector<std::uint32_t>{0, 1, 2}));
        edgeCount += curve.points.size() - 1;
        for (std::size_t i = 0; i + 1 < curve.points.size(); ++i) {
            const auto* e = curves.findEdge(curve.points[i], curve.points[i + 1]);
            ASSERT_NE(e, nullptr);
            EXPECT_EQ(e->curve, c);
            EXPECT_EQ(e->segment, i);
        }
        EXPECT_GE(curves.junctionSample(curve.points.front()), 0);
        EXPECT_GE(curves.junctionSample(curve.points.back()), 0);
    }
    EXPECT_EQ(edgeCount, curves.edges.size());
    // The contact rectangle x = 8, y in [1, 6), z in [0, 5) has perimeter 2 * (5 + 5) = 20.
    EXPECT_EQ(edgeCount, 20u);

    vdbi::smoothFeatureCurves(curves, raw, 10, Vec3d(0.5));
    vdbi::resampleFeatureCurves(curves, 2.0);
    for (const auto& curve : curves.curves) {
        ASSERT_EQ(curve.smoothed.size(), curve.points.size());
        for (std::size_t i = 0; i < curve.points.size(); ++i) {
            EXPECT_LE((curve.smoothed[i] - raw.points[curve.points[i]]).length(), 0.5 + 1e-12);
        }
        const std::size_t n = curve.samples.size() - 1;
        EXPECT_GE(n, curve.isClosed() ? 3u : 1u);
        EXPECT_EQ(long(n), std::max(curve.isClosed() ? 3L : 1L,
                                    std::lround(curve.length() / 2.0)));
        for (std::size_t k = 1; k < n; ++k) {
            // Uniform in arc length.
            EXPECT_NEAR(curve.sampleArcLength[k], curve.length() * k / n, 1e-9);
        }
    }
}

// A ball of label 1 in a shell of label 2: two closed patches (no curves), and the patch
// (0, 2) outside; the remeshed surfaces stay within a voxel of the staircase.
TEST_F(TestRemeshing, testNestedBalls)
{
    const auto raw = extract(*nestedBalls(4.5, 8.0));
    checkRemeshing("nested balls, 1 voxel", raw, 1.0);
    checkRemeshing("nested balls, 2 voxels", raw, 2.0);
}

TEST_F(TestRemeshing, testTouchingBoxes)
{
    const auto raw = extract(*touchingBoxes());
    checkRemeshing("touching boxes, 1 voxel", raw, 1.0);
    checkRemeshing("touching boxes, 2 voxels", raw, 2.0);
    checkRemeshing("touching boxes, 0.5 voxel", raw, 0.5);
}

// Random blobs with many junctions, thin necks and tiny pieces.
TEST_F(TestRemeshing, testRandomBlobs)
{
    for (unsigned seed = 1; seed <= 4; ++seed) {
        const auto raw = extract(*randomBlobs(seed, 20, 4, 10));
        checkRemeshing("random blobs, 1.5 voxels", raw, 1.5, seed <= 2);
    }
}

// Noise volumes: the hardest case for the curve network (junctions everywhere, patches of
// one or two faces). Only the guarantees are asserted.
TEST_F(TestRemeshing, testNoiseVolumes)
{
    for (unsigned seed = 1; seed <= 10; ++seed) {
        auto grid = openvdb::Int32Grid::create(0);
        auto acc = grid->getAccessor();
        unsigned state = seed;
        for (int x = 0; x < 8; ++x) for (int y = 0; y < 8; ++y) for (int z = 0; z < 8; ++z) {
            state = state * 1664525u + 1013904223u;
            acc.setValue(Coord(x, y, z), int((state >> 16) % (2 + seed % 4)));
        }
        const auto raw = extract(*grid);
        for (double target : {0.7, 2.0}) {
            const auto out = remesh(raw, target);
            EXPECT_TRUE(isConsistentAndManifold(out)) << "seed " << seed << " target " << target;
            expectSameTopology(raw, out, "noise seed " + std::to_string(seed));
            ASSERT_EQ(out.patches.size(), raw.patches.size());
            for (const auto& p : out.patches) EXPECT_GT(p.triangleCount, 0u);
        }
    }
}

// Voxel art: one-voxel bumps and rods everywhere, and 566 subdivided voxels. At one voxel
// everything stays within a voxel; at two voxels, twice the size of its finest details,
// the surface may pass a little farther from a one-voxel bump.
TEST_F(TestRemeshing, testChrKnight)
{
    const auto grid = vdbi::readLabelVolume(vdbi_test::dataPath("chr_knight.vox"));
    const auto raw = extract(*grid);
    checkRemeshing("chr_knight, 1 voxel", raw, 1.0);
    checkRemeshing("chr_knight, 2 voxels", raw, 2.0, true, 1.25);
}

// 1 thread, N threads and no threading give the same bytes.
TEST_F(TestRemeshing, testDeterministic)
{
    const auto grid = vdbi::readLabelVolume(vdbi_test::dataPath("chr_knight.vox"));
    const auto raw = extract(*grid);
    const auto parallel = remesh(raw, 1.5, true);
    const auto serial = remesh(raw, 1.5, false);
    vdbi::InterfaceMesh single;
    tbb::task_arena arena(1);
    arena.execute([&] { single = remesh(raw, 1.5, true); });
    EXPECT_TRUE(sameMesh(parallel, serial));
    EXPECT_TRUE(sameMesh(parallel, single));
}

TEST_F(TestRemeshing, testInvalidOptions)
{
    const auto raw = extract(*touchingBoxes());
    vdbi::RemeshOptions options;
    options.edgeLength = 0.0;
    EXPECT_THROW(vdbi::remeshPatches(raw, options), openvdb::ValueError);
    options.edgeLength = std::nan("");
    EXPECT_THROW(vdbi::remeshPatches(raw, options), openvdb::ValueError);
    options.edgeLength = 1.0;
    options.iterations = -1;
    EXPECT_THROW(vdbi::remeshPatches(raw, options), openvdb::ValueError);
}

// Zero iterations: only the boundary replacement; still every guarantee.
TEST_F(TestRemeshing, testZeroIterations)
{
    const auto raw = extract(*randomBlobs(5, 16, 3, 8));
    const auto out = remesh(raw, 2.0, true, 0);
    EXPECT_TRUE(isConsistentAndManifold(out));
}

// The pipeline entry point remeshes when asked: edge length 0 means one voxel, the stage is
// timed, the statistics count the remeshed mesh.
TEST_F(TestRemeshing, testPipeline)
{
    auto grid = nestedBalls(3.5, 6.0);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
    vdbi::Options options;
    options.remesh = true;
    const vdbi::Result result = vdbi::extractInterfaces(*grid, options);
    EXPECT_TRUE(isConsistentAndManifold(result.mesh));
    EXPECT_TRUE(result.mesh.pointKeys.empty());
    EXPECT_EQ(result.statistics.triangles, result.mesh.triangles.size());
    EXPECT_EQ(result.statistics.vertices, result.mesh.points.size());
    ASSERT_FALSE(result.statistics.stageSeconds.empty());
    EXPECT_EQ(result.statistics.stageSeconds.back().first, "remeshing");
    const Quality q = measureQuality(result.mesh, 0.5);
    EXPECT_GT(q.inRange, 0.95);

    const vdbi::Result raw = vdbi::extractInterfaces(*grid);
    options.edgeLength = 1.0;   // two voxels
    const vdbi::Result coarse = vdbi::extractInterfaces(*grid, options);
    EXPECT_TRUE(isConsistentAndManifold(coarse.mesh));
    EXPECT_LT(coarse.mesh.triangles.size(), raw.mesh.triangles.size() / 2);
}

// An interrupter that says stop ends the remeshing with vdbi::Interrupted.
TEST_F(TestRemeshing, testInterrupted)
{
    struct Stop : openvdb::util::NullInterrupter
    {
        bool wasInterrupted(int = -1) override { return true; }
    } stop;
    const auto raw = extract(*touchingBoxes());
    vdbi::RemeshOptions options;
    options.edgeLength = 1.0;
    options.interrupter = &stop;
    EXPECT_THROW(vdbi::remeshPatches(raw, options), vdbi::Interrupted);
}
