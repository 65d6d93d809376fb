// SPDX-License-Identifier: Apache-2.0
/// @file bench/bench_frog.cc
/// @brief The sample volumes through every stage: read, prepare (voxelizedLabels +
/// collectLabels), critical elements, fattening, extraction, write (.ply into a temp folder).
/// @details Prints the median seconds per stage for three threading setups: the serial
/// fallback (RepairOptions::threaded = false), TBB limited to 1 thread and TBB with 2 threads
/// (tbb::global_control), in wall and in CPU seconds, with the sizes of the result and the
/// memory: memUsage() of the grids, the bytes of the mesh, the peak RSS of every stage (VmHWM
/// after resetting it through /proc/self/clear_refs) in a process that ran the volume once.
///
/// Times: one child process runs all volumes and setups in rounds, interleaved, after one
/// warm-up round, so that a change of load on a shared machine hits all of them alike.
/// Memory: every (volume, setup) runs once in a forked child of its own. The parent never
/// starts TBB itself.
///
/// Usage: bench_frog [--reps N] [--frog-only] [--keep DIR]
///        bench_frog --profile [--threads T]   one run of the frog's repair and extraction,
///            with callgrind instrumentation switched on only around it (run it under
///            valgrind --tool=callgrind --collect-atstart=no, or perf record).

#include "support/TestData.h"

#include <vdbi/CriticalElements.h>
#include <vdbi/Fattening.h>
#include <vdbi/InterfaceExtraction.h>
#include <vdbi/LabelGrid.h>
#include <vdbi/LabelVolumeReader.h>
#include <vdbi/MeshWriter.h>

#include <openvdb/openvdb.h>

#include <tbb/global_control.h>

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#endif

#include <malloc.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

double
seconds(Clock::time_point a, Clock::time_point b)
{
    return std::chrono::duration<double>(b - a).count();
}

/// CPU seconds of this process, all threads.
double
cpuSeconds()
{
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

double
median(std::vector<double> v)
{
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct MemKb
{
    long rss = 0, hwm = 0;
};

MemKb
readMem()
{
    MemKb m;
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmRSS:", 0) == 0) m.rss = std::atol(line.c_str() + 6);
        if (line.rfind("VmHWM:", 0) == 0) m.hwm = std::atol(line.c_str() + 6);
    }
    return m;
}

/// Returns freed heap to the system and resets VmHWM to the current RSS.
bool
resetPeak()
{
    malloc_trim(0);
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    clear.flush();
    return bool(clear);
}

std::string
loadAverage()
{
    std::ifstream f("/proc/loadavg");
    std::string a, b, c;
    f >> a >> b >> c;
    return a + " " + b + " " + c;
}

/// The stages, in the order they run.
enum Stage { READ, PREPARE, CRITICAL, FATTENING, EXTRACTION, WRITE, STAGE_COUNT };
const char* const STAGE_NAMES[STAGE_COUNT] = {"read", "prepare", "critical", "fattening",
    "extraction", "write"};

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
    long long inputBytes = 0, fineBytes = 0, maskBytes = 0, meshBytes = 0, fileBytes = 0;
};

/// One run of all stages: wall and CPU seconds of each, and the sizes.
struct RunResult
{
    std::array<double, STAGE_COUNT> seconds{}, cpu{};
    Sizes sizes;
};

long long
meshBytes(const vdbi::InterfaceMesh& m)
{
    return (long long)(m.points.size() * sizeof(openvdb::Vec3d)
        + m.triangles.size() * sizeof(openvdb::Vec3I)
        + m.pointKeys.size() * sizeof(vdbi::VertexKey)
        + m.patches.size() * sizeof(vdbi::InterfacePatch));
}

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

/// One run of all stages; with @a peak, also the peak RSS of each stage (this resets VmHWM,
/// so ru_maxrss of the process no longer holds its overall peak: PeakKb does).
RunResult
runStages(const std::string& volume, const Setup& setup, const std::string& outDir,
          PeakKb* peak)
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
    const std::string file = outDir + "/" + std::filesystem::path(volume).stem().string()
        + ".ply";
    stage(WRITE, [&] { vdbi::writeInterfaceMesh(mesh, file); });

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
measureTimes(int reps, int volumes, const std::string& outDir)
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
                const RunResult r = runStages(VOLUMES[v], SETUPS[c], outDir, nullptr);
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

