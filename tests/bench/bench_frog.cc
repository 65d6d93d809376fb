// SPDX-License-Identifier: Apache-2.0
/// @file bench/bench_frog.cc
/// @brief The sample volumes through every stage: read, prepare (voxelizedLabels +
/// collectLabels), critical elements, fattening, extraction, remeshing (remeshPatches with
/// the pipeline's settings: one voxel, 10 iterations), write (.ply of the final mesh into a
/// temp folder).
/// @details Prints the median seconds per stage for three threading setups: the serial
/// fallback (RepairOptions::threaded = false), TBB limited to 1 thread and TBB with 2 threads
/// (tbb::global_control), in wall and in CPU seconds; labelled voxels and triangles per second
/// of every stage; the speedup of 2 threads over 1; the sizes of the result and the memory:
/// memUsage() of the grids, the bytes of the mesh, the peak RSS of every stage (VmHWM after
/// resetting it through /proc/self/clear_refs) in a process that ran the volume once.
///
/// Times: one child process runs all volumes and setups in rounds, interleaved, after one
/// warm-up round, so that a change of load on a shared machine hits all of them alike.
/// Memory: every (volume, setup) runs once in a forked child of its own. The parent never
/// starts TBB itself.
///
/// Usage: bench_frog [--reps N] [--frog-only] [--no-remesh] [--keep DIR] [--keep-heap]
///            (remeshing takes most of the time: --no-remesh skips it, and writes the raw mesh;
///            --keep-heap: glibc serves every block from its heap and keeps what is freed, as
///            a long-running host reuses its memory, see keepHeap())
///        bench_frog --profile [--threads T]   one run of the frog's repair and extraction,
///            with callgrind instrumentation switched on only around it (run it under
///            valgrind --tool=callgrind --collect-atstart=no, or perf record).

#include "BenchSupport.h"
#include "support/TestData.h"

#include <vdbi/CriticalElements.h>
#include <vdbi/Fattening.h>
#include <vdbi/HugePages.h>
#include <vdbi/InterfaceExtraction.h>
#include <vdbi/LabelGrid.h>
#include <vdbi/LabelVolumeReader.h>
#include <vdbi/MeshWriter.h>
#include <vdbi/Remeshing.h>

#include <openvdb/openvdb.h>

#include <tbb/global_control.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#endif

#include <stdlib.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace {

using vdbi_bench::Clock;
using vdbi_bench::cpuSeconds;
using vdbi_bench::heapPages;
using vdbi_bench::loadAverage;
using vdbi_bench::median;
using vdbi_bench::MemKb;
using vdbi_bench::meshBytes;
using vdbi_bench::ratio;
using vdbi_bench::readMem;
using vdbi_bench::resetPeak;
using vdbi_bench::seconds;

/// The stages, in the order they run.
enum Stage { READ, PREPARE, CRITICAL, FATTENING, EXTRACTION, REMESHING, WRITE, STAGE_COUNT };
const char* const STAGE_NAMES[STAGE_COUNT] = {"read", "prepare", "critical", "fattening",
    "extraction", "remeshing", "write"};

struct Setup
{
    const char* name;
    bool threaded;
    int threads;
};
const Setup SETUPS[] = {
    {"serial (threaded=false)", false, 1},
    {"TBB, 1 thread", true, 1},
    {"TBB, 2 threads", true, 2},
};
constexpr int SETUP_COUNT = 3;

const char* const VOLUMES[] = {"frogtissue.mhd", "chr_knight.vox", "monu1.vox", "monu16.vox",
    "menger.vox"};
constexpr int VOLUME_COUNT = 5;

/// Sizes of one run; the same for every setup (the stages are deterministic).
struct Sizes
{
    long long inputVoxels = 0, leaves = 0, labels = 0;
    long long criticalEdges = 0, criticalVertices = 0, singularVertices = 0;
    long long subdividedVoxels = 0, relabelledSubvoxels = 0;
    long long patches = 0, triangles = 0, vertices = 0;
    long long remeshedTriangles = 0, remeshedVertices = 0; ///< 0 without remeshing
    long long inputBytes = 0, fineBytes = 0, maskBytes = 0, meshBytes = 0, fileBytes = 0;
};

