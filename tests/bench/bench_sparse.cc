// SPDX-License-Identifier: Apache-2.0
/// @file bench/bench_sparse.cc
/// @brief Checks the claim "cost grows with the stored voxels, not with the bounding box".
/// @details Two small blobs of random labels (balls of radius 6, seeded, with many critical
/// edges and vertices) are placed next to each other, then 10^6 and 10^8 voxels apart, on one
/// and on all three axes. The repair and extraction stages run on each placement; the program
/// prints the median seconds per stage, the memory of the grids and the mesh, the peak RSS,
/// and the ratio of every placement to the adjacent one. All should be 1 within noise.
///
/// Memory: every placement runs once in a forked child of its own, so that its peak RSS
/// (ru_maxrss of the child, and VmHWM per stage after resetting it through
/// /proc/self/clear_refs) is its own. Times: one more child runs all placements in rounds,
/// interleaved, so that the load of a shared machine hits them alike. The parent never starts
/// TBB itself.
///
/// Usage: bench_sparse [--reps N] [--threads T]   (defaults: 11 rounds, 2 threads)

#include "BenchSupport.h"

#include <vdbi/CriticalElements.h>
#include <vdbi/Fattening.h>
#include <vdbi/HugePages.h>
#include <vdbi/InterfaceExtraction.h>
#include <vdbi/LabelGrid.h>
#include <vdbi/LabelWindow.h>

#include <openvdb/openvdb.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace {

using openvdb::Coord;
using vdbi_bench::Clock;
using vdbi_bench::heapPages;
using vdbi_bench::loadAverage;
using vdbi_bench::median;
using vdbi_bench::MemKb;
using vdbi_bench::meshBytes;
using vdbi_bench::ratio;
using vdbi_bench::readMem;
using vdbi_bench::resetPeak;
using vdbi_bench::seconds;

/// A ball of radius 6 around @a centre, each voxel a random label 1..4 (seeded).
void
addBlob(openvdb::Int32Tree& tree, const Coord& centre, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> label(1, 4);
    openvdb::tree::ValueAccessor<openvdb::Int32Tree> acc(tree);
    const int r = 6;
    for (int x = -r; x <= r; ++x) for (int y = -r; y <= r; ++y) for (int z = -r; z <= r; ++z) {
        if (x * x + y * y + z * z > r * r) continue;
        acc.setValueOn(centre.offsetBy(x, y, z), label(rng));
    }
}

struct Placement
{
    const char* name;
    Coord a, b; ///< the two blob centres
};

// The blobs sit inside one node of every tree level (centre 100: voxels 94..106 of the
// internal node [0, 128)), and every offset is a multiple of 4096, the extent of the top
// internal nodes: each blob meets the tree the same way in every placement. Only the adjacent
// pair shares nodes (and the leaf column x 104..111); from "4096 apart" on, the trees of all
// placements have the same number of nodes of every level, only their root keys differ.
constexpr int C = 100;
constexpr int E6 = 244 * 4096;   //     999,424 ~ 10^6
constexpr int E8 = 24414 * 4096; //  99,999,744 ~ 10^8
const Placement PLACEMENTS[] = {
    {"adjacent (gap 3)", Coord(C), Coord(C + 16, C, C)},
    {"4096 apart on x", Coord(C), Coord(C + 4096, C, C)},
    {"~10^6 apart on x", Coord(C), Coord(C + E6, C, C)},
    {"~10^6 apart x,y,z", Coord(C), Coord(C + E6)},
    {"~10^8 apart x,y,z", Coord(C), Coord(C + E8)},
    {"-10^8 and +10^8 x,y,z", Coord(C - E8), Coord(C + E8)},
};
constexpr std::size_t PLACEMENT_COUNT = sizeof(PLACEMENTS) / sizeof(PLACEMENTS[0]);

/// Sizes and memory of one placement, measured in a child process of its own.
struct MemoryResult
{
    long long inputVoxels = 0, leaves = 0, blocks = 0;
    long long criticalEdges = 0, criticalVertices = 0;
    long long subdividedVoxels = 0, relabelledSubvoxels = 0;
    long long triangles = 0, vertices = 0, patches = 0;
    long long coarseBytes = 0, fineBytes = 0, maskBytes = 0, meshBytes = 0;
    long criticalPeakKb = -1, fatteningPeakKb = -1, extractionPeakKb = -1;
    /// Peak RSS of the child: VmHWM before the first reset, then after every stage (the
    /// resets make ru_maxrss report only the peak since the last one).
    long maxRssKb = 0;
    bool ok = false;
};

/// Median seconds of every stage of one placement.
struct TimeResult
{
    double critical = 0, fattening = 0, extraction = 0, total = 0;
};

openvdb::Int32Grid::Ptr
makeGrid(const Placement& p)
{
    openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(0);
    addBlob(grid->tree(), p.a, 1);
    addBlob(grid->tree(), p.b, 2);
    return grid;
}

