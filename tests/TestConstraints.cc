// SPDX-License-Identifier: Apache-2.0
/// @file TestConstraints.cc
/// @brief Separation constraints "A and B are separated by C" (ALGORITHM.md §2, §6), checked
/// by independent checkers (support/RefinedChecker.h, support/SeparationChecker.h,
/// support/MeshChecker.h): after the repair no label has a critical edge or vertex on the
/// fine grid and the closed sets of A and B do not touch at all; relabelled subvoxels stay
/// within 3/7 voxel of their new label (the separator layer aside); the extracted patches
/// keep every guarantee and none joins a constrained pair; threads change nothing.

#include <vdbi/CriticalElements.h>
#include <vdbi/Fattening.h>
#include <vdbi/InterfaceExtraction.h>
#include <vdbi/Interfaces.h>
#include <vdbi/LabelGrid.h>
#include <vdbi/LabelVolumeReader.h>

#include "support/BlockEnumeration.h"
#include "support/HandMadeGrids.h"
#include "support/MeshChecker.h"
#include "support/RandomVolumes.h"
#include "support/RawExtraction.h"
#include "support/RefinedChecker.h"
#include "support/SeparationChecker.h"
#include "support/TestData.h"

#include <gtest/gtest.h>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using openvdb::Coord;
using vdbi::Label;
using vdbi::SeparationConstraint;

class TestConstraints : public ::testing::Test
{
protected:
    void SetUp() override { openvdb::initialize(); }
};