/// One run of all stages: wall and CPU seconds of each, and the sizes.
struct RunResult
{
    std::array<double, STAGE_COUNT> seconds{}, cpu{};
    Sizes sizes;
};

/// A fresh temporary folder, removed with the object.
class TempDir
{
public:
    TempDir()
    {
        std::string pattern = (std::filesystem::temp_directory_path() / "vdbi_bench_XXXXXX")
            .string();
        if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
        mPath = pattern;
    }
    ~TempDir()
    {
        std::error_code ec;
        std::filesystem::remove_all(mPath, ec);
    }
    const std::string& path() const { return mPath; }

private:
    std::string mPath;
};

/// Peak RSS of every stage of one run, in kB: the growth over the RSS before the stage and
/// the absolute peak (VmHWM, reset through clear_refs before the stage).
struct PeakKb
{
    std::array<long, STAGE_COUNT> growth{}, absolute{};
    long before = 0; ///< VmHWM before the first stage (the process's peak until then)
};

/// One run of all stages (remeshing only with @a remesh, else the raw mesh is written); with
/// @a peak, also the peak RSS of each stage (this resets VmHWM, so ru_maxrss of the process
/// no longer holds its overall peak: PeakKb does).
RunResult
runStages(const std::string& volume, const Setup& setup, const std::string& outDir,
          bool remesh, PeakKb* peak)
{
    RunResult r;
    vdbi::RepairOptions options;
    options.threaded = setup.threaded;
    vdbi::ExtractionOptions extraction;
    extraction.threaded = setup.threaded;

    // Times one stage; with @a peak, also its peak RSS (measured outside the timed span).
    if (peak) peak->before = readMem().hwm;
    auto stage = [&](Stage s, auto&& body) {
        MemKb before;
        const bool canPeak = peak && resetPeak();
        if (canPeak) before = readMem();
        const double c0 = cpuSeconds();
        const auto t0 = Clock::now();
        body();
        const auto t1 = Clock::now();
        r.cpu[s] = cpuSeconds() - c0;
        r.seconds[s] = seconds(t0, t1);
        if (peak) {
            const MemKb after = readMem();
            peak->growth[s] = canPeak ? after.hwm - before.rss : -1;
            peak->absolute[s] = canPeak ? after.hwm : -1;
        }
    };

    openvdb::Int32Grid::Ptr grid;
    stage(READ, [&] { grid = vdbi::readLabelVolume(vdbi_test::dataPath(volume)); });
    openvdb::Int32Grid::ConstPtr labels;
    std::size_t labelCount = 0;
    stage(PREPARE, [&] {
        labels = vdbi::voxelizedLabels(*grid);
        labelCount = vdbi::collectLabels(*labels, setup.threaded).size();
    });
    vdbi::CriticalElements elements;
    stage(CRITICAL, [&] { elements = vdbi::findCriticalElements(*labels, options); });
    std::optional<vdbi::RefinedLabels> refined;
    stage(FATTENING, [&] { refined = vdbi::fattenCriticalElements(labels, elements, options); });
    vdbi::InterfaceMesh mesh;
    stage(EXTRACTION, [&] { mesh = vdbi::extractInterfacePatches(*refined, extraction); });
    // The settings of vdbi::extractInterfaces() with Options::remesh.
    vdbi::InterfaceMesh remeshed;
    if (remesh) {
        vdbi::RemeshOptions remeshing;
        remeshing.voxelSize = grid->voxelSize();
        remeshing.edgeLength = remeshing.voxelSize[0];
        remeshing.threaded = setup.threaded;
        stage(REMESHING, [&] { remeshed = vdbi::remeshPatches(mesh, remeshing); });
    }
    const std::string file = outDir + "/" + std::filesystem::path(volume).stem().string()
        + ".ply";
    stage(WRITE, [&] { vdbi::writeInterfaceMesh(remesh ? remeshed : mesh, file); });

    Sizes& z = r.sizes;
    z.inputVoxels = (long long)grid->activeVoxelCount();
    z.leaves = (long long)labels->tree().leafCount();
    z.labels = (long long)labelCount;
    z.criticalEdges = (long long)elements.edges.size();
    z.criticalVertices = (long long)elements.vertices.size();
    z.singularVertices = (long long)elements.singularVertexCount();
    z.subdividedVoxels = (long long)refined->subdivided->activeVoxelCount();
    z.relabelledSubvoxels = (long long)refined->fine->activeVoxelCount();
    z.patches = (long long)mesh.patches.size();
    z.triangles = (long long)mesh.triangles.size();
    z.vertices = (long long)mesh.points.size();
    z.remeshedTriangles = (long long)remeshed.triangles.size();
    z.remeshedVertices = (long long)remeshed.points.size();
    z.inputBytes = (long long)labels->memUsage();
    z.fineBytes = (long long)refined->fine->memUsage();
    z.maskBytes = (long long)refined->subdivided->memUsage();
    z.meshBytes = meshBytes(mesh);
    z.fileBytes = (long long)std::filesystem::file_size(file);
    return r;
}

