// SPDX-License-Identifier: Apache-2.0
/// @file TestExtractionProperties.cc
/// @brief The guarantees of the extracted interfaces (ALGORITHM.md §4), checked by the
/// independent mesh checker: every patch a consistently oriented 2-manifold, patch boundaries
/// shared, every label's patches a closed surface whose Euler characteristic is that of the
/// repaired label set and whose enclosed volume is the refined volume of the label.

#include "support/BlockEnumeration.h"
#include "support/HandMadeGrids.h"
#include "support/MeshChecker.h"
#include "support/RandomVolumes.h"
#include "support/RawExtraction.h"
#include "support/RefinedChecker.h"
#include "support/TestData.h"

#include <vdbi/CriticalElements.h>
#include <vdbi/Fattening.h>
#include <vdbi/InterfaceExtraction.h>
#include <vdbi/Interfaces.h>
#include <vdbi/LabelGrid.h>
#include <vdbi/LabelVolumeReader.h>

#include <openvdb/openvdb.h>

#include <tbb/task_arena.h>

#include <gtest/gtest.h>

#include <chrono>
#include <iostream>
#include <sstream>

using vdbi::Label;

class TestExtractionProperties : public ::testing::Test
{
protected:
    void SetUp() override { openvdb::initialize(); }
};

