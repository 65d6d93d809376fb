// SPDX-License-Identifier: Apache-2.0
/// @file bench/bench_scale.cc
/// @brief Checks that time and memory grow with the labelled voxels only: k copies of the frog
/// scattered over an index box no dense tool can allocate, for k = 1, 2, 4, 8, 16.
/// @details Copy c of the frog has its labels shifted by 30c (the frog's labels are 0..29), so
/// copies share no label, and sits at its own offset: copy 0 at the frog's own place, copy 1
/// at (span, span, span), so that from k = 2 on the volume spans more than @a span voxels
/// along every axis, the others at seeded random offsets in [0, span]^3 at least 16 voxels
/// away from every earlier copy (copies never touch: the work of every copy is the frog's).
/// The offsets are not multiples of the leaf size, so every copy meets the tree differently.
/// The copies of k are those of 2k's first half.
///
/// For every k, repair + extraction (critical elements, fattening, extraction; the input is
/// voxelized beforehand) with TBB limited to 1 and to 2 threads. Printed: the median seconds,
/// seconds and bytes per labelled voxel, their ratio to k = 1 (target: flat within 1.3x), the
/// speedup of 2 threads over 1, the peak RSS against (input tree + output mesh) (target at
/// most 3x), and the bounding box, to compare with what a dense volume of it would need.
///
/// Memory: every k runs in a forked child of its own: it builds the volume, returns freed
/// heap to the system, resets VmHWM (/proc/self/clear_refs) and runs once with 1 thread and
/// once with 2 threads, each after a reset, so the peaks are that k's. Times: one more child
/// builds all volumes and runs them in rounds, interleaved (k and thread count), each round
/// starting at another volume, after one warm-up round, so that the load of a shared machine
/// hits them alike. The parent never starts TBB itself.
///
/// On a virtual machine, memory new to the process can be new to the host too, and the host
/// backing it on first touch can cost more than the run's own work (README, Benchmarks). So
/// that every timed run finds its memory in the same state, whatever ran before it (a smaller
/// k, or the same k with the other thread count), each timed run is preceded by touching and
/// freeing more memory than it will use. The memory children do the same before each of
/// their runs, so these runs still write only pages new to the process (their heap is
/// trimmed first) but no longer depend on what the host did with them.
///
/// Usage: bench_scale [--reps N] [--span S] [--seed X] [--max-k K]
///        (defaults: 5 rounds, span 100000, seed 1, K 16)

#include "BenchSupport.h"
#include "support/TestData.h"

#include <vdbi/CriticalElements.h>
#include <vdbi/Fattening.h>
#include <vdbi/HugePages.h>
#include <vdbi/InterfaceExtraction.h>
#include <vdbi/LabelGrid.h>
#include <vdbi/LabelVolumeReader.h>

#include <openvdb/openvdb.h>

#include <tbb/global_control.h>

#include <sys/mman.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

using openvdb::Coord;
using openvdb::CoordBBox;
using vdbi_bench::Clock;
using vdbi_bench::heapPages;
using vdbi_bench::loadAverage;
using vdbi_bench::median;
using vdbi_bench::MemKb;
using vdbi_bench::ratio;
using vdbi_bench::readMem;
using vdbi_bench::resetPeak;
using vdbi_bench::seconds;

constexpr int COPY_COUNTS[] = {1, 2, 4, 8, 16};
constexpr int CASE_COUNT = 5;
constexpr int THREAD_COUNTS[] = {1, 2};
/// Labels of copy c are the frog's plus c * LABEL_STRIDE (the frog's labels are 0..29).
constexpr int LABEL_STRIDE = 30;
/// Empty voxels between the bounding boxes of any two copies.
constexpr int GAP = 16;

/// Bytes per labelled voxel that a run of repair + extraction may take: above its peak
/// growth (about 270 at every k on the frog copies).
constexpr std::size_t WARM_BYTES_PER_VOXEL = 400;

/// Touches fresh memory for a run over @a labelledVoxels (WARM_BYTES_PER_VOXEL each), one
/// write per page, and gives it back, so that the run's allocations find pages the host
/// already backs.
void
warmMemory(openvdb::Index64 labelledVoxels)
{
    const std::size_t bytes = WARM_BYTES_PER_VOXEL * std::size_t(labelledVoxels);
    void* block = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS,
                       -1, 0);
    if (block == MAP_FAILED) return; // only a worse measurement: nothing to fail for
    madvise(block, bytes, MADV_HUGEPAGE); // the pages the heap asks for (HugePages.h)
    auto* bytesOf = static_cast<volatile char*>(block);
    for (std::size_t b = 0; b < bytes; b += 4096) bytesOf[b] = 1;
    munmap(block, bytes);
}