/// What one memory child sends back.
struct MemoryResult
{
    Sizes sizes;
    PeakKb peak;
    bool ok = false;

    /// The process's peak RSS over the whole run.
    long maxKb() const
    {
        long m = peak.before;
        for (long a : peak.absolute) m = std::max(m, a);
        return m;
    }
};

/// Median seconds of every stage, and of the sum critical + fattening + extraction
/// ("repair + extraction") and of prepare + that (all of extractInterfaces()).
struct TimeResult
{
    std::array<double, STAGE_COUNT> seconds{}, cpu{};
    double repairExtraction = 0, pipeline = 0;
    double repairExtractionCpu = 0, pipelineCpu = 0;
};

using TimeTable = std::array<std::array<TimeResult, SETUP_COUNT>, VOLUME_COUNT>;

TimeTable
measureTimes(int reps, int volumes, const std::string& outDir, bool remesh)
{
    // Per (volume, setup): wall seconds of the stages, of the two sums, then the same in CPU
    // seconds.
    constexpr std::size_t W = STAGE_COUNT + 2;
    using Samples = std::array<std::vector<double>, 2 * W>;
    std::vector<std::array<Samples, SETUP_COUNT>> samples{std::size_t(volumes)};
    for (int rep = -1; rep < reps; ++rep) { // rep -1: warm-up
        for (int v = 0; v < volumes; ++v) {
            for (int c = 0; c < SETUP_COUNT; ++c) {
                tbb::global_control control(tbb::global_control::max_allowed_parallelism,
                    std::size_t(SETUPS[c].threads));
                const RunResult r = runStages(VOLUMES[v], SETUPS[c], outDir, remesh, nullptr);
                if (rep < 0) continue;
                Samples& s = samples[std::size_t(v)][std::size_t(c)];
                for (std::size_t o : {std::size_t(0), W}) {
                    const auto& x = o == 0 ? r.seconds : r.cpu;
                    for (int k = 0; k < STAGE_COUNT; ++k) s[o + std::size_t(k)].push_back(x[k]);
                    const double repair = x[CRITICAL] + x[FATTENING] + x[EXTRACTION];
                    s[o + STAGE_COUNT].push_back(repair);
                    s[o + STAGE_COUNT + 1].push_back(repair + x[PREPARE]);
                }
            }
        }
    }
    TimeTable t{};
    for (int v = 0; v < volumes; ++v) {
        for (int c = 0; c < SETUP_COUNT; ++c) {
            const Samples& s = samples[std::size_t(v)][std::size_t(c)];
            TimeResult& out = t[std::size_t(v)][std::size_t(c)];
            for (int k = 0; k < STAGE_COUNT; ++k) {
                out.seconds[k] = median(s[std::size_t(k)]);
                out.cpu[k] = median(s[W + std::size_t(k)]);
            }
            out.repairExtraction = median(s[STAGE_COUNT]);
            out.pipeline = median(s[STAGE_COUNT + 1]);
            out.repairExtractionCpu = median(s[W + STAGE_COUNT]);
            out.pipelineCpu = median(s[W + STAGE_COUNT + 1]);
        }
    }
    return t;
}