namespace {

/// The pipeline stage by stage, so that the repaired labels are at hand for comparison.
struct PipelineRun
{
    vdbi::RefinedLabels refined;
    vdbi::InterfaceMesh mesh;
};

PipelineRun
run(const openvdb::Int32Grid& grid, bool threaded = true)
{
    vdbi::RepairOptions options;
    options.threaded = threaded;
    PipelineRun r;
    const auto coarse = vdbi::voxelizedLabels(grid);
    r.refined = vdbi::fattenCriticalElements(coarse, vdbi::findCriticalElements(*coarse, options),
                                            options);
    vdbi::ExtractionOptions extraction;
    extraction.threaded = threaded;
    extraction.pointKeys = true; // the checker identifies vertices by their keys
    r.mesh = vdbi::extractInterfacePatches(r.refined, extraction);
    return r;
}

/// "" when the mesh passes every check of the mesh checker and agrees with the repaired
/// labels: per label, V - E + F of the closed surface equals the Euler characteristic of the
/// boundary of the label's fine set (computed by the independent checker from the fine
/// labels), and for every bounded label the enclosed volume equals its refined volume exactly.
std::string
verify(const PipelineRun& r, const vdbi_test::MeshReport& report)
{
    std::ostringstream os;
    if (!report.ok()) return report.summary();
    const vdbi_test::ManifoldReport fine = vdbi_test::checkManifold(r.refined);
    if (!fine.ok()) return "repaired labels not manifold: " + fine.summary();
    const auto volumes = vdbi_test::refinedVolumes(r.refined);
    const Label background = r.refined.coarse->background();
    for (const auto& entry : report.labels) {
        const vdbi_test::LabelReport& l = entry.second;
        if (l.euler != fine.euler(l.label)) {
            os << "label " << l.label << ": mesh Euler " << l.euler << ", fine labels "
               << fine.euler(l.label);
            return os.str();
        }
        if (l.label == background) continue;
        const auto v = volumes.find(l.label);
        if (v == volumes.end() || !vdbi_test::volumeEqualsFineVoxels(l, v->second)) {
            os << "label " << l.label << ": mesh volume " << l.volume << ", refined volume "
               << (v == volumes.end() ? 0 : v->second) << " fine voxels";
            return os.str();
        }
    }
    // Every label present in the volume must have a surface (labels that vanished entirely
    // have volume 0 and no entry).
    for (const auto& v : volumes) {
        if (!report.labels.count(v.first)) {
            os << "label " << v.first << " has volume but no surface";
            return os.str();
        }
    }
    return "";
}

double
secondsSince(const std::chrono::steady_clock::time_point& t0)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

TEST_F(TestExtractionProperties, testHandMadeGridsExactly)
{
    // Counts derived by hand. Surface area, Euler characteristic and volume do not depend on
    // the triangulation; triangle counts follow the library's documented rule (§4, and
    // InterfaceExtraction.cc): a coarse face with no split side is 2 triangles; the s x s fine
    // faces of a coarse face next to a subdivided voxel (and of a plane inside one) are merged
    // greedily, rows along the face's first axis (a+1)%3 then columns along (a+2)%3, into
    // rectangles h x w of one label pair, each a fan of 2(h + w) triangles when h w > h + w,
    // else 2 triangles per fine face. Here s = 5, a fine face is 1/25 of a coarse face.
    // - singleVoxel: a cube, 12 triangles, 8 vertices.
    // - twoVoxelsSharingVertex (and antipodalPair2x2x2): N2 of the vertex goes to 0 and cuts a
    //   2^3 corner from each voxel (area unchanged: 150 fine faces each, 300). Per voxel: 3
    //   whole faces (5x5 rectangles: 20 triangles each), 3 faces with a 2x2 notch in a corner
    //   (rectangles 3x5 and 2x3: 16 + 10 = 26 each, wherever the notch is), 3 inner 2x2 faces
    //   of the notch (8 each): 60 + 78 + 24 = 162, 324 in all. Two spheres: V = 2 + 3F/2 - F
    //   per voxel = 83, 166 in all. Volume 2 x (125 - 8) fine voxels.
    // - twoVoxelsSharingEdge: N1 of the edge and N2 of its end points go to 0, cutting from
    //   each voxel a 1x1 column along the edge and 2x2x2 blocks at its ends (17 of 125 fine
    //   voxels; 148 fine faces each: 150 - 26 outside + 24 inside, 296 in all). Voxel (0,0,0):
    //   faces x=0, y=0: 20 + 20; z=0, z=5 (notch in a corner): 26 + 26; x=5 and y=5 (a 3x5
    //   rectangle plus one fine face): 18 + 18; inside: planes x=3, y=3 (two 2x2 squares):
    //   16 + 16, x=4, y=4 (one fine face): 2 + 2, z=2, z=3 (an L of 3: 1x2 + 1x1): 6 + 6; 176.
    //   Voxel (1,1,0), the mirror image, is scanned from the other corner: x=5 face 28 (4x1
    //   strip of quads 8 + two 3x2 fans 10 + 10), everything else as above: 186. 362 triangles;
    //   V = (2 + 264 - 176) + (2 + 279 - 186) = 185.
    // - antipodalSix: N2 of the centre goes to 0 and joins the two 0 voxels through it: the
    //   six voxels become a solid torus (Euler 0). 18 whole outer faces (360 triangles, 450
    //   fine faces), 6 faces of the 0 voxels with a 2x2 notch (156; 126 fine faces), 3 inner
    //   2x2 faces in each of the six voxels (144; 72 fine faces): 660 triangles, 648 fine
    //   faces; V = E - F = 990 - 660 = 330. Volume 6 x 125 - 48 fine voxels.
    // - nothing critical: 2 triangles per coarse face (hollowShell 408 triangles on 208
    //   vertices; the torus ring 64 on 32; tJunction3 60 on 27; corner4 64 on 27).
    struct Expect
    {
        const char* name;
        openvdb::Int32Grid::Ptr grid;
        std::size_t patches, triangles, vertices;
        std::int64_t fineFaces; // all patches, in faces of a grid 5 times finer
        Label label;
        std::int64_t euler;
        double volume;
    };
    const Expect cases[] = {
        {"singleVoxel", vdbi_test::singleVoxel(), 1, 12, 8, 6 * 25, 1, 2, 1.0},
        {"twoVoxelsSharingEdge", vdbi_test::twoVoxelsSharingEdge(), 1, 362, 185, 296, 1, 4,
         216 / 125.0},
        {"twoVoxelsSharingVertex", vdbi_test::twoVoxelsSharingVertex(), 1, 324, 166, 300, 1, 4,
         234 / 125.0},
        {"antipodalPair2x2x2", vdbi_test::antipodalPair2x2x2(), 1, 324, 166, 300, 1, 4,
         234 / 125.0},
        {"antipodalSix", vdbi_test::antipodalSix(), 1, 660, 330, 648, 1, 0, 702 / 125.0},
        {"hollowShell", vdbi_test::hollowShell(), 1, 408, 208, 204 * 25, 1, 4, 98.0},
        {"hollowShellFilled", vdbi_test::hollowShellFilled(), 2, 408, 208, 204 * 25, 2, 2, 27.0},
        {"torusRing", vdbi_test::torusRing(), 1, 64, 32, 32 * 25, 1, 0, 8.0},
        {"tJunction3", vdbi_test::tJunction3(), 6, 60, 27, 30 * 25, 3, 2, 4.0},
        {"corner4", vdbi_test::corner4(), 8, 64, 27, 32 * 25, 4, 2, 2.0},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        const vdbi::Result result = vdbi_test::extractRaw(*c.grid);
        const vdbi::InterfaceMesh& mesh = result.mesh;
        EXPECT_EQ(mesh.patches.size(), c.patches);
        EXPECT_EQ(mesh.triangleCount(), c.triangles);
        EXPECT_EQ(mesh.pointCount(), c.vertices);
        const auto report = vdbi_test::checkMesh(mesh);
        ASSERT_TRUE(report.ok()) << report.summary();
        // Area in fine faces of s = 5, whatever s the library used for the keys.
        const std::int64_t K = mesh.keyScale;
        EXPECT_EQ(report.sum(&vdbi_test::PatchReport::skewTriangles), 0u);
        std::int64_t twiceArea = 0;
        for (const auto& p : report.patchReports) twiceArea += p.twiceAreaKeys;
        EXPECT_EQ(twiceArea * 100, c.fineFaces * 8 * K * K);
        EXPECT_EQ(report.labels.at(c.label).euler, c.euler);
        EXPECT_NEAR(report.labels.at(c.label).volume, c.volume, 1e-12);
        EXPECT_EQ(verify(run(*c.grid), report), "");
    }
    // Where nothing is critical the output is the plain face extraction.
    for (const auto& c : vdbi_test::handMadeCases()) {
        if (c.criticalEdges + c.criticalVertices > 0) continue;
        const vdbi::InterfaceMesh mesh = vdbi_test::extractRaw(*c.grid).mesh;
        EXPECT_EQ(vdbi_test::compareWithPlainFaces(mesh, *c.grid), "") << c.name;
    }
    // The repaired checkerboard and the tile grid have no simple hand count; they must still
    // pass every check.
    for (const auto& grid : {vdbi_test::checkerboard2x2(), vdbi_test::activeTileGrid()}) {
        const PipelineRun r = run(*grid);
        const auto report = vdbi_test::checkMesh(r.mesh);
        EXPECT_EQ(verify(r, report), "");
        EXPECT_EQ(vdbi_test::compareMeshes(r.mesh, vdbi_test::extractRaw(*grid).mesh), "");
    }
}

TEST_F(TestExtractionProperties, testBlockClassSample)
{
    // Every 8th 2x2x2 block class (about 3,000, with and without background) yields a mesh
    // that passes every check, with Euler characteristics and volumes of the repaired labels.
    std::size_t checked = 0, failing = 0, severalOpenFans = 0;
    std::string first;
    vdbi_test::forEachBlockClass([&](std::size_t i, const vdbi_test::BlockClass& c) {
        if (i % 8 != 0) return;
        const auto grid = vdbi_test::blockGrid(c.labels);
        const PipelineRun r = run(*grid);
        const auto report = vdbi_test::checkMesh(r.mesh);
        severalOpenFans += report.sum(&vdbi_test::PatchReport::severalOpenFans);
        const std::string problem = verify(r, report);
        ++checked;
        if (!problem.empty() && failing++ == 0) {
            std::ostringstream os;
            os << "block";
            for (Label l : c.labels) os << " " << l;
            first = os.str() + ": " + problem;
        }
    });
    EXPECT_EQ(checked, 2998u);
    EXPECT_EQ(failing, 0u) << first;
    std::cout << "      " << checked << " block classes, " << failing << " failing, "
              << severalOpenFans << " patch vertices with several open fans" << std::endl;
}

TEST_F(TestExtractionProperties, testRandomVolumes)
{
    // 100 random volumes of every generator: every check, Euler characteristic and volume.
    const auto t0 = std::chrono::steady_clock::now();
    for (vdbi_test::Generator g : vdbi_test::allGenerators()) {
        std::size_t triangles = 0, failing = 0;
        std::string first;
        for (std::uint64_t seed = 5000; seed < 5100; ++seed) {
            const auto grid =
                vdbi_test::randomVolume(g, seed, 3 + int(seed % 7), 2 + int(seed % 5));
            const PipelineRun r = run(*grid);
            const auto report = vdbi_test::checkMesh(r.mesh);
            triangles += r.mesh.triangleCount();
            const std::string problem = verify(r, report);
            if (!problem.empty() && failing++ == 0) {
                first = "seed " + std::to_string(seed) + ": " + problem;
            }
        }
        EXPECT_EQ(failing, 0u) << vdbi_test::generatorName(g) << " " << first;
        std::cout << "      " << vdbi_test::generatorName(g) << ": 100 volumes, " << triangles
                  << " triangles, " << failing << " failing" << std::endl;
    }
    std::cout << "      " << secondsSince(t0) << " s" << std::endl;
}

TEST_F(TestExtractionProperties, testMengerSpongeIsPlainFaceExtraction)
{
    // menger.vox has no critical element, so nothing is subdivided and the output must be the
    // plain face extraction: 2 triangles per boundary face. The sponge is a handlebody: its
    // surface's Euler characteristic is twice that of the voxel set (V - E + F - C of the
    // cubical complex, counted independently).
    const auto grid = vdbi::readLabelVolume(vdbi_test::dataPath("menger.vox"));
    const vdbi::Result result = vdbi_test::extractRaw(*grid);
    EXPECT_EQ(result.statistics.criticalEdges + result.statistics.criticalVertices, 0u);
    EXPECT_EQ(vdbi_test::compareWithPlainFaces(result.mesh, *grid), "");
    const auto faces = vdbi_test::interfaceFacesPerPair(*grid);
    ASSERT_EQ(faces.size(), 1u);
    EXPECT_EQ(result.mesh.triangleCount(), 2 * faces.begin()->second);
    const auto report = vdbi_test::checkMesh(result.mesh);
    ASSERT_TRUE(report.ok()) << report.summary();
    const Label label = faces.begin()->first.second;
    const std::int64_t solid = vdbi_test::voxelSetEuler(*grid, label);
    EXPECT_EQ(report.labels.at(label).euler, 2 * solid);
    EXPECT_DOUBLE_EQ(report.labels.at(label).volume, double(grid->activeVoxelCount()));
    EXPECT_EQ(verify(run(*grid), report), "");
    std::cout << "      menger: " << faces.begin()->second << " faces, Euler characteristic "
              << report.labels.at(label).euler << " (genus "
              << 1 - report.labels.at(label).euler / 2
              << "), solid " << solid << std::endl;
}

namespace {

void
checkSample(const std::string& name)
{
    SCOPED_TRACE(name);
    const auto t0 = std::chrono::steady_clock::now();
    const auto grid = vdbi::readLabelVolume(vdbi_test::dataPath(name));
    const PipelineRun r = run(*grid);
    const double seconds = secondsSince(t0);
    const auto report = vdbi_test::checkMesh(r.mesh);
    EXPECT_EQ(verify(r, report), "");
    std::int64_t eulerSum = 0;
    for (const auto& l : report.labels) eulerSum += l.second.euler;
    std::cout << "      " << name << ": " << r.mesh.patches.size() << " patches, "
              << r.mesh.triangleCount() << " triangles, " << r.mesh.pointCount() << " points, "
              << report.labels.size() << " labels (sum of Euler characteristics " << eulerSum
              << "), " << report.sum(&vdbi_test::PatchReport::severalOpenFans)
              << " vertices with several open fans; pipeline " << seconds << " s, total "
              << secondsSince(t0) << " s" << std::endl;
}

} // namespace

TEST_F(TestExtractionProperties, testSampleVolumes)
{
    // The sample volumes: every check, per-label Euler characteristics of the repaired labels
    // and exact volumes.
    checkSample("chr_knight.vox");
    checkSample("monu1.vox");
    checkSample("monu16.vox");
}

TEST_F(TestExtractionProperties, testLongFrog)
{
    // The frog: 6.8 million triangles in 96 patches; every check (about 30 s).
    checkSample("frogtissue.mhd");
}

TEST_F(TestExtractionProperties, testThreadCountDoesNotChangeTheMesh)
{
    // The output is assembled in a fixed order: serial, one TBB thread and the default arena
    // give byte-identical meshes (points, triangles, patches, keys).
    std::vector<openvdb::Int32Grid::Ptr> grids = {
        vdbi::readLabelVolume(vdbi_test::dataPath("chr_knight.vox")),
        vdbi::readLabelVolume(vdbi_test::dataPath("monu16.vox")),
        vdbi_test::activeTileGrid()};
    for (vdbi_test::Generator g : vdbi_test::allGenerators()) {
        grids.push_back(vdbi_test::randomVolume(g, 77, 24, 6));
    }
    for (std::size_t i = 0; i < grids.size(); ++i) {
        SCOPED_TRACE("volume " + std::to_string(i));
        vdbi::Options serial;
        serial.repair.threaded = false;
        const vdbi::InterfaceMesh a = vdbi_test::extractRaw(*grids[i], serial).mesh;
        vdbi::InterfaceMesh b;
        tbb::task_arena arena(1);
        arena.execute([&] { b = vdbi_test::extractRaw(*grids[i]).mesh; });
        const vdbi::InterfaceMesh c = vdbi_test::extractRaw(*grids[i]).mesh;
        EXPECT_EQ(vdbi_test::compareMeshes(a, b), "");
        EXPECT_EQ(vdbi_test::compareMeshes(a, c), "");
        EXPECT_GT(a.triangleCount(), 0u);
    }
}