namespace {

using Constraints = std::vector<SeparationConstraint>;

double
secondsSince(const std::chrono::steady_clock::time_point& t0)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The repair of @a labels (voxelized, see LabelGrid.h).
vdbi::RefinedLabels
repair(const openvdb::Int32Grid::ConstPtr& labels, const vdbi::RepairOptions& options)
{
    return vdbi::fattenCriticalElements(labels, vdbi::findCriticalElements(*labels, options),
                                        options);
}

/// The literal reading of the paper (only the A|B faces are constraint elements; edges and
/// vertices keep their §2 rule) built from the library's own pieces: the negative control.
vdbi::RefinedLabels
repairLiterally(const openvdb::Int32Grid::ConstPtr& labels, const vdbi::RepairOptions& options)
{
    vdbi::RepairOptions plain = options;
    plain.constraints.clear();
    vdbi::CriticalElements literal = vdbi::findCriticalElements(*labels, plain);
    literal.faces = vdbi::findCriticalElements(*labels, options).faces;
    return vdbi::fattenCriticalElements(labels, literal, options);
}

std::string
describe(const Constraints& cs)
{
    std::ostringstream os;
    for (const SeparationConstraint& c : cs) {
        os << " (" << c.a << "," << c.b << ":" << c.separator << ")";
    }
    return os.str();
}

// ---------------------------------------------------------------------------------------------
// Block classes

/// Where the sweep puts the 2x2x2 block: its fine voxels (and the padding's) then lie inside
/// one internal node of every tree, where around the origin each tree the library builds
/// would allocate eight (the repair is translation invariant; this is only cost).
const Coord BLOCK_ORIGIN(20, 20, 20);

/// @brief Every single constraint for one block class (ALGORITHM.md §6): A < B among the
/// labels present (the block's and the background 0 of the padding), C every other present
/// label and one absent label; plus one constraint naming absent labels only.
/// @details One absent C stands for all: with a single constraint an absent label enters the
/// repair only as the dominant label of the constraint elements. Its rank could matter only
/// for a subvoxel contested by two elements of different labels in one pass, and there are
/// none that survive: all faces carry C; two edges' N2 boxes meet only inside the N3 box of
/// their common end point, which is critical too (by §2 rule 1, or because its block holds
/// A and B) and is relabelled afterwards; N3 boxes of distinct points are disjoint (3 + 3 < 7).
/// A constraint with A or B absent finds no element with both, so all such constraints give
/// the same repair (s = 7 with the §2 elements only): one of them is run.
Constraints
everySingleConstraint(const vdbi_test::BlockClass& bc)
{
    std::vector<Label> present(bc.labels.begin(), bc.labels.end());
    present.push_back(0);
    std::sort(present.begin(), present.end());
    present.erase(std::unique(present.begin(), present.end()), present.end());
    const Label absent = present.back() + 1;
    Constraints all;
    for (std::size_t i = 0; i < present.size(); ++i) {
        for (std::size_t j = i + 1; j < present.size(); ++j) {
            for (std::size_t k = 0; k <= present.size(); ++k) {
                const Label c = k < present.size() ? present[k] : absent;
                if (c != present[i] && c != present[j]) all.push_back({present[i], present[j], c});
            }
        }
    }
    all.push_back({present.front(), absent, absent + 1});
    return all;
}

/// What a sweep over block classes found.
struct BlockSweep
{
    vdbi_test::SeparationReport report;
    std::size_t classes = 0;
    std::size_t firstFailingClass = SIZE_MAX;
    std::string firstFailure;
};

/// @brief Repairs every @a classStride-th block class under every single constraint (every
/// @a constraintStride-th of them), in parallel over classes, and checks each repair densely.
/// @param literal  repair by the literal reading instead (the negative control)
BlockSweep
sweepBlockClasses(std::size_t classStride, std::size_t constraintStride, bool literal)
{
    const auto& classes = vdbi_test::blockClasses();
    struct Local
    {
        BlockSweep sweep;
    };
    tbb::enumerable_thread_specific<Local> locals;
    const std::size_t count = (classes.size() + classStride - 1) / classStride;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4),
        [&](const tbb::blocked_range<std::size_t>& range) {
            BlockSweep& sweep = locals.local().sweep;
            for (std::size_t n = range.begin(); n != range.end(); ++n) {
                const std::size_t ci = n * classStride;
                const vdbi_test::BlockClass& bc = classes[ci];
                const auto grid = vdbi_test::gridFromDense(2, 2, 2,
                    std::vector<Label>(bc.labels.begin(), bc.labels.end()), BLOCK_ORIGIN, 0);
                const auto labels = vdbi::voxelizedLabels(*grid);
                vdbi_test::SmallVolumeChecker checker(*grid,
                    openvdb::CoordBBox(BLOCK_ORIGIN.offsetBy(-1), BLOCK_ORIGIN.offsetBy(2)), 7);
                const Constraints all = everySingleConstraint(bc);
                ++sweep.classes;
                for (std::size_t k = ci % constraintStride; k < all.size();
                     k += constraintStride) {
                    vdbi::RepairOptions options;
                    options.threaded = false; // parallel over classes instead
                    options.constraints = {all[k]};
                    const auto refined = literal ? repairLiterally(labels, options)
                                                 : repair(labels, options);
                    const std::size_t failed = sweep.report.failingRepairs;
                    checker.check(refined, options.constraints, sweep.report);
                    if (sweep.report.failingRepairs > failed && ci < sweep.firstFailingClass) {
                        sweep.firstFailingClass = ci;
                        std::ostringstream os;
                        os << "class " << ci << " block";
                        for (Label l : bc.labels) os << " " << l;
                        os << describe(options.constraints);
                        sweep.firstFailure = os.str();
                    }
                }
            }
        });
    BlockSweep total;
    for (const Local& l : locals) {
        total.report.add(l.sweep.report);
        total.classes += l.sweep.classes;
        if (l.sweep.firstFailingClass < total.firstFailingClass) {
            total.firstFailingClass = l.sweep.firstFailingClass;
            total.firstFailure = l.sweep.firstFailure;
        }
    }
    return total;
}

void
printSweep(const char* what, const BlockSweep& s, double seconds)
{
    const auto& r = s.report;
    std::cout << "      " << what << ": " << s.classes << " classes, " << r.repairs
              << " (class, constraint) repairs, " << r.failingRepairs << " failing ("
              << r.nonManifold << " non-manifold (point, label), " << r.touching
              << " touching points, " << r.outsideBox << " outside); " << r.pointsChecked
              << " points checked, " << r.relabelled << " relabelled subvoxels, max distance "
              << r.maxDistance << " (separator " << r.maxSeparatorDistance << "); " << seconds
              << " s" << std::endl;
}

// ---------------------------------------------------------------------------------------------
// Random volumes

/// One seeded random volume with valid constraints.
struct ConstrainedVolume
{
    openvdb::Int32Grid::Ptr grid;
    Constraints constraints;
    std::string name;
};