/// Runs @a body in a forked child; its result comes back through a pipe, the child's peak
/// RSS through wait4(). Returns false if the child failed.
template<typename T, typename Body>
bool
inChild(const Body& body, T& out, long& maxRssKb)
{
    int fd[2];
    if (pipe(fd) != 0) { std::perror("pipe"); std::exit(1); }
    std::fflush(stdout);
    std::fflush(stderr);
    const pid_t pid = fork();
    if (pid < 0) { std::perror("fork"); std::exit(1); }
    if (pid == 0) {
        close(fd[0]);
        bool ok = false;
        try {
            openvdb::initialize();
            const auto result = std::make_unique<T>(body());
            const char* p = reinterpret_cast<const char*>(result.get());
            std::size_t left = sizeof(T);
            while (left > 0) {
                const ssize_t w = write(fd[1], p, left);
                if (w <= 0) break;
                p += w;
                left -= std::size_t(w);
            }
            ok = left == 0;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "child: %s\n", e.what());
        }
        close(fd[1]);
        _exit(ok ? 0 : 1);
    }
    close(fd[1]);
    char* p = reinterpret_cast<char*>(&out);
    std::size_t got = 0;
    while (got < sizeof(T)) {
        const ssize_t n = read(fd[0], p + got, sizeof(T) - got);
        if (n <= 0) break;
        got += std::size_t(n);
    }
    close(fd[0]);
    int status = 0;
    struct rusage usage;
    std::memset(&usage, 0, sizeof usage);
    wait4(pid, &status, 0, &usage);
    maxRssKb = usage.ru_maxrss;
    return got == sizeof(T) && WIFEXITED(status) && WEXITSTATUS(status) == 0;
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

} // namespace

int
main(int argc, char** argv)
{
    int reps = 7, threads = 1;
    bool frogOnly = false, profileRun = false;
    std::string keep;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--reps" && i + 1 < argc) reps = std::max(1, std::atoi(argv[++i]));
        else if (arg == "--threads" && i + 1 < argc) threads = std::max(1, std::atoi(argv[++i]));
        else if (arg == "--frog-only") frogOnly = true;
        else if (arg == "--profile") profileRun = true;
        else if (arg == "--keep" && i + 1 < argc) keep = argv[++i];
        else {
            std::fprintf(stderr, "usage: %s [--reps N] [--frog-only] [--keep DIR] | "
                "--profile [--threads T]\n", argv[0]);
            return 2;
        }
    }
    if (profileRun) return profile(threads);

    const int volumes = frogOnly ? 1 : VOLUME_COUNT;
    std::unique_ptr<TempDir> temp;
    if (keep.empty()) temp = std::make_unique<TempDir>();
    const std::string outDir = keep.empty() ? temp->path() : keep;

    std::printf("bench_frog: %d volume(s) x {serial, TBB 1 thread, TBB 2 threads}; "
        "%d timed rounds (interleaved) after a warm-up round; .ply into %s\n"
        "load average before: %s\n", volumes, reps, outDir.c_str(), loadAverage().c_str());

    // Memory first: one process per (volume, setup), one run each.
    std::vector<std::array<MemoryResult, SETUP_COUNT>> mem{std::size_t(volumes)};
    bool ok = true;
    for (int v = 0; v < volumes; ++v) {
        for (int c = 0; c < SETUP_COUNT; ++c) {
            MemoryResult r;
            long rss = 0;
            const bool done = inChild([&] {
                tbb::global_control control(tbb::global_control::max_allowed_parallelism,
                    std::size_t(SETUPS[c].threads));
                MemoryResult m;
                m.sizes = runStages(VOLUMES[v], SETUPS[c], outDir, &m.peak).sizes;
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
    const bool timed = inChild([&] { return measureTimes(reps, volumes, outDir); }, times,
        timingRss);
    ok = ok && timed;

    for (int v = 0; v < volumes; ++v) {
        const MemoryResult& m0 = mem[std::size_t(v)][0];
        const Sizes& z = m0.sizes;
        std::printf("\n== %s: %lld input voxels, %lld leaves, %lld labels (background "
            "included)\n", VOLUMES[v], z.inputVoxels, z.leaves, z.labels);
        std::printf("   critical edges %lld, critical vertices %lld (singular %lld), "
            "subdivided voxels %lld, relabelled subvoxels %lld\n", z.criticalEdges,
            z.criticalVertices, z.singularVertices, z.subdividedVoxels, z.relabelledSubvoxels);
        std::printf("   patches %lld, triangles %lld, vertices %lld, .ply %lld bytes\n",
            z.patches, z.triangles, z.vertices, z.fileBytes);
        std::printf("   bytes: input grid %lld, fine grid %lld, mask %lld, mesh %lld\n",
            z.inputBytes, z.fineBytes, z.maskBytes, z.meshBytes);
        for (int c = 1; c < SETUP_COUNT; ++c) {
            const Sizes& y = mem[std::size_t(v)][std::size_t(c)].sizes;
            if (y.triangles != z.triangles || y.vertices != z.vertices
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
    std::printf("load average: before (see top); after the memory runs %s; at the end %s\n",
        loadMid.c_str(), loadAverage().c_str());
    if (!timed) std::printf("the timing process FAILED\n");
    return ok ? 0 : 1;
}