/// One run of the frog's repair and extraction for a profiler.
int
profile(int threads)
{
    openvdb::initialize();
    tbb::global_control control(tbb::global_control::max_allowed_parallelism,
        std::size_t(threads));
    vdbi::RepairOptions options;
    options.threaded = threads > 1;
    vdbi::ExtractionOptions extraction;
    extraction.threaded = options.threaded;
    const openvdb::Int32Grid::Ptr grid = vdbi::readLabelVolume(
        vdbi_test::dataPath("frogtissue.mhd"));

    const auto t0 = Clock::now();
    CALLGRIND_START_INSTRUMENTATION;
    const openvdb::Int32Grid::ConstPtr labels = vdbi::voxelizedLabels(*grid);
    const vdbi::CriticalElements elements = vdbi::findCriticalElements(*labels, options);
    const vdbi::RefinedLabels refined = vdbi::fattenCriticalElements(labels, elements, options);
    const vdbi::InterfaceMesh mesh = vdbi::extractInterfacePatches(refined, extraction);
    CALLGRIND_STOP_INSTRUMENTATION;
    const auto t1 = Clock::now();
    std::printf("profile run (%d thread%s, threaded=%d): %zu critical edges, %zu critical "
        "vertices, %zu triangles, %.3f s\n", threads, threads > 1 ? "s" : "",
        int(options.threaded), elements.edges.size(), elements.vertices.size(),
        mesh.triangles.size(), seconds(t0, t1));
    return 0;
}

/// Labelled voxels and triangles per second of every stage and of the sums, for one setup.
void
printThroughput(const char* setup, const TimeResult& t, const Sizes& z, bool remesh)
{
    // Triangles per second: the triangles the pipeline delivers after that stage's part of
    // it, the raw ones up to extraction, the remeshed ones for remeshing and write.
    auto triangles = [&](int k) {
        return double(remesh && k >= REMESHING ? z.remeshedTriangles : z.triangles);
    };
    auto rate = [](double amount, double s) { return s > 0 ? amount / s : 0.0; };
    std::printf("   %-24s", setup);
    for (int k = 0; k < STAGE_COUNT; ++k) {
        if (k == REMESHING && !remesh) {
            std::printf(" %15s", "-");
            continue;
        }
        std::printf(" %7.2f/%7.2f", 1e-6 * rate(double(z.inputVoxels), t.seconds[k]),
            1e-6 * rate(triangles(k), t.seconds[k]));
    }
    std::printf(" %7.2f/%7.2f %7.2f/%7.2f\n",
        1e-6 * rate(double(z.inputVoxels), t.repairExtraction),
        1e-6 * rate(double(z.triangles), t.repairExtraction),
        1e-6 * rate(double(z.inputVoxels), t.pipeline),
        1e-6 * rate(double(z.triangles), t.pipeline));
}

/// @brief Makes glibc serve large blocks from its heap instead of mmap(): freed, they stay
/// for the next round instead of going back to the kernel, to be faulted in and cleared
/// again. Frog's extraction writes ~160 MB of new arrays per run; on the project's virtual
/// machines those faults cost the 2-thread runs more than the 1-thread ones.
bool
keepHeap()
{
#ifdef __GLIBC__
    return mallopt(M_MMAP_MAX, 0) == 1;
#else
    return false;
#endif
}

} // namespace