/// Volume @a seed of generator @a g with @a count constraints over its label pool.
ConstrainedVolume
constrainedVolume(vdbi_test::Generator g, std::uint64_t seed, int count, int size)
{
    ConstrainedVolume v;
    const int labels = count + 2 + int(seed % 3);
    v.grid = vdbi_test::randomVolume(g, seed, size, labels);
    vdbi_test::Rng rng(seed * 7919 + std::uint64_t(count));
    v.constraints = vdbi_test::randomConstraints(rng, vdbi_test::labelPool(seed, labels), count);
    std::ostringstream os;
    os << vdbi_test::generatorName(g) << " seed " << seed << " size " << size << " labels "
       << labels << describe(v.constraints);
    v.name = os.str();
    return v;
}

/// The verdict of the independent checkers on one repair.
struct VolumeCheck
{
    vdbi_test::ManifoldReport manifold;
    std::size_t touching = 0;
    bool ok() const { return manifold.ok() && touching == 0; }
};

VolumeCheck
checkRepair(const vdbi::RefinedLabels& refined, const Constraints& cs)
{
    VolumeCheck c;
    vdbi_test::CheckOptions options;
    options.computeEuler = false;
    c.manifold = vdbi_test::checkManifold(refined, options);
    c.touching = vdbi_test::touchingPoints(refined, cs);
    return c;
}

/// "" when the mesh passes every check of the mesh checker, agrees with the repaired labels
/// (per label Euler characteristic and exact volume) and has no patch of a constrained pair.
std::string
verifyMesh(const vdbi::RefinedLabels& refined, const vdbi::InterfaceMesh& mesh,
           const Constraints& cs)
{
    std::ostringstream os;
    const vdbi_test::MeshReport report = vdbi_test::checkMesh(mesh);
    if (!report.ok()) return report.summary();
    for (const auto& p : mesh.patches) {
        for (const SeparationConstraint& c : cs) {
            if (p.a == std::min(c.a, c.b) && p.b == std::max(c.a, c.b)) {
                os << "patch (" << p.a << "," << p.b << ") of a constrained pair";
                return os.str();
            }
        }
    }
    const vdbi_test::ManifoldReport fine = vdbi_test::checkManifold(refined);
    const auto volumes = vdbi_test::refinedVolumes(refined);
    for (const auto& entry : report.labels) {
        const vdbi_test::LabelReport& l = entry.second;
        if (!l.closed() || l.euler != fine.euler(l.label)) {
            os << "label " << l.label << ": closed " << l.closed() << ", Euler " << l.euler
               << ", fine labels " << fine.euler(l.label);
            return os.str();
        }
        if (l.label == refined.coarse->background()) continue;
        const auto v = volumes.find(l.label);
        if (v == volumes.end() || !vdbi_test::volumeEqualsFineVoxels(l, v->second)) {
            os << "label " << l.label << ": mesh volume " << l.volume;
            return os.str();
        }
    }
    for (const auto& v : volumes) {
        if (!report.labels.count(v.first)) return "a label with volume but no surface";
    }
    return "";
}

/// "" when two repairs are the same label function (same subdivided voxels, same relabelled
/// subvoxels with the same labels).
std::string
compareRepairs(const vdbi::RefinedLabels& a, const vdbi::RefinedLabels& b)
{
    if (a.subdivision != b.subdivision) return "subdivision";
    if (!a.subdivided->tree().hasSameTopology(b.subdivided->tree())) return "subdivided voxels";
    if (!a.fine->tree().hasSameTopology(b.fine->tree())) return "relabelled subvoxels";
    auto acc = b.fine->getConstAccessor();
    for (auto it = a.fine->cbeginValueOn(); it; ++it) {
        if (acc.getValue(it.getCoord()) != *it) return "a relabelled subvoxel's label";
    }
    return "";
}

/// Runs sweepBlockClasses() over every class with every @a constraintStride-th constraint
/// and checks the outcome: no failing repair, distances within 3/7 voxel (separator aside).
void
checkEveryBlockClass(std::size_t constraintStride)
{
    const auto t0 = std::chrono::steady_clock::now();
    const BlockSweep s = sweepBlockClasses(1, constraintStride, false);
    printSweep("every class, single constraints", s, secondsSince(t0));
    std::size_t expected = 0, ci = 0;
    for (const auto& bc : vdbi_test::blockClasses()) {
        const std::size_t n = everySingleConstraint(bc).size(), first = ci++ % constraintStride;
        expected += n > first ? (n - first + constraintStride - 1) / constraintStride : 0;
    }
    EXPECT_EQ(s.classes, 23982u);
    EXPECT_EQ(s.report.repairs, expected);
    EXPECT_EQ(s.report.failingRepairs, 0u) << s.firstFailure;
    EXPECT_LE(s.report.maxDistance, 3.0 / 7.0 + 1e-12);
}

} // namespace

