// SPDX-License-Identifier: Apache-2.0

#include <vdbi/CriticalElements.h>
#include <vdbi/Fattening.h>
#include <vdbi/Interfaces.h>
#include <vdbi/LabelGrid.h>

#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

using openvdb::Coord;
using vdbi::SeparationConstraint;

class TestConstraints : public ::testing::Test {};

namespace {

/// Labels 0..labels-1 at random in a size^3 box (a portable LCG, so the volumes are the same
/// everywhere); background 0.
openvdb::Int32Grid::Ptr
noiseGrid(unsigned seed, int size, int labels)
{
    auto grid = openvdb::Int32Grid::create(0);
    auto acc = grid->getAccessor();
    unsigned state = seed * 2654435761u + 1u;
    for (int x = 0; x < size; ++x) for (int y = 0; y < size; ++y) for (int z = 0; z < size; ++z) {
        state = state * 1664525u + 1013904223u;
        const int l = int((state >> 16) % unsigned(labels));
        if (l != 0) acc.setValue(Coord(x, y, z), l);
    }
    return grid;
}

/// The refined labels written out densely, s times finer (small volumes only): a grid on which
/// the §2 rules can be evaluated directly.
openvdb::Int32Grid::Ptr
denseFineGrid(const vdbi::RefinedLabels& r)
{
    const int s = r.subdivision;
    openvdb::CoordBBox box = r.coarse->evalActiveVoxelBoundingBox();
    box.expand(1);
    auto fine = openvdb::Int32Grid::create(r.coarse->background());
    auto out = fine->getAccessor();
    vdbi::RefinedLabels::Accessor in(r);
    const Coord lo = box.min(), hi = box.max().offsetBy(1);
    const openvdb::CoordBBox fineBox(Coord(lo.x() * s, lo.y() * s, lo.z() * s),
                                     Coord(hi.x() * s - 1, hi.y() * s - 1, hi.z() * s - 1));
    for (auto it = fineBox.begin(); it; ++it) {
        const vdbi::Label l = in.fineLabel(*it);
        if (l != r.coarse->background()) out.setValue(*it, l);
    }
    return fine;
}

struct RepairCheck
{
    std::size_t criticalLeft = 0;  ///< §2 critical edges + vertices on the fine grid
    std::size_t touching = 0;      ///< fine faces/edges/points where both A and B occur
};

/// Evaluates the repaired labels on the fine grid: the §2 rules for every label, and the
/// constraint rule (an element at which A and B both occur) for every constraint.
RepairCheck
checkFine(const vdbi::RefinedLabels& refined, const std::vector<SeparationConstraint>& cs)
{
    const auto fine = denseFineGrid(refined);
    RepairCheck c;
    const auto plain = vdbi::findCriticalElements(*fine);
    c.criticalLeft = plain.edges.size() + plain.vertices.size();
    vdbi::RepairOptions constrained;
    constrained.constraints = cs;
    const auto both = vdbi::findCriticalElements(*fine, constrained);
    // With constraints every element touching A and B is critical; those not critical by §2
    // alone are exactly the touching ones (faces are only ever constraint elements).
    c.touching = both.faces.size() + both.edges.size() + both.vertices.size()
        - std::min(both.edges.size() + both.vertices.size(), c.criticalLeft);
    return c;
}

vdbi::RefinedLabels
repair(const openvdb::Int32Grid& grid, const vdbi::RepairOptions& options)
{
    const auto labels = vdbi::voxelizedLabels(grid);
    return vdbi::fattenCriticalElements(labels, vdbi::findCriticalElements(*labels, options),
                                        options);
}

/// The literal reading of the paper (only the A|B faces are constraint elements; edges and
/// vertices keep their §2 rule) built from the library's own pieces.
vdbi::RefinedLabels
repairLiterally(const openvdb::Int32Grid& grid, const vdbi::RepairOptions& options)
{
    const auto labels = vdbi::voxelizedLabels(grid);
    vdbi::CriticalElements literal = vdbi::findCriticalElements(*labels);
    literal.faces = vdbi::findCriticalElements(*labels, options).faces;
    return vdbi::fattenCriticalElements(labels, literal, options);
}

const std::vector<std::vector<SeparationConstraint>>&
constraintSets()
{
    // 1, 2 and 3 constraints; no separator is a separated label (ALGORITHM.md §6).
    static const std::vector<std::vector<SeparationConstraint>> sets = {
        {{1, 2, 3}},
        {{1, 2, 0}},
        {{1, 2, 4}, {3, 1, 4}},
        {{1, 2, 0}, {1, 3, 0}, {2, 3, 0}},
    };
    return sets;
}

} // namespace