/// The settings of one invocation.
struct Settings
{
    int reps = 5;
    int span = 100000;
    unsigned seed = 1;
    int maxCopies = 16;
};

/// The offsets of the first @a count copies of a volume with bounding box @a box (see the file
/// comment): the same sequence for every count.
std::vector<Coord>
copyOffsets(const CoordBBox& box, int count, const Settings& settings)
{
    std::vector<Coord> offsets;
    std::vector<CoordBBox> placed;
    std::mt19937 rng(settings.seed);
    std::uniform_int_distribution<int> position(0, settings.span);
    auto fits = [&](const Coord& offset) {
        CoordBBox b(box.min() + offset, box.max() + offset);
        b.expand(GAP);
        for (const CoordBBox& other : placed) if (b.hasOverlap(other)) return false;
        return true;
    };
    for (int c = 0; c < count; ++c) {
        Coord offset = c == 1 ? Coord(settings.span) : Coord(0);
        for (int attempt = 0; !fits(offset) && attempt < 100000; ++attempt) {
            offset = Coord(position(rng), position(rng), position(rng));
        }
        if (!fits(offset)) throw std::runtime_error("the span is too small for the copies");
        offsets.push_back(offset);
        placed.emplace_back(box.min() + offset, box.max() + offset);
    }
    return offsets;
}

/// @a count copies of the frog, labels shifted and placed as the file comment says.
openvdb::Int32Grid::Ptr
makeVolume(int count, const Settings& settings)
{
    const openvdb::Int32Grid::Ptr frogGrid = vdbi::readLabelVolume(
        vdbi_test::dataPath("frogtissue.mhd"));
    const openvdb::Int32Grid::ConstPtr frog = vdbi::voxelizedLabels(*frogGrid);
    const vdbi::Label background = frog->background();
    const std::vector<vdbi::Label> labels = vdbi::collectLabels(*frog);
    if (labels.front() < background || labels.back() >= background + LABEL_STRIDE) {
        throw std::runtime_error("the frog's labels are not 0..29");
    }

    openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(background);
    grid->setTransform(frog->transform().copy());
    openvdb::tree::ValueAccessor<openvdb::Int32Tree> out(grid->tree());
    const std::vector<Coord> offsets = copyOffsets(frog->evalActiveVoxelBoundingBox(), count,
        settings);
    for (int c = 0; c < count; ++c) {
        const Coord& offset = offsets[std::size_t(c)];
        for (auto v = frog->cbeginValueOn(); v; ++v) {
            const vdbi::Label label = *v == background ? background : *v + c * LABEL_STRIDE;
            out.setValueOn(v.getCoord() + offset, label);
        }
    }
    return grid;
}

/// Repair + extraction of @a labels; the seconds of its three stages and their sum.
struct RunSeconds
{
    double critical = 0, fattening = 0, extraction = 0, total = 0;
};

RunSeconds
repairAndExtract(const openvdb::Int32Grid::ConstPtr& labels, vdbi::InterfaceMesh* keep = nullptr)
{
    RunSeconds r;
    const vdbi::RepairOptions options;
    const auto t0 = Clock::now();
    const vdbi::CriticalElements elements = vdbi::findCriticalElements(*labels, options);
    const auto t1 = Clock::now();
    const vdbi::RefinedLabels refined = vdbi::fattenCriticalElements(labels, elements, options);
    const auto t2 = Clock::now();
    vdbi::InterfaceMesh mesh = vdbi::extractInterfacePatches(refined);
    const auto t3 = Clock::now();
    r.critical = seconds(t0, t1);
    r.fattening = seconds(t1, t2);
    r.extraction = seconds(t2, t3);
    r.total = seconds(t0, t3);
    if (keep) *keep = std::move(mesh);
    return r;
}

/// What the memory child of one k sends back.
struct MemoryResult
{
    long long labelledVoxels = 0, leaves = 0, labels = 0;
    long long triangles = 0, vertices = 0, patches = 0;
    long long inputBytes = 0, meshBytes = 0;
    std::array<long long, 3> boxMin{}, boxDim{};
    long emptyKb = 0;    ///< RSS of the process before it built the volume
    long volumeKb = 0;   ///< RSS with the volume built (and the frog released)
    /// Per thread count: VmHWM during repair + extraction (absolute), and the growth over the
    /// RSS before it.
    std::array<long, 2> peakKb{}, growthKb{};
    /// Per thread count: seconds of that single run, after the heap was trimmed (every page it
    /// writes is new to the process), beside the timing process's medians of repeated runs.
    std::array<double, 2> firstRunSeconds{};
    bool ok = false;
};