// Every block class (the 23,982 classes of ALGORITHM.md §6) with every fourth single
// constraint (which ones rotates with the class): the repair leaves no non-manifold point
// and A and B nowhere touching, and relabelled subvoxels stay within 3/7 voxel of their new
// label unless they are the separator. About 650,000 repairs.
TEST_F(TestConstraints, testEveryBlockClassWithSingleConstraints)
{
    checkEveryBlockClass(4);
}

// The same with every single constraint: 2,591,337 repairs, about 700 CPU seconds (run it
// with --gtest_also_run_disabled_tests).
TEST_F(TestConstraints, DISABLED_testEveryBlockClassWithEverySingleConstraint)
{
    checkEveryBlockClass(1);
}

// The dense block checker can fail: the literal reading fails on block classes, unrepaired
// blocks are non-manifold, and on a sample of repairs the dense checker and the independent
// RefinedChecker agree run by run.
TEST_F(TestConstraints, testBlockCheckerDetectsFailures)
{
    const auto t0 = std::chrono::steady_clock::now();
    const BlockSweep s = sweepBlockClasses(23, 5, true);
    printSweep("literal reading, sample", s, secondsSince(t0));
    EXPECT_GT(s.report.failingRepairs, s.report.repairs / 20);
    EXPECT_GT(s.report.touching, 0u);

    // Both checkers on a sample of repairs by the working and the literal reading, and on
    // the unrepaired blocks (nothing relabelled: non-manifold wherever §2 finds an element).
    std::size_t compared = 0, failing = 0, nonManifold = 0, disagreements = 0;
    const auto& classes = vdbi_test::blockClasses();
    for (std::size_t ci = 0; ci < classes.size(); ci += 997) {
        const auto grid = vdbi_test::gridFromDense(2, 2, 2,
            std::vector<Label>(classes[ci].labels.begin(), classes[ci].labels.end()),
            BLOCK_ORIGIN, 0);
        const auto labels = vdbi::voxelizedLabels(*grid);
        vdbi_test::SmallVolumeChecker checker(*grid,
            openvdb::CoordBBox(BLOCK_ORIGIN.offsetBy(-1), BLOCK_ORIGIN.offsetBy(2)), 7);
        for (const SeparationConstraint& c : everySingleConstraint(classes[ci])) {
            vdbi::RepairOptions options;
            options.constraints = {c};
            const vdbi::RefinedLabels repairs[3] = {repair(labels, options),
                repairLiterally(labels, options),
                vdbi::fattenCriticalElements(labels, vdbi::CriticalElements(), options)};
            for (const vdbi::RefinedLabels& refined : repairs) {
                vdbi_test::SeparationReport dense;
                checker.check(refined, options.constraints, dense);
                const bool independentOk = checkRepair(refined, options.constraints).ok();
                disagreements += (dense.failingRepairs == 0) != independentOk ? 1 : 0;
                failing += independentOk ? 0 : 1;
                nonManifold += dense.nonManifold > 0 ? 1 : 0;
                ++compared;
            }
        }
    }
    std::cout << "      " << compared << " repairs compared with the RefinedChecker, "
              << failing << " failing (" << nonManifold << " non-manifold), " << disagreements
              << " disagreements" << std::endl;
    EXPECT_EQ(disagreements, 0u);
    EXPECT_GT(failing, 0u);
    EXPECT_GT(nonManifold, 0u);
}

