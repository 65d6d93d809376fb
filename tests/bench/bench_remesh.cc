// SPDX-License-Identifier: Apache-2.0
/// @file bench/bench_remesh.cc
/// @brief Remeshing of the frog (or another sample volume) at edge lengths of 1, 2 and 4
/// voxels: wall seconds per stage (extraction, feature curves, reference surfaces,
/// remeshing, separation of crossing patches), CPU seconds of extraction + remeshing,
/// triangles and the quality figures; then where the time of remeshing and separation goes:
/// the steps of the rounds (CPU seconds summed over the patches) and the parts of separation.
/// @details Every figure is the median of --reps runs (default 3), all lengths interleaved
/// round by round so that a change of load on a shared machine hits them alike. With --check
/// the remeshed meshes also go through the independent checks of the tests (MeshChecker,
/// closeness to the raw patches, triangle intersections) and the results are printed.
///
/// Usage: bench_remesh [--reps N] [--threads T] [--iterations I] [--check] [--volume FILE]
///        [LENGTH...]  (lengths in voxels, default 1 2 4; iterations default: the library's)

#include "BenchSupport.h"
#include "support/MeshChecker.h"
#include "support/MeshIntersections.h"
#include "support/MeshQuality.h"
#include "support/TestData.h"

#include <vdbi/HugePages.h>
#include <vdbi/Interfaces.h>
#include <vdbi/LabelVolumeReader.h>
#include <vdbi/Remeshing.h>

#include <openvdb/openvdb.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

namespace {

using vdbi_bench::Clock;
using vdbi_bench::cpuSeconds;
using vdbi_bench::median;
using vdbi_bench::seconds;

/// The runs of one edge length.
struct Runs
{
    double voxels = 1.0;
    std::vector<double> extraction, curves, reference, remeshing, separation, total, cpu;
    /// Per run: the rounds' steps, then the parts of separation (RemeshStatistics).
    std::vector<std::vector<double>> steps;
    vdbi::InterfaceMesh raw, remeshed;
};

} // namespace