int
main(int argc, char** argv)
{
    vdbi::restartWithHugePages(argv); // as the CLI does: see HugePages.h
    int reps = 7, threads = 1;
    bool frogOnly = false, profileRun = false, remesh = true, keptHeap = false;
    std::string keep;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--reps" && i + 1 < argc) reps = std::max(1, std::atoi(argv[++i]));
        else if (arg == "--threads" && i + 1 < argc) threads = std::max(1, std::atoi(argv[++i]));
        else if (arg == "--frog-only") frogOnly = true;
        else if (arg == "--no-remesh") remesh = false;
        else if (arg == "--profile") profileRun = true;
        else if (arg == "--keep" && i + 1 < argc) keep = argv[++i];
        else if (arg == "--keep-heap") keptHeap = keepHeap();
        else {
            std::fprintf(stderr, "usage: %s [--reps N] [--frog-only] [--no-remesh] [--keep DIR] "
                "[--keep-heap] | --profile [--threads T]\n", argv[0]);
            return 2;
        }
    }
    if (profileRun) return profile(threads);

    const int volumes = frogOnly ? 1 : VOLUME_COUNT;
    std::unique_ptr<TempDir> temp;
    if (keep.empty()) temp = std::make_unique<TempDir>();
    const std::string outDir = keep.empty() ? temp->path() : keep;

    std::printf("bench_frog: %d volume(s) x {serial, TBB 1 thread, TBB 2 threads}; "
        "%d timed rounds (interleaved) after a warm-up round; remeshing %s; .ply into %s\n"
        "load average before: %s; heap: %s%s\n", volumes, reps,
        remesh ? "on" : "off (--no-remesh)", outDir.c_str(), loadAverage().c_str(),
        heapPages().c_str(), keptHeap ? "; freed memory kept in the heap (--keep-heap)" : "");

    // Memory first: one process per (volume, setup), one run each.
    std::vector<std::array<MemoryResult, SETUP_COUNT>> mem{std::size_t(volumes)};
    bool ok = true;
    for (int v = 0; v < volumes; ++v) {
        for (int c = 0; c < SETUP_COUNT; ++c) {
            MemoryResult r;
            long rss = 0;
            const bool done = vdbi_bench::inChild([&] {
                tbb::global_control control(tbb::global_control::max_allowed_parallelism,
                    std::size_t(SETUPS[c].threads));
                MemoryResult m;
                m.sizes = runStages(VOLUMES[v], SETUPS[c], outDir, remesh, &m.peak).sizes;
                m.ok = true;
                return m;
            }, r, rss);
            r.ok = done && r.ok;
            mem[std::size_t(v)][std::size_t(c)] = r;
            ok = ok && r.ok;
        }
    }
    const std::string loadMid = loadAverage();

    TimeTable times{};
    long timingRss = 0;
    const double cpu0 = vdbi_bench::childCpuSeconds();
    const auto wall0 = Clock::now();
    const bool timed = vdbi_bench::inChild([&] {
        return measureTimes(reps, volumes, outDir, remesh);
    }, times, timingRss);
    const double timingCpu = vdbi_bench::childCpuSeconds() - cpu0;
    const double timingWall = seconds(wall0, Clock::now());
    ok = ok && timed;

    for (int v = 0; v < volumes; ++v) {
        const MemoryResult& m0 = mem[std::size_t(v)][0];
        const Sizes& z = m0.sizes;
        std::printf("\n== %s: %lld input voxels, %lld leaves, %lld labels (background "
            "included)\n", VOLUMES[v], z.inputVoxels, z.leaves, z.labels);
        std::printf("   critical edges %lld, critical vertices %lld (singular %lld), "
            "subdivided voxels %lld, relabelled subvoxels %lld\n", z.criticalEdges,
            z.criticalVertices, z.singularVertices, z.subdividedVoxels, z.relabelledSubvoxels);
        std::printf("   patches %lld, triangles %lld, vertices %lld", z.patches, z.triangles,
            z.vertices);
        if (remesh) {
            std::printf("; remeshed: triangles %lld, vertices %lld", z.remeshedTriangles,
                z.remeshedVertices);
        }
        std::printf("; .ply %lld bytes\n", z.fileBytes);
        std::printf("   bytes: input grid %lld, fine grid %lld, mask %lld, mesh %lld\n",
            z.inputBytes, z.fineBytes, z.maskBytes, z.meshBytes);
        for (int c = 1; c < SETUP_COUNT; ++c) {
            const Sizes& y = mem[std::size_t(v)][std::size_t(c)].sizes;
            if (y.triangles != z.triangles || y.vertices != z.vertices
                || y.remeshedTriangles != z.remeshedTriangles
                || y.criticalEdges != z.criticalEdges || y.fileBytes != z.fileBytes) {
                std::printf("   !! %s gives different sizes\n", SETUPS[c].name);
            }
        }
        std::printf("   median wall seconds of %d runs (the machine is shared: see the load):\n",
            reps);
        std::printf("   %-24s", "setup");
        for (int k = 0; k < STAGE_COUNT; ++k) std::printf(" %10s", STAGE_NAMES[k]);
        std::printf(" %10s %10s\n", "crit+fat+x", "+prepare");
        for (int c = 0; c < SETUP_COUNT; ++c) {
            const TimeResult& t = times[std::size_t(v)][std::size_t(c)];
            std::printf("   %-24s", SETUPS[c].name);
            for (int k = 0; k < STAGE_COUNT; ++k) std::printf(" %10.4f", t.seconds[k]);
            std::printf(" %10.4f %10.4f\n", t.repairExtraction, t.pipeline);
        }
        std::printf("   median CPU seconds (all threads; for 1 thread close to the wall time of "
            "an idle machine):\n");
        for (int c = 0; c < SETUP_COUNT; ++c) {
            const TimeResult& t = times[std::size_t(v)][std::size_t(c)];
            std::printf("   %-24s", SETUPS[c].name);
            for (int k = 0; k < STAGE_COUNT; ++k) std::printf(" %10.4f", t.cpu[k]);
            std::printf(" %10.4f %10.4f\n", t.repairExtractionCpu, t.pipelineCpu);
        }
        std::printf("   throughput from the median wall seconds, million labelled voxels per "
            "second / million triangles per second\n   (triangles: the raw mesh's up to "
            "extraction, the remeshed mesh's from remeshing on):\n");
        std::printf("   %-24s", "setup");
        for (int k = 0; k < STAGE_COUNT; ++k) std::printf(" %15s", STAGE_NAMES[k]);
        std::printf(" %15s %15s\n", "crit+fat+x", "+prepare");
        for (int c = 0; c < SETUP_COUNT; ++c) {
            printThroughput(SETUPS[c].name, times[std::size_t(v)][std::size_t(c)], z, remesh);
        }
        const TimeResult& one = times[std::size_t(v)][1];
        const TimeResult& two = times[std::size_t(v)][2];
        std::printf("   speedup of TBB 2 threads over TBB 1 thread (median wall seconds):\n");
        std::printf("   %-24s", "");
        for (int k = 0; k < STAGE_COUNT; ++k) {
            std::printf(" %10.2f", ratio(one.seconds[k], two.seconds[k]));
        }
        std::printf(" %10.2f %10.2f   <- repair + extraction: %.2fx\n",
            ratio(one.repairExtraction, two.repairExtraction), ratio(one.pipeline, two.pipeline),
            ratio(one.repairExtraction, two.repairExtraction));
        std::printf("   peak RSS per stage in kB (one run in a process of its own): growth over "
            "the RSS before the stage / absolute peak (VmHWM after clear_refs); max: the "
            "process's peak\n");
        std::printf("   %-24s", "setup");
        for (int k = 0; k < STAGE_COUNT; ++k) std::printf(" %17s", STAGE_NAMES[k]);
        std::printf(" %8s\n", "max");
        for (int c = 0; c < SETUP_COUNT; ++c) {
            const MemoryResult& m = mem[std::size_t(v)][std::size_t(c)];
            std::printf("   %-24s", SETUPS[c].name);
            for (int k = 0; k < STAGE_COUNT; ++k) {
                std::printf(" %8ld/%8ld", m.peak.growth[k], m.peak.absolute[k]);
            }
            std::printf(" %8ld%s\n", m.maxKb(), m.ok ? "" : "  FAILED");
        }
    }
    std::printf("\nru_maxrss of the timing process (all volumes and setups, no VmHWM resets): "
        "%ld kB\n", timingRss);
    std::printf("timing process: %.1f s wall, %.1f s CPU (user + system)\n", timingWall,
        timingCpu);
    std::printf("load average: before (see top); after the memory runs %s; at the end %s\n",
        loadMid.c_str(), loadAverage().c_str());
    if (!timed) std::printf("the timing process FAILED\n");
    return ok ? 0 : 1;
}