/// One run of the three stages, with the peak RSS growth of each (VmHWM after clear_refs).
MemoryResult
measureMemory(const Placement& p)
{
    MemoryResult r;
    const openvdb::Int32Grid::Ptr grid = makeGrid(p);
    r.inputVoxels = (long long)grid->activeVoxelCount();
    r.leaves = (long long)grid->tree().leafCount();
    const vdbi::RepairOptions options;
    const openvdb::Int32Grid::ConstPtr labels = vdbi::voxelizedLabels(*grid);
    r.blocks = (long long)vdbi::blockOrigins(labels->tree(), true).size();

    r.maxRssKb = readMem().hwm;
    MemKb before;
    // Peak growth of the stage that just ran; keeps the process's overall peak in maxRssKb.
    auto peakSince = [&](bool canPeak, long& out) {
        const MemKb after = readMem();
        r.maxRssKb = std::max(r.maxRssKb, after.hwm);
        if (canPeak) out = after.hwm - before.rss;
    };
    bool canPeak = resetPeak();
    before = readMem();
    const vdbi::CriticalElements elements = vdbi::findCriticalElements(*labels, options);
    peakSince(canPeak, r.criticalPeakKb);

    canPeak = resetPeak();
    before = readMem();
    const vdbi::RefinedLabels refined = vdbi::fattenCriticalElements(labels, elements, options);
    peakSince(canPeak, r.fatteningPeakKb);

    canPeak = resetPeak();
    before = readMem();
    const vdbi::InterfaceMesh mesh = vdbi::extractInterfacePatches(refined);
    peakSince(canPeak, r.extractionPeakKb);

    r.criticalEdges = (long long)elements.edges.size();
    r.criticalVertices = (long long)elements.vertices.size();
    r.subdividedVoxels = (long long)refined.subdivided->activeVoxelCount();
    r.relabelledSubvoxels = (long long)refined.fine->activeVoxelCount();
    r.triangles = (long long)mesh.triangles.size();
    r.vertices = (long long)mesh.points.size();
    r.patches = (long long)mesh.patches.size();
    r.coarseBytes = (long long)labels->memUsage();
    r.fineBytes = (long long)refined.fine->memUsage();
    r.maskBytes = (long long)refined.subdivided->memUsage();
    r.meshBytes = meshBytes(mesh);
    r.ok = true;
    return r;
}

/// @a reps rounds over all placements, interleaved so that a change of the machine's load
/// hits every placement alike, each round starting at another placement so that none always
/// runs on the heap left by the same predecessor; medians per stage and placement.
std::vector<TimeResult>
measureTimes(int reps)
{
    std::vector<openvdb::Int32Grid::Ptr> grids;
    for (const Placement& p : PLACEMENTS) grids.push_back(makeGrid(p));
    const vdbi::RepairOptions options;

    std::vector<std::vector<double>> crit(PLACEMENT_COUNT), fat(PLACEMENT_COUNT),
        ext(PLACEMENT_COUNT), total(PLACEMENT_COUNT);
    for (int rep = -1; rep < reps; ++rep) { // rep -1 warms up caches and the TBB pool
        for (std::size_t m = 0; m < PLACEMENT_COUNT; ++m) {
            const std::size_t n = (m + std::size_t(rep + 1)) % PLACEMENT_COUNT;
            const openvdb::Int32Grid::ConstPtr labels = vdbi::voxelizedLabels(*grids[n]);
            const auto t0 = Clock::now();
            const vdbi::CriticalElements elements = vdbi::findCriticalElements(*labels, options);
            const auto t1 = Clock::now();
            const vdbi::RefinedLabels refined =
                vdbi::fattenCriticalElements(labels, elements, options);
            const auto t2 = Clock::now();
            const vdbi::InterfaceMesh mesh = vdbi::extractInterfacePatches(refined);
            const auto t3 = Clock::now();
            if (rep < 0) continue;
            crit[n].push_back(seconds(t0, t1));
            fat[n].push_back(seconds(t1, t2));
            ext[n].push_back(seconds(t2, t3));
            total[n].push_back(seconds(t0, t3));
        }
    }
    std::vector<TimeResult> r(PLACEMENT_COUNT);
    for (std::size_t n = 0; n < PLACEMENT_COUNT; ++n) {
        r[n] = {median(crit[n]), median(fat[n]), median(ext[n]), median(total[n])};
    }
    return r;
}

} // namespace

