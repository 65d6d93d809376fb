// SPDX-License-Identifier: Apache-2.0
/// @file bench/bench_random_remesh.cc
/// @brief How often remeshing keeps each promise of its output on seeded random volumes
/// (support/RandomVolumes.h), per kind of volume: the figures of robustness beyond the sample
/// volumes, where the tests assert every promise.
/// @details For every seed and kind, a volume of 8 + seed % 9 voxels per side with 2 + seed % 5
/// labels is extracted and remeshed at every target length (voxels). Each result goes
/// through the independent checks of the tests: the checker (every patch a manifold, every
/// label closed and oriented) with the raw extraction's Euler characteristic per label,
/// triangles with area, no intersecting triangles, closeness both ways within one voxel.
/// Every run that breaks one is listed (kind, seed, target, what), then a table of counts.
/// Noise volumes (a label per voxel drawn at random) are the slowest by far.
///
/// Usage: bench_random_remesh [--seeds FIRST LAST] [--threads T] [--kinds all|smooth]
///        [LENGTH...]   (default seeds 1 20, lengths 1.5 2 3, kinds all)

#include "support/MeshChecker.h"
#include "support/MeshIntersections.h"
#include "support/MeshQuality.h"
#include "support/RandomVolumes.h"
#include "support/RawExtraction.h"

#include <vdbi/Remeshing.h>

#include <openvdb/openvdb.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

namespace {

/// Runs per kind of volume, and how many broke each promise.
struct Tally
{
    std::size_t runs = 0, checker = 0, topology = 0, area = 0, crossings = 0, closeness = 0,
                threw = 0;
};

/// What @a out (remeshed to @a target, world units) breaks of the promises, "" if nothing.
std::string
brokenPromises(const vdbi::InterfaceMesh& raw, const vdbi::InterfaceMesh& out,
               const vdbi_test::MeshReport& before, double target,
               const openvdb::Vec3d& voxel, Tally& tally)
{
    std::string what;
    const vdbi_test::MeshReport after = vdbi_test::checkMesh(out, false);
    if (!after.ok()) {
        ++tally.checker;
        what += " checker";
    }
    bool sameTopology = out.patches.size() == raw.patches.size();
    for (const vdbi::InterfacePatch& p : out.patches) sameTopology &= p.triangleCount > 0;
    for (const auto& [label, report] : before.labels) {
        const auto it = after.labels.find(label);
        sameTopology &= it != after.labels.end() && it->second.closed()
            && it->second.euler == report.euler;
    }
    if (!sameTopology) {
        ++tally.topology;
        what += " topology";
    }
    const std::size_t withoutArea = vdbi_test::countTrianglesWithoutArea(out);
    if (withoutArea > 0) {
        ++tally.area;
        what += " " + std::to_string(withoutArea) + " without area";
    }
    const auto found = vdbi_test::findSelfIntersections(out, target);
    if (!found.empty()) {
        ++tally.crossings;
        what += " " + std::to_string(found.size()) + " crossing pairs";
    }
    const vdbi_test::Closeness c = vdbi_test::measureCloseness(raw, out, voxel);
    if (c.vertexToRaw > 1.0 || c.faceCentreToOutput > 1.0) {
        ++tally.closeness;
        char text[80];
        std::snprintf(text, sizeof(text), " closeness %.3f / %.3f", c.vertexToRaw,
                      c.faceCentreToOutput);
        what += text;
    }
    return what;
}

} // namespace


int
main(int argc, char** argv)
{
    std::uint64_t first = 1, last = 20;
    int threads = 0;
    bool smoothOnly = false;
    std::vector<double> lengths;
    auto usage = [&] {
        std::fprintf(stderr, "usage: %s [--seeds FIRST LAST] [--threads T] "
                     "[--kinds all|smooth] [LENGTH...]  (lengths in voxels, > 0)\n", argv[0]);
        return 2;
    };
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "-h") || !std::strcmp(argv[i], "--help")) return usage(), 0;
        if (!std::strcmp(argv[i], "--seeds") && i + 2 < argc) {
            first = std::strtoull(argv[++i], nullptr, 10);
            last = std::strtoull(argv[++i], nullptr, 10);
        } else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) {
            threads = std::atoi(argv[++i]);
        } else if (!std::strcmp(argv[i], "--kinds") && i + 1 < argc) {
            const std::string kinds = argv[++i];
            if (kinds != "all" && kinds != "smooth") return usage();
            smoothOnly = kinds == "smooth";
        } else {
            char* end = nullptr;
            const double length = std::strtod(argv[i], &end);
            if (end == argv[i] || *end != '\0' || !(length > 0.0)) return usage();
            lengths.push_back(length);
        }
    }
    if (first < 1 || last < first) return usage();
    if (lengths.empty()) lengths = {1.5, 2.0, 3.0};
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0) {
        limit.reset(new tbb::global_control(tbb::global_control::max_allowed_parallelism,
                                            std::size_t(threads)));
    }

    openvdb::initialize();
    std::vector<vdbi_test::Generator> kinds;
    for (const vdbi_test::Generator g : vdbi_test::allGenerators()) {
        const bool noise = g == vdbi_test::Generator::Noise
            || g == vdbi_test::Generator::BiasedNoise;
        if (!(smoothOnly && noise)) kinds.push_back(g);
    }
    std::vector<Tally> tallies(kinds.size());
    for (std::uint64_t seed = first; seed <= last; ++seed) {
        const int size = 8 + int(seed % 9), labels = 2 + int(seed % 5);
        for (std::size_t k = 0; k < kinds.size(); ++k) {
            const auto grid = vdbi_test::randomVolume(kinds[k], seed, size, labels);
            const vdbi::InterfaceMesh raw = vdbi_test::extractRaw(*grid).mesh;
            if (raw.triangles.empty()) continue;
            const vdbi_test::MeshReport before = vdbi_test::checkMesh(raw);
            for (const double target : lengths) {
                Tally& tally = tallies[k];
                ++tally.runs;
                std::string what;
                try {
                    vdbi::RemeshOptions options;
                    options.voxelSize = grid->voxelSize();
                    options.edgeLength = target * options.voxelSize[0];
                    what = brokenPromises(raw, vdbi::remeshPatches(raw, options), before,
                                          options.edgeLength, options.voxelSize, tally);
                } catch (const std::exception& e) {
                    ++tally.threw;
                    what = std::string(" threw: ") + e.what();
                }
                if (!what.empty()) {
                    std::printf("%s seed %llu (%d voxels per side, %d labels) at %g voxels:%s\n",
                                vdbi_test::generatorName(kinds[k]).c_str(),
                                static_cast<unsigned long long>(seed), size, labels, target,
                                what.c_str());
                    std::fflush(stdout);
                }
            }
        }
    }
    std::printf("\nseeds %llu..%llu, lengths", static_cast<unsigned long long>(first),
                static_cast<unsigned long long>(last));
    for (const double l : lengths) std::printf(" %g", l);
    std::printf(" voxels: runs, and runs that broke each promise\n");
    std::printf("%-14s %6s %8s %9s %6s %10s %10s %6s\n", "kind", "runs", "checker", "topology",
                "area", "crossings", "closeness", "threw");
    for (std::size_t k = 0; k < kinds.size(); ++k) {
        const Tally& t = tallies[k];
        std::printf("%-14s %6zu %8zu %9zu %6zu %10zu %10zu %6zu\n",
                    vdbi_test::generatorName(kinds[k]).c_str(), t.runs, t.checker, t.topology,
                    t.area, t.crossings, t.closeness, t.threw);
    }
    return 0;
}