MemoryResult
measureMemory(int count, const Settings& settings)
{
    MemoryResult r;
    r.emptyKb = readMem().rss;
    const openvdb::Int32Grid::ConstPtr labels = vdbi::voxelizedLabels(
        *makeVolume(count, settings));
    resetPeak();
    r.volumeKb = readMem().rss;
    r.labelledVoxels = (long long)labels->activeVoxelCount();
    r.leaves = (long long)labels->tree().leafCount();
    r.inputBytes = (long long)labels->memUsage();
    const CoordBBox box = labels->evalActiveVoxelBoundingBox();
    for (int a = 0; a < 3; ++a) {
        r.boxMin[std::size_t(a)] = box.min()[a];
        r.boxDim[std::size_t(a)] = box.dim()[a];
    }
    for (std::size_t t = 0; t < 2; ++t) {
        tbb::global_control control(tbb::global_control::max_allowed_parallelism,
            std::size_t(THREAD_COUNTS[t]));
        vdbi::InterfaceMesh mesh;
        // Before the reset: its peak is not the run's.
        warmMemory(openvdb::Index64(r.labelledVoxels));
        const bool canPeak = resetPeak();
        const MemKb before = readMem();
        r.firstRunSeconds[t] = repairAndExtract(labels, &mesh).total;
        const MemKb after = readMem();
        r.peakKb[t] = canPeak ? after.hwm : -1;
        r.growthKb[t] = canPeak ? after.hwm - before.rss : -1;
        r.triangles = (long long)mesh.triangles.size();
        r.vertices = (long long)mesh.points.size();
        r.patches = (long long)mesh.patches.size();
        r.meshBytes = vdbi_bench::meshBytes(mesh);
    }
    r.labels = (long long)vdbi::collectLabels(*labels).size();
    r.ok = true;
    return r;
}

/// Median seconds per (k, thread count).
struct TimeResult
{
    RunSeconds seconds;
    double cpu = 0; ///< median CPU seconds (all threads) of repair + extraction
};
using TimeTable = std::array<std::array<TimeResult, 2>, CASE_COUNT>;

TimeTable
measureTimes(int cases, const Settings& settings)
{
    std::vector<openvdb::Int32Grid::ConstPtr> volumes;
    for (int n = 0; n < cases; ++n) {
        volumes.push_back(vdbi::voxelizedLabels(*makeVolume(COPY_COUNTS[n], settings)));
    }
    std::vector<std::array<std::array<std::vector<double>, 5>, 2>> samples(
        static_cast<std::size_t>(cases));
    for (int rep = -1; rep < settings.reps; ++rep) { // rep -1 warms up caches and TBB
        for (int m = 0; m < cases; ++m) {
            const int n = (m + rep + 1) % cases;
            for (std::size_t t = 0; t < 2; ++t) {
                tbb::global_control control(tbb::global_control::max_allowed_parallelism,
                    std::size_t(THREAD_COUNTS[t]));
                warmMemory(volumes[std::size_t(n)]->activeVoxelCount());
                const double c0 = vdbi_bench::cpuSeconds();
                const RunSeconds r = repairAndExtract(volumes[std::size_t(n)]);
                const double cpu = vdbi_bench::cpuSeconds() - c0;
                if (rep < 0) continue;
                auto& s = samples[std::size_t(n)][t];
                s[0].push_back(r.critical);
                s[1].push_back(r.fattening);
                s[2].push_back(r.extraction);
                s[3].push_back(r.total);
                s[4].push_back(cpu);
            }
        }
    }
    TimeTable table{};
    for (int n = 0; n < cases; ++n) {
        for (std::size_t t = 0; t < 2; ++t) {
            const auto& s = samples[std::size_t(n)][t];
            table[std::size_t(n)][t] = {{median(s[0]), median(s[1]), median(s[2]),
                median(s[3])}, median(s[4])};
        }
    }
    return table;
}

} // namespace