// Seeded random volumes of every generator with 1, 2 and 3 valid constraints (1,002 volumes
// each): no critical edge or vertex left by the independent vertex-link checker, A and B not
// touching anywhere, relabelled subvoxels within 3/7 voxel of their new label except the
// separator layer.
TEST_F(TestConstraints, testRandomVolumesAreSeparated)
{
    const auto t0 = std::chrono::steady_clock::now();
    for (int count = 1; count <= 3; ++count) {
        std::size_t volumes = 0, failing = 0, separatedFaces = 0;
        vdbi_test::SeparationReport distances;
        std::string first;
        for (vdbi_test::Generator g : vdbi_test::allGenerators()) {
            for (std::uint64_t seed = 0; seed < 167; ++seed) {
                const ConstrainedVolume v = constrainedVolume(g, seed, count, 3 + int(seed % 6));
                vdbi::RepairOptions options;
                options.constraints = v.constraints;
                const auto labels = vdbi::voxelizedLabels(*v.grid);
                const auto elements = vdbi::findCriticalElements(*labels, options);
                const auto refined = vdbi::fattenCriticalElements(labels, elements, options);
                ASSERT_EQ(refined.subdivision, 7);
                const VolumeCheck c = checkRepair(refined, v.constraints);
                if (!c.ok() && failing++ == 0) {
                    first = v.name + ": " + c.manifold.summary() + ", "
                        + std::to_string(c.touching) + " touching points";
                }
                distances.add(vdbi_test::measureDistances(refined, v.constraints));
                separatedFaces += elements.faces.size();
                ++volumes;
            }
        }
        EXPECT_EQ(failing, 0u) << first;
        EXPECT_LE(distances.maxDistance, 3.0 / 7.0 + 1e-12);
        EXPECT_GT(separatedFaces, 1000u); // the volumes do exercise the constraints
        std::cout << "      " << count << " constraint(s): " << volumes << " volumes, "
                  << separatedFaces << " A|B faces separated, " << failing << " failing, "
                  << distances.relabelled << " relabelled subvoxels, max distance "
                  << distances.maxDistance << " (separator " << distances.maxSeparatorDistance
                  << ")" << std::endl;
    }
    std::cout << "      " << secondsSince(t0) << " s" << std::endl;
}

// The checker above is a real negative control: the literal faces-only reading leaves A and
// B touching (or critical elements) in a large share of the same volumes (ALGORITHM.md §6
// reports 57 % on its own volumes).
TEST_F(TestConstraints, testLiteralReadingFails)
{
    std::size_t failed = 0, touchingOnly = 0, total = 0;
    for (vdbi_test::Generator g : vdbi_test::allGenerators()) {
        for (std::uint64_t seed = 0; seed < 50; ++seed) {
            const ConstrainedVolume v = constrainedVolume(g, seed, 1, 3 + int(seed % 6));
            vdbi::RepairOptions options;
            options.constraints = v.constraints;
            const auto refined = repairLiterally(vdbi::voxelizedLabels(*v.grid), options);
            const VolumeCheck c = checkRepair(refined, v.constraints);
            failed += c.ok() ? 0 : 1;
            touchingOnly += (c.manifold.ok() && c.touching > 0) ? 1 : 0;
            ++total;
        }
    }
    std::cout << "      literal reading: " << failed << " of " << total << " volumes fail ("
              << touchingOnly << " only by A touching B)" << std::endl;
    EXPECT_GT(failed, total / 4);
}

// The frog with constraints between neighbouring tissues (three of its largest interfaces
// between two tissues): separated everywhere, no critical element left, relabelled subvoxels
// close, and the extraction keeps every guarantee without a patch of a separated pair.
TEST_F(TestConstraints, testFrogWithRealConstraints)
{
    const auto t0 = std::chrono::steady_clock::now();
    const auto frog = vdbi::readLabelVolume(vdbi_test::dataPath("frogtissue.mhd"));
    vdbi::RepairOptions options;
    options.constraints = {{4, 5, 0}, {10, 15, 0}, {6, 3, 12}};
    const auto labels = vdbi::voxelizedLabels(*frog);
    const std::size_t faces = vdbi::findCriticalElements(*labels, options).faces.size();
    const auto refined = repair(labels, options);
    const VolumeCheck c = checkRepair(refined, options.constraints);
    EXPECT_TRUE(c.manifold.ok()) << c.manifold.summary();
    EXPECT_EQ(c.touching, 0u);
    const vdbi_test::SeparationReport d = vdbi_test::measureDistances(refined, options.constraints);
    EXPECT_LE(d.maxDistance, 3.0 / 7.0 + 1e-12);
    EXPECT_GT(faces, 1000u);

    vdbi::ExtractionOptions extraction;
    extraction.pointKeys = true; // the checker's exact volumes
    const vdbi::InterfaceMesh mesh = vdbi::extractInterfacePatches(refined, extraction);
    EXPECT_EQ(verifyMesh(refined, mesh, options.constraints), "");
    std::cout << "      frog: " << faces << " A|B faces separated, " << c.manifold.pointsChecked
              << " fine points checked, " << d.relabelled << " relabelled subvoxels, max distance "
              << d.maxDistance << " (separator " << d.maxSeparatorDistance << "), "
              << mesh.triangleCount() << " triangles; " << secondsSince(t0) << " s" << std::endl;
}