int
main(int argc, char** argv)
{
    vdbi::restartWithHugePages(argv); // as the CLI does: see HugePages.h
    int reps = 11, threads = 2;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--reps" && i + 1 < argc) reps = std::max(1, std::atoi(argv[++i]));
        else if (arg == "--threads" && i + 1 < argc) threads = std::max(1, std::atoi(argv[++i]));
        else {
            std::fprintf(stderr, "usage: %s [--reps N] [--threads T]\n", argv[0]);
            return 2;
        }
    }

    std::printf("bench_sparse: two random-label balls (r = 6, labels 1..4, seeds 1 and 2), "
        "%d TBB thread(s)\nload average before: %s; heap: %s\n\n", threads,
        loadAverage().c_str(), heapPages().c_str());

    // Memory: every placement in a process of its own.
    std::vector<MemoryResult> mem(PLACEMENT_COUNT);
    bool ok = true;
    for (std::size_t n = 0; n < PLACEMENT_COUNT; ++n) {
        long rss = 0;
        MemoryResult r;
        const bool done = vdbi_bench::inChild([&] {
            tbb::global_control control(tbb::global_control::max_allowed_parallelism,
                std::size_t(threads));
            return measureMemory(PLACEMENTS[n]);
        }, r, rss);
        r.ok = done && r.ok;
        mem[n] = r;
        ok = ok && r.ok;
    }
    // Times: all placements in one process, interleaved.
    using Times = std::array<TimeResult, PLACEMENT_COUNT>;
    Times times{};
    long timingRss = 0;
    const bool timed = vdbi_bench::inChild([&] {
        tbb::global_control control(tbb::global_control::max_allowed_parallelism,
            std::size_t(threads));
        const std::vector<TimeResult> v = measureTimes(reps);
        Times t{};
        std::copy(v.begin(), v.end(), t.begin());
        return t;
    }, times, timingRss);
    ok = ok && timed;

    std::printf("median of %d runs per placement (rounds over all placements, interleaved, "
        "rotated, after one warm-up round); ms\n", reps);
    std::printf("%-22s %8s %8s %8s %8s | %6s %5s %6s %6s %6s %6s %7s %7s %7s\n", "placement",
        "crit", "fatten", "extract", "total", "voxels", "leafs", "blocks", "c.edge", "c.vert",
        "subdiv", "fine", "tris", "verts");
    for (std::size_t n = 0; n < PLACEMENT_COUNT; ++n) {
        const MemoryResult& m = mem[n];
        const TimeResult& t = times[n];
        std::printf("%-22s %8.3f %8.3f %8.3f %8.3f | %6lld %5lld %6lld %6lld %6lld %6lld %7lld "
            "%7lld %7lld%s\n", PLACEMENTS[n].name, 1e3 * t.critical, 1e3 * t.fattening,
            1e3 * t.extraction, 1e3 * t.total, m.inputVoxels, m.leaves, m.blocks, m.criticalEdges,
            m.criticalVertices, m.subdividedVoxels, m.relabelledSubvoxels, m.triangles,
            m.vertices, m.ok && timed ? "" : "  FAILED");
    }

    std::printf("\nmemory: bytes (memUsage() of the voxelized input, the fine grid and the "
        "mask; vector bytes of the mesh);\npeak RSS growth per stage in kB (VmHWM after "
        "clear_refs, minus RSS before); maxrss: peak RSS of the placement's own process in kB\n");
    std::printf("%-22s %9s %9s %9s %9s | %7s %7s %7s | %9s\n", "placement", "input", "fine",
        "mask", "mesh", "crit", "fatten", "extract", "maxrss");
    for (std::size_t n = 0; n < PLACEMENT_COUNT; ++n) {
        const MemoryResult& r = mem[n];
        std::printf("%-22s %9lld %9lld %9lld %9lld | %7ld %7ld %7ld | %9ld\n",
            PLACEMENTS[n].name, r.coarseBytes, r.fineBytes, r.maskBytes, r.meshBytes,
            r.criticalPeakKb, r.fatteningPeakKb, r.extractionPeakKb, r.maxRssKb);
    }

    for (std::size_t base : {std::size_t(0), std::size_t(1)}) {
        std::printf("\nratio to \"%s\" (1.00: independent of the distance)\n",
            PLACEMENTS[base].name);
        std::printf("%-22s %8s %8s %8s %8s | %8s %8s %8s %8s %8s\n", "placement", "crit",
            "fatten", "extract", "total", "input", "fine", "mask", "mesh", "maxrss");
        const TimeResult& bt = times[base];
        const MemoryResult& bm = mem[base];
        for (std::size_t n = base + 1; n < PLACEMENT_COUNT; ++n) {
            const TimeResult& t = times[n];
            const MemoryResult& m = mem[n];
            std::printf("%-22s %8.2f %8.2f %8.2f %8.2f | %8.2f %8.2f %8.2f %8.2f %8.2f\n",
                PLACEMENTS[n].name, ratio(t.critical, bt.critical),
                ratio(t.fattening, bt.fattening), ratio(t.extraction, bt.extraction),
                ratio(t.total, bt.total), ratio(double(m.coarseBytes), double(bm.coarseBytes)),
                ratio(double(m.fineBytes), double(bm.fineBytes)),
                ratio(double(m.maskBytes), double(bm.maskBytes)),
                ratio(double(m.meshBytes), double(bm.meshBytes)),
                ratio(double(m.maxRssKb), double(bm.maxRssKb)));
        }
    }
    std::printf("\nru_maxrss of the timing process (all placements): %ld kB\n", timingRss);
    std::printf("load average after: %s\n", loadAverage().c_str());
    return ok ? 0 : 1;
}