int
main(int argc, char** argv)
{
    vdbi::restartWithHugePages(argv); // as the CLI does: see HugePages.h
    Settings settings;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--reps" && i + 1 < argc) settings.reps = std::max(1, std::atoi(argv[++i]));
        else if (arg == "--span" && i + 1 < argc) settings.span = std::atoi(argv[++i]);
        else if (arg == "--seed" && i + 1 < argc) settings.seed = unsigned(std::atol(argv[++i]));
        else if (arg == "--max-k" && i + 1 < argc) settings.maxCopies = std::atoi(argv[++i]);
        else {
            std::fprintf(stderr, "usage: %s [--reps N] [--span S] [--seed X] [--max-k K]\n",
                argv[0]);
            return 2;
        }
    }
    if (settings.span < 1000 || settings.span > (1 << 30)) {
        std::fprintf(stderr, "--span must be in [1000, 2^30]\n");
        return 2;
    }
    int cases = 0;
    while (cases < CASE_COUNT && COPY_COUNTS[cases] <= settings.maxCopies) ++cases;

    std::printf("bench_scale: k copies of frogtissue.mhd (labels + 30 c) over a span of %d "
        "voxels per axis, seed %u; repair + extraction with TBB at 1 and 2 threads\n"
        "load average before: %s; heap: %s\n", settings.span, settings.seed,
        loadAverage().c_str(), heapPages().c_str());

    std::vector<MemoryResult> mem(static_cast<std::size_t>(cases));
    bool ok = true;
    for (int n = 0; n < cases; ++n) {
        long rss = 0;
        MemoryResult r;
        const bool done = vdbi_bench::inChild([&] {
            return measureMemory(COPY_COUNTS[n], settings);
        }, r, rss);
        r.ok = done && r.ok;
        mem[std::size_t(n)] = r;
        ok = ok && r.ok;
    }
    const std::string loadMid = loadAverage();
    TimeTable times{};
    long timingRss = 0;
    const double cpu0 = vdbi_bench::childCpuSeconds();
    const auto wall0 = Clock::now();
    const bool timed = vdbi_bench::inChild([&] { return measureTimes(cases, settings); },
        times, timingRss);
    const double timingCpu = vdbi_bench::childCpuSeconds() - cpu0;
    const double timingWall = seconds(wall0, Clock::now());
    ok = ok && timed;

    std::printf("\nvolumes (each built in its own process; memUsage() bytes of the input tree, "
        "vector bytes of the output mesh)\n");
    std::printf("%3s %9s %7s %6s %9s %9s %11s %11s %30s %10s\n", "k", "voxels", "leaves",
        "labels", "triangles", "vertices", "input B", "mesh B", "bounding box (dims)",
        "box voxels");
    for (int n = 0; n < cases; ++n) {
        const MemoryResult& m = mem[std::size_t(n)];
        const double boxVoxels = double(m.boxDim[0]) * double(m.boxDim[1])
            * double(m.boxDim[2]);
        std::printf("%3d %9lld %7lld %6lld %9lld %9lld %11lld %11lld %9lld x %8lld x %8lld "
            "%10.2e%s\n", COPY_COUNTS[n], m.labelledVoxels, m.leaves, m.labels, m.triangles,
            m.vertices, m.inputBytes, m.meshBytes, m.boxDim[0], m.boxDim[1], m.boxDim[2],
            boxVoxels, m.ok ? "" : "  FAILED");
    }
    const MemoryResult& largest = mem[std::size_t(cases - 1)];
    const double largestBox = double(largest.boxDim[0]) * double(largest.boxDim[1])
        * double(largest.boxDim[2]);
    std::printf("a dense int32 array of the k = %d bounding box would need %.2e bytes; the "
        "input tree needs %lld\n", COPY_COUNTS[cases - 1], 4.0 * largestBox,
        largest.inputBytes);

    std::printf("\nrepair + extraction, median wall seconds of %d rounds (interleaved over k "
        "and threads, after a warm-up round; each run after warming %zu bytes\nper labelled "
        "voxel of memory); per labelled voxel in ns\n", settings.reps, WARM_BYTES_PER_VOXEL);
    std::printf("%3s %9s %9s %7s | %9s %9s %7s | %8s | %8s %8s %8s %8s %8s %8s\n", "k",
        "1 thr s", "ns/voxel", "ratio", "2 thr s", "ns/voxel", "ratio", "speedup", "crit 1",
        "fat 1", "ext 1", "crit 2", "fat 2", "ext 2");
    const double base1 = ratio(times[0][0].seconds.total, double(mem[0].labelledVoxels));
    const double base2 = ratio(times[0][1].seconds.total, double(mem[0].labelledVoxels));
    for (int n = 0; n < cases; ++n) {
        const auto& t = times[std::size_t(n)];
        const double voxels = double(mem[std::size_t(n)].labelledVoxels);
        const double per1 = ratio(t[0].seconds.total, voxels);
        const double per2 = ratio(t[1].seconds.total, voxels);
        std::printf("%3d %9.4f %9.1f %7.2f | %9.4f %9.1f %7.2f | %8.2f | %8.4f %8.4f %8.4f "
            "%8.4f %8.4f %8.4f\n", COPY_COUNTS[n], t[0].seconds.total, 1e9 * per1,
            ratio(per1, base1), t[1].seconds.total, 1e9 * per2, ratio(per2, base2),
            ratio(t[0].seconds.total, t[1].seconds.total), t[0].seconds.critical,
            t[0].seconds.fattening, t[0].seconds.extraction, t[1].seconds.critical,
            t[1].seconds.fattening, t[1].seconds.extraction);
    }
    std::printf("median CPU seconds (all threads) of repair + extraction: ");
    for (int n = 0; n < cases; ++n) {
        std::printf("%sk=%d %.3f/%.3f", n ? ", " : "", COPY_COUNTS[n],
            times[std::size_t(n)][0].cpu, times[std::size_t(n)][1].cpu);
    }
    std::printf(" (1/2 threads)\n");

    std::printf("\nmemory in bytes per labelled voxel; peak: VmHWM during repair + extraction "
        "minus the RSS of the empty process\n(before the volume was built), so it holds the "
        "input tree, the intermediates and the mesh; ratio to k = 1\n");
    std::printf("%3s %8s %8s %8s %7s | %9s %8s %7s %9s | %9s %8s %7s %9s\n", "k", "input",
        "mesh", "in+mesh", "ratio", "peak1 kB", "B/voxel", "ratio", "/(in+msh)", "peak2 kB",
        "B/voxel", "ratio", "/(in+msh)");
    auto peakBytes = [](const MemoryResult& m, std::size_t t) {
        return 1024.0 * double(m.peakKb[t] - m.emptyKb);
    };
    const MemoryResult& m0 = mem[0];
    const double v0 = double(m0.labelledVoxels);
    for (int n = 0; n < cases; ++n) {
        const MemoryResult& m = mem[std::size_t(n)];
        const double voxels = double(m.labelledVoxels);
        const double inMesh = double(m.inputBytes + m.meshBytes);
        std::printf("%3d %8.1f %8.1f %8.1f %7.2f", COPY_COUNTS[n], double(m.inputBytes) / voxels,
            double(m.meshBytes) / voxels, inMesh / voxels,
            ratio(inMesh / voxels, double(m0.inputBytes + m0.meshBytes) / v0));
        for (std::size_t t = 0; t < 2; ++t) {
            std::printf(" | %9ld %8.1f %7.2f %9.2f", m.peakKb[t] - m.emptyKb,
                peakBytes(m, t) / voxels, ratio(peakBytes(m, t) / voxels,
                peakBytes(m0, t) / v0), ratio(peakBytes(m, t), inMesh));
        }
        std::printf("\n");
    }
    std::printf("raw kB per k (empty process / with the volume / peak 1 thread / peak 2 "
        "threads; growth during repair + extraction 1 / 2 threads):\n");
    for (int n = 0; n < cases; ++n) {
        const MemoryResult& m = mem[std::size_t(n)];
        std::printf("  k=%-2d %7ld / %7ld / %7ld / %7ld; %7ld / %7ld\n", COPY_COUNTS[n],
            m.emptyKb, m.volumeKb, m.peakKb[0], m.peakKb[1], m.growthKb[0], m.growthKb[1]);
    }
    std::printf("one run per k and thread count on pages new to the process (the memory runs, "
        "each after a heap trim),\nrepair + extraction s, ns per labelled voxel and its ratio to "
        "k = 1:\n");
    for (int n = 0; n < cases; ++n) {
        const MemoryResult& m = mem[std::size_t(n)];
        std::printf("  k=%-2d", COPY_COUNTS[n]);
        for (std::size_t t = 0; t < 2; ++t) {
            const double ns = 1e9 * m.firstRunSeconds[t] / double(m.labelledVoxels);
            const double ns1 = 1e9 * mem[0].firstRunSeconds[t] / double(mem[0].labelledVoxels);
            std::printf("   %d thr %8.4f s %7.1f ns %5.2f", THREAD_COUNTS[t],
                m.firstRunSeconds[t], ns, ns / ns1);
        }
        std::printf("\n");
    }
    std::printf("\nru_maxrss of the timing process (all volumes): %ld kB\n", timingRss);
    std::printf("timing process: %.1f s wall, %.1f s CPU (user + system)\n", timingWall,
        timingCpu);
    std::printf("load average: after the memory runs %s; at the end %s\n", loadMid.c_str(),
        loadAverage().c_str());
    if (!timed) std::printf("the timing process FAILED\n");
    return ok ? 0 : 1;
}