// After extraction on constrained random volumes: every guarantee of the extraction (mesh
// checker: manifold, oriented, patches fit, every label closed, Euler characteristic and
// volume of the repaired labels) and no patch between a constrained pair.
TEST_F(TestConstraints, testExtractionKeepsEveryGuarantee)
{
    const auto t0 = std::chrono::steady_clock::now();
    std::size_t volumes = 0, failing = 0, triangles = 0;
    std::string first;
    for (int count = 1; count <= 3; ++count) {
        for (vdbi_test::Generator g : vdbi_test::allGenerators()) {
            for (std::uint64_t seed = 1000; seed < 1050; ++seed) {
                const ConstrainedVolume v = constrainedVolume(g, seed, count, 3 + int(seed % 6));
                vdbi::RepairOptions options;
                options.constraints = v.constraints;
                const auto refined = repair(vdbi::voxelizedLabels(*v.grid), options);
                vdbi::ExtractionOptions extraction;
                extraction.pointKeys = true; // the checker's exact volumes
                const vdbi::InterfaceMesh mesh = vdbi::extractInterfacePatches(refined, extraction);
                const std::string problem = verifyMesh(refined, mesh, v.constraints);
                if (!problem.empty() && failing++ == 0) first = v.name + ": " + problem;
                triangles += mesh.triangleCount();
                ++volumes;
            }
        }
    }
    EXPECT_EQ(failing, 0u) << first;
    std::cout << "      " << volumes << " volumes, " << triangles << " triangles, " << failing
              << " failing; " << secondsSince(t0) << " s" << std::endl;
}

// Serial, one TBB thread and the default arena give the same repaired labels and
// byte-identical meshes with constraints.
TEST_F(TestConstraints, testThreadsGiveIdenticalResults)
{
    std::vector<ConstrainedVolume> volumes;
    for (vdbi_test::Generator g : vdbi_test::allGenerators()) {
        for (int count = 1; count <= 3; ++count) {
            volumes.push_back(constrainedVolume(g, 40 + std::uint64_t(count), count, 24));
        }
    }
    ConstrainedVolume frog;
    frog.grid = vdbi::readLabelVolume(vdbi_test::dataPath("frogtissue.mhd"));
    frog.constraints = {{4, 5, 0}, {10, 15, 0}, {6, 3, 12}};
    frog.name = "frog";
    volumes.push_back(frog);
    std::size_t separatedFaces = 0;
    for (const ConstrainedVolume& v : volumes) {
        SCOPED_TRACE(v.name);
        vdbi::Options serial;
        serial.repair.threaded = false;
        serial.repair.constraints = v.constraints;
        vdbi::Options threaded = serial;
        threaded.repair.threaded = true;
        const auto labels = vdbi::voxelizedLabels(*v.grid);
        const auto a = repair(labels, serial.repair);
        const auto b = repair(labels, threaded.repair);
        EXPECT_EQ(compareRepairs(a, b), "");
        const vdbi::Result ra = vdbi_test::extractRaw(*v.grid, serial);
        vdbi::Result rb;
        tbb::task_arena(1).execute([&] { rb = vdbi_test::extractRaw(*v.grid, threaded); });
        const vdbi::Result rc = vdbi_test::extractRaw(*v.grid, threaded);
        EXPECT_EQ(vdbi_test::compareMeshes(ra.mesh, rb.mesh), "");
        EXPECT_EQ(vdbi_test::compareMeshes(ra.mesh, rc.mesh), "");
        separatedFaces += ra.statistics.criticalFaces;
    }
    EXPECT_GT(separatedFaces, 1000u);
}

// Constraints naming labels absent from the volume are allowed.
TEST_F(TestConstraints, testAbsentLabelsAreAllowed)
{
    vdbi::Options options;
    options.repair.constraints = {{100, 200, 300}};
    const auto grid = vdbi_test::randomVolume(vdbi_test::Generator::Noise, 3, 5, 3);
    const auto r = vdbi_test::extractRaw(*grid, options);
    EXPECT_EQ(r.statistics.criticalFaces, 0u);
    EXPECT_EQ(r.statistics.subdivision, 7);
}