int
main(int argc, char** argv)
{
    vdbi::restartWithHugePages(argv); // as the CLI does: see HugePages.h
    int reps = 3, threads = 0, iterations = vdbi::RemeshOptions().iterations;
    bool check = false;
    std::string volume = vdbi_test::dataPath("frogtissue.mhd");
    std::vector<double> lengths;
    auto usage = [&] {
        std::fprintf(stderr, "usage: %s [--reps N] [--threads T] [--iterations I] [--check] "
                     "[--volume FILE] [LENGTH...]  (lengths in voxels, > 0; default 1 2 4)\n",
                     argv[0]);
        return 2;
    };
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "-h") || !std::strcmp(argv[i], "--help")) return usage(), 0;
        if (!std::strcmp(argv[i], "--reps") && i + 1 < argc) reps = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--iterations") && i + 1 < argc) {
            iterations = std::atoi(argv[++i]);
        } else if (!std::strcmp(argv[i], "--check")) check = true;
        else if (!std::strcmp(argv[i], "--volume") && i + 1 < argc) volume = argv[++i];
        else {
            char* end = nullptr;
            const double length = std::strtod(argv[i], &end);
            if (end == argv[i] || *end != '\0' || !(length > 0.0)) return usage();
            lengths.push_back(length);
        }
    }
    if (reps < 1 || iterations < 0) return usage();
    if (lengths.empty()) lengths = {1.0, 2.0, 4.0};
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0) {
        limit.reset(new tbb::global_control(tbb::global_control::max_allowed_parallelism,
                                            std::size_t(threads)));
    }

    openvdb::initialize();
    const openvdb::Int32Grid::Ptr grid = vdbi::readLabelVolume(volume);
    const openvdb::Vec3d voxel = grid->voxelSize();
    std::printf("heap: %s\n", vdbi_bench::heapPages().c_str());
    std::printf("%s: voxel %g x %g x %g, %d iterations, %d runs per length%s\n",
                volume.c_str(), voxel[0], voxel[1], voxel[2], iterations, reps,
                threads > 0 ? "" : ", all threads");

    std::vector<Runs> runs(lengths.size());
    for (std::size_t l = 0; l < lengths.size(); ++l) runs[l].voxels = lengths[l];
    vdbi::Options rawExtraction;
    rawExtraction.remesh = false; // remeshed below, stage by stage
    for (int rep = 0; rep < reps; ++rep) {
        for (Runs& r : runs) {
            const double cpu0 = cpuSeconds();
            const Clock::time_point t0 = Clock::now();
            vdbi::InterfaceMesh raw = vdbi::extractInterfaces(*grid, rawExtraction).mesh;
            const Clock::time_point t1 = Clock::now();
            vdbi::RemeshOptions options;
            options.edgeLength = r.voxels * voxel[0];
            options.voxelSize = voxel;
            options.iterations = iterations;
            vdbi::RemeshStatistics stats;
            vdbi::InterfaceMesh out = vdbi::remeshPatches(raw, options, &stats);
            const Clock::time_point t2 = Clock::now();
            r.cpu.push_back(cpuSeconds() - cpu0);
            r.extraction.push_back(seconds(t0, t1));
            r.curves.push_back(stats.curveSeconds);
            r.reference.push_back(stats.referenceSeconds);
            r.remeshing.push_back(stats.remeshingSeconds);
            r.separation.push_back(stats.separationSeconds);
            const vdbi::RemeshStepSeconds& round = stats.roundSteps;
            r.steps.push_back({round.split, round.collapse, round.flip, round.relax,
                round.project, round.sharpFans, stats.separationCycleSeconds,
                stats.pullSeconds, stats.fanShapingSeconds, stats.finalCollapseSeconds,
                stats.checkSeconds});
            r.total.push_back(seconds(t0, t2));
            r.raw = std::move(raw);
            r.remeshed = std::move(out);
        }
    }

    std::printf("\n%-8s %10s %8s %10s %10s %10s %10s %10s\n", "length", "extraction",
                "curves", "reference", "remeshing", "separation", "total wall", "total CPU");
    for (const Runs& r : runs) {
        std::printf("%-8g %10.2f %8.2f %10.2f %10.2f %10.2f %10.2f %10.2f\n", r.voxels,
                    median(r.extraction), median(r.curves), median(r.reference),
                    median(r.remeshing), median(r.separation), median(r.total), median(r.cpu));
    }
    std::printf("\nrounds' steps, CPU seconds summed over the patches | parts of separation, "
                "wall seconds\n%-8s", "length");
    const char* stepNames[] = {"split", "collapse", "flip", "relax", "project", "sharp fans",
                               "| cycles", "pulls", "fan shape", "collapses", "checks"};
    for (const char* name : stepNames) std::printf(" %10s", name);
    std::printf("\n");
    for (const Runs& r : runs) {
        std::printf("%-8g", r.voxels);
        for (std::size_t k = 0; k < std::size(stepNames); ++k) {
            std::vector<double> values;
            for (const std::vector<double>& run : r.steps) values.push_back(run[k]);
            std::printf(" %10.2f", median(values));
        }
        std::printf("\n");
    }
    std::printf("\n");
    for (const Runs& r : runs) {
        const vdbi_test::MeshQuality q = vdbi_test::measureMeshQuality(r.remeshed,
                                                                       r.voxels * voxel[0]);
        std::printf("%g voxels: %zu raw -> %s\n", r.voxels, r.raw.triangles.size(),
                    q.summary().c_str());
    }
    if (!check) return 0;
    std::printf("\n");
    for (const Runs& r : runs) {
        const vdbi_test::MeshReport report = vdbi_test::checkMesh(r.remeshed, false);
        const vdbi_test::Closeness c = vdbi_test::measureCloseness(r.raw, r.remeshed, voxel);
        const auto found = vdbi_test::findSelfIntersections(r.remeshed, r.voxels * voxel[0],
                                                            std::size_t(-1));
        // Patch of every triangle, to tell crossings within one patch from those between two.
        std::vector<std::size_t> patchOf(r.remeshed.triangles.size());
        for (std::size_t p = 0; p < r.remeshed.patches.size(); ++p) {
            const vdbi::InterfacePatch& patch = r.remeshed.patches[p];
            std::fill_n(patchOf.begin() + patch.firstTriangle, patch.triangleCount, p);
        }
        std::size_t withinPatch = 0;
        for (const auto& pair : found) withinPatch += patchOf[pair.first] == patchOf[pair.second];
        std::printf("%g voxels: checker %s; closeness: vertex->raw %.3f, face centre->remeshed "
                    "%.3f (raw centroids %.3f) voxels; intersections (%zu within one patch): "
                    "%s\n", r.voxels, report.ok() ? "ok" : report.summary().c_str(),
                    c.vertexToRaw, c.faceCentreToOutput, c.rawToOutput, withinPatch,
                    found.empty() ? "none" :
                    vdbi_test::describeIntersections(r.remeshed, found).c_str());
    }
    return 0;
}