// The working reading (ALGORITHM.md §6): after repair with s = 7 (faces N1, edges N2,
// vertices N3) no label has a critical element on the fine grid, and the closed sets of A
// and B do not touch at all, for 1, 2 and 3 constraints on seeded random volumes.
TEST_F(TestConstraints, testRandomVolumesAreSeparated)
{
    std::size_t volumes = 0, separatedFaces = 0;
    for (const auto& cs : constraintSets()) {
        for (unsigned seed = 1; seed <= 60; ++seed) {
            const auto grid = noiseGrid(seed, 4 + seed % 4, 5);
            vdbi::RepairOptions options;
            options.constraints = cs;
            const auto refined = repair(*grid, options);
            ASSERT_EQ(refined.subdivision, 7);
            const RepairCheck c = checkFine(refined, cs);
            EXPECT_EQ(c.criticalLeft, 0u) << "seed " << seed << ", " << cs.size() << " constraints";
            EXPECT_EQ(c.touching, 0u) << "seed " << seed << ", " << cs.size() << " constraints";
            separatedFaces += vdbi::findCriticalElements(*grid, options).faces.size();
            ++volumes;
        }
    }
    EXPECT_EQ(volumes, 240u);
    std::cout << volumes << " volumes, " << separatedFaces << " A|B faces separated\n";
    EXPECT_GT(separatedFaces, 1000u); // the volumes do exercise the constraint
}

// The check above can fail: the literal faces-only reading leaves A and B touching (or
// critical elements) in a large share of the same volumes, as ALGORITHM.md §6 reports (57 %).
TEST_F(TestConstraints, testLiteralReadingFails)
{
    int failed = 0, total = 0;
    const std::vector<SeparationConstraint> cs = {{1, 2, 3}};
    for (unsigned seed = 1; seed <= 60; ++seed) {
        const auto grid = noiseGrid(seed, 4 + seed % 4, 5);
        vdbi::RepairOptions options;
        options.constraints = cs;
        const RepairCheck c = checkFine(repairLiterally(*grid, options), cs);
        failed += (c.touching > 0 || c.criticalLeft > 0) ? 1 : 0;
        ++total;
    }
    EXPECT_GT(failed, total / 4) << failed << " of " << total;
    std::cout << "literal reading: " << failed << " of " << total << " volumes fail\n";
}

// Relabelled subvoxels stay within 3/7 voxel (Chebyshev, closed cubes) of an input voxel of
// their new label, except those that became the separator.
TEST_F(TestConstraints, testRelabelledSubvoxelsStayClose)
{
    double worst = 0;
    for (unsigned seed = 1; seed <= 40; ++seed) {
        const auto grid = noiseGrid(seed, 6, 5);
        vdbi::RepairOptions options;
        options.constraints = {{1, 2, 3}};
        const auto refined = repair(*grid, options);
        const int s = refined.subdivision;
        auto acc = grid->getConstAccessor();
        for (auto it = refined.fine->cbeginValueOn(); it; ++it) {
            if (*it == 3) continue; // the separator layer itself
            const Coord f = it.getCoord();
            const Coord c = vdbi::coarseOf(f, s);
            double best = 1e9;
            for (auto n = openvdb::CoordBBox(c.offsetBy(-1), c.offsetBy(1)).begin(); n; ++n) {
                if (acc.getValue(*n) != *it) continue;
                double d = 0;
                for (int a = 0; a < 3; ++a) {
                    const double lo = double(f[a]) / s, hi = double(f[a] + 1) / s;
                    d = std::max(d, std::max(0.0, std::max(double((*n)[a]) - hi, lo - double((*n)[a] + 1))));
                }
                best = std::min(best, d);
            }
            worst = std::max(worst, best);
        }
    }
    EXPECT_LE(worst, 3.0 / 7.0 + 1e-12);
    std::cout << "largest distance of a relabelled subvoxel: " << worst << " voxel\n";
}

// After extraction no patch joins a constrained pair; the output is the same for any number
// of threads.
TEST_F(TestConstraints, testNoPatchBetweenSeparatedLabels)
{
    for (unsigned seed = 1; seed <= 10; ++seed) {
        const auto grid = noiseGrid(seed, 8, 5);
        vdbi::Options options;
        options.repair.constraints = {{1, 2, 0}, {3, 4, 0}};
        const auto a = vdbi::extractInterfaces(*grid, options);
        vdbi::Result b;
        tbb::task_arena(1).execute([&] { b = vdbi::extractInterfaces(*grid, options); });
        for (const auto& p : a.mesh.patches) {
            EXPECT_FALSE(p.a == 1 && p.b == 2);
            EXPECT_FALSE(p.a == 3 && p.b == 4);
        }
        EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
        EXPECT_EQ(a.mesh.points, b.mesh.points);
        EXPECT_GT(a.statistics.criticalFaces, 0u);
    }
}

// Constraints naming labels absent from the volume are allowed.
TEST_F(TestConstraints, testAbsentLabelsAreAllowed)
{
    vdbi::Options options;
    options.repair.constraints = {{100, 200, 300}};
    const auto r = vdbi::extractInterfaces(*noiseGrid(3, 5, 3), options);
    EXPECT_EQ(r.statistics.criticalFaces, 0u);
    EXPECT_EQ(r.statistics.subdivision, 7);
}
