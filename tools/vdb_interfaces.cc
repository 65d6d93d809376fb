// SPDX-License-Identifier: Apache-2.0
/// @file tools/vdb_interfaces.cc
/// @brief vdb_interfaces: label volume in, interface meshes out.
/// @details Parsing with CLI11, checks of the command line and the file system before any
/// work, then readLabelVolume(), extractInterfaces() and the writers. Exit status 0 on
/// success, 1 on a runtime error ("vdb_interfaces: FILE: problem"), 2 on a bad command line
/// (a message plus a usage line).

#include <vdbi/AtomicFile.h>
#include <vdbi/HugePages.h>
#include <vdbi/Interfaces.h>
#include <vdbi/LabelVolumeReader.h>
#include <vdbi/MeshWriter.h>
#include <vdbi/RunReport.h>
#include <vdbi/Types.h>

#include <openvdb/Exceptions.h>
#include <openvdb/openvdb.h>
#include <openvdb/util/NullInterrupter.h>

#include <tbb/global_control.h>

#include <CLI/CLI.hpp>

#include <pthread.h>      // for pthread_sigmask
#include <signal.h>       // for sigwait
#include <unistd.h>       // for isatty, access

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#ifndef VDBI_VERSION
#define VDBI_VERSION "unknown"
#endif

namespace fs = std::filesystem;

namespace {

const char* const PROGRAM = "vdb_interfaces";
const char* const USAGE_LINE = "Usage: vdb_interfaces [OPTIONS] INPUT -o OUTPUT";

/// A bad command line: exit status 2, message plus usage line.
class UsageError : public std::runtime_error
{
public:
    using std::runtime_error::runtime_error;
};

/// A problem found before any work (missing file, unwritable folder): exit status 1.
class CheckError : public std::runtime_error
{
public:
    using std::runtime_error::runtime_error;
};

/// Everything the command line sets.
struct Settings
{
    std::string input;
    std::string output;
    std::string perLabelDir;
    std::string perLabelFormat = "stl";
    std::string gridName;
    std::string reportPath;
    int threads = 0; // 0: TBB's default, all cores
    std::vector<vdbi::Label> priority;
    std::vector<std::string> separate;
    double edgeLength = 0.0;
    int iterations = vdbi::Options().iterations;
    bool noRemesh = false;
    bool stats = false;
};

// ---------------------------------------------------------------------------------------
// Values

std::string
lowerExtension(const std::string& path)
{
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
        [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

/// "'.ext'" as written, or "(no extension)": an empty '' would puzzle.
std::string
quotedExtension(const std::string& path)
{
    const std::string ext = fs::path(path).extension().string();
    return ext.empty() ? std::string("(no extension)") : "'" + ext + "'";
}

/// Parses all of @a text as an integer of type T; false on anything else.
template<typename T>
bool
parseInteger(const std::string& text, T& value)
{
    const char* begin = text.data();
    const char* end = begin + text.size();
    if (begin != end && *begin == '+') ++begin;
    const auto result = std::from_chars(begin, end, value);
    return begin != end && result.ec == std::errc() && result.ptr == end;
}

/// "A,B:C" (labels A and B are always separated by C); an empty string on success, else
/// what is wrong.
std::string
parseConstraint(const std::string& text, vdbi::SeparationConstraint& constraint)
{
    const std::size_t comma = text.find(',');
    const std::size_t colon = text.find(':', comma == std::string::npos ? 0 : comma);
    if (comma == std::string::npos || colon == std::string::npos
        || !parseInteger(text.substr(0, comma), constraint.a)
        || !parseInteger(text.substr(comma + 1, colon - comma - 1), constraint.b)
        || !parseInteger(text.substr(colon + 1), constraint.separator))
    {
        return "expected A,B:C with integer labels (A and B are separated by C), got '"
            + text + "'";
    }
    if (constraint.a == constraint.b) {
        return "'" + text + "': the two separated labels must differ";
    }
    if (constraint.separator == constraint.a || constraint.separator == constraint.b) {
        return "'" + text + "': the separator must differ from both separated labels";
    }
    return std::string();
}

/// CLI11 validators return an empty string when the value is fine.
const CLI::Validator POSITIVE_REAL(
    [](std::string& text) -> std::string {
        const char* begin = text.c_str();
        char* end = nullptr;
        errno = 0;
        const double value = std::strtod(begin, &end);
        if (text.empty() || end != begin + text.size() || errno == ERANGE
            || !std::isfinite(value))
        {
            return "expected a number, got '" + text + "'";
        }
        if (!(value > 0.0)) return "must be greater than 0, got " + text;
        return std::string();
    },
    "", "POSITIVE_REAL");

CLI::Validator
integerAtLeast(int minimum)
{
    return CLI::Validator(
        [minimum](std::string& text) -> std::string {
            int value = 0;
            if (!parseInteger(text, value)) return "expected an integer, got '" + text + "'";
            if (value < minimum) {
                return "must be at least " + std::to_string(minimum) + ", got " + text;
            }
            return std::string();
        },
        "", "INTEGER");
}

const CLI::Validator LABEL(
    [](std::string& text) -> std::string {
        vdbi::Label value = 0;
        if (!parseInteger(text, value)) return "expected an integer label, got '" + text + "'";
        return std::string();
    },
    "", "LABEL");

const CLI::Validator CONSTRAINT(
    [](std::string& text) -> std::string {
        vdbi::SeparationConstraint constraint;
        return parseConstraint(text, constraint);
    },
    "", "CONSTRAINT");

const CLI::Validator MESH_EXTENSION(
    [](std::string& path) -> std::string {
        const std::string ext = lowerExtension(path);
        if (ext == ".ply" || ext == ".obj" || ext == ".vtp") return std::string();
        return "'" + path + "': unknown output format " + quotedExtension(path)
            + " (expected .ply, .obj or .vtp)";
    },
    "", "MESH");

const CLI::Validator VOLUME_EXTENSION(
    [](std::string& path) -> std::string {
        const std::string ext = lowerExtension(path);
        if (ext == ".vdb" || ext == ".vox" || ext == ".mhd" || ext == ".mha") {
            return std::string();
        }
        return "'" + path + "': unknown input format " + quotedExtension(path)
            + " (expected .vdb, .vox, .mhd or .mha)";
    },
    "", "VOLUME");

// ---------------------------------------------------------------------------------------
// Command line

const char* const DESCRIPTION =
    "Triangle meshes of the interfaces between the labels of a 3D label volume:\n"
    "consistent, manifold patches, one per pair of adjacent labels, after removing\n"
    "the critical configurations (Bischoff & Kobbelt 2006).";

const char* const FOOTER =
    "Input formats (by extension):\n"
    "  .vdb       OpenVDB: the first Int32 grid, or the one named by --grid. Int64, Bool,\n"
    "             Float and Double grids are converted exactly when every value is an\n"
    "             integer in int32 range.\n"
    "  .vox       MagicaVoxel: palette index per voxel, 0 is empty.\n"
    "  .mhd/.mha  MetaImage with integer voxels.\n"
    "\n"
    "Output formats (-o, by extension):\n"
    "  .ply  binary little-endian, float x y z, triangles with int face properties\n"
    "        label0 < label1\n"
    "  .obj  one group per patch, named patch_A_B (an m marks a negative label:\n"
    "        patch_m3_5 is between -3 and 5)\n"
    "  .vtp  VTK XML PolyData with the 2-component cell array BoundaryLabels\n"
    "  Triangles of patch (A, B) are counter-clockwise seen from label B.\n"
    "  --per-label writes DIR/label_L.stl or .ply (label_m3 for -3), one closed, outward\n"
    "  oriented surface per label but the background; DIR is created if missing.\n"
    "\n"
    "Every patch is remeshed towards --edge-length (default one voxel), its boundary\n"
    "curves smoothed and shared with its neighbours: every patch stays a manifold and\n"
    "every label closed. At longer edge lengths a few triangles may cross where patches\n"
    "meet at sharp angles. --no-remesh writes the raw extraction instead: the voxel faces\n"
    "themselves, exact to the input, in a fraction of the time.\n"
    "\n"
    "Files are written to a temporary name and renamed when complete: a failed or\n"
    "interrupted run never leaves a partial output.\n"
    "\n"
    "Exit status: 0 success, 1 runtime error (vdb_interfaces: FILE: problem), 2 bad\n"
    "command line, 128+N on signal N (130 for Ctrl-C).\n"
    "\n"
    "Example:\n"
    "  vdb_interfaces labels.vox -o interfaces.ply --per-label surfaces --stats";

void
configure(CLI::App& app, Settings& s)
{
    app.footer(FOOTER);
    app.get_formatter()->column_width(26);
    app.set_help_flag("-h,--help", "Print this help and exit");
    app.set_version_flag("--version", std::string(PROGRAM) + " " + VDBI_VERSION,
        "Print the version and exit");

    // Descriptions are wrapped by hand: CLI11 does not wrap.
    app.add_option("INPUT", s.input, "Label volume: .vdb, .vox, .mhd or .mha")
        ->type_name("FILE")
        ->required()
        ->check(VOLUME_EXTENSION);

    CLI::Option* perLabel;
    app.add_option("-o,--output", s.output, "Interface mesh to write: .ply, .obj or .vtp")
        ->type_name("FILE")
        ->check(MESH_EXTENSION);
    perLabel = app.add_option("--per-label", s.perLabelDir,
        "Write one closed surface per label into DIR\n(created if missing)")
        ->type_name("DIR");
    app.add_option("--per-label-format", s.perLabelFormat,
        "Format of the per-label surfaces, binary STL\nor binary PLY (default: stl)")
        ->type_name("stl|ply")
        ->check(CLI::IsMember({"stl", "ply"}, CLI::ignore_case).description(""))
        ->needs(perLabel);
    app.add_option("--grid", s.gridName,
        ".vdb input: the grid to read (default: the\nfirst Int32 grid)")
        ->type_name("NAME");
    app.add_option("--threads", s.threads, "Use at most N >= 1 threads (default: all)")
        ->type_name("N")
        ->check(integerAtLeast(1));
    app.add_option("--priority", s.priority,
        "Labels in priority order for repairing\ncritical elements (default: smallest first)")
        ->type_name("L1,L2,...")
        ->delimiter(',')
        ->allow_extra_args(false)
        ->check(LABEL);
    app.add_option("--separate", s.separate,
        "Labels A and B are always separated by label\nC (repeatable)")
        ->type_name("A,B:C")
        ->allow_extra_args(false)
        ->check(CONSTRAINT);
    CLI::Option* noRemesh = app.add_flag("--no-remesh", s.noRemesh,
        "Write the raw extraction, the voxel faces\nthemselves, instead of remeshing");
    app.add_flag("--remesh", "Remesh (the default; see below)")
        ->excludes(noRemesh);
    app.add_option("--edge-length", s.edgeLength,
        "Remeshing: target edge length in world\nunits, X > 0 (default: one voxel)")
        ->type_name("X")
        ->check(POSITIVE_REAL)
        ->excludes(noRemesh);
    app.add_option("--iterations", s.iterations,
        "Remeshing: number of iterations, N >= 0\n(default: "
        + std::to_string(vdbi::Options().iterations) + ")")
        ->type_name("N")
        ->check(integerAtLeast(0))
        ->excludes(noRemesh);
    app.add_flag("--stats", s.stats,
        "Print statistics to stdout: labels, critical\nelements, subdivided voxels, patches,\n"
        "triangles, meeting triangle pairs, far voxel\nface centres, seconds per stage, peak\n"
        "memory");
    app.add_option("--report", s.reportPath, "Write the same statistics as JSON to FILE")
        ->type_name("FILE");
}

/// OpenVDB's what() reads "IoError: path: problem"; the type name is noise to a user.
std::string
withoutTypePrefix(const std::string& message)
{
    const std::size_t colon = message.find(": ");
    if (colon != std::string::npos && colon >= 5
        && message.compare(colon - 5, 5, "Error") == 0
        && std::all_of(message.begin(), message.begin() + colon,
               [](unsigned char c) { return std::isalpha(c); }))
    {
        return message.substr(colon + 2);
    }
    return message;
}

/// The checks CLI11 cannot express; throws UsageError.
void
checkCombination(const Settings& s)
{
    if (s.output.empty() && s.perLabelDir.empty() && !s.stats && s.reportPath.empty()) {
        throw UsageError("nothing to do: give at least one of -o/--output, --per-label, "
            "--stats, --report");
    }
    if (!s.gridName.empty() && lowerExtension(s.input) != ".vdb") {
        throw UsageError("--grid: applies to .vdb input only, not '" + s.input + "'");
    }
    try {
        vdbi::LabelPriority priority(s.priority);
    } catch (const openvdb::Exception& e) {
        throw UsageError("--priority: " + withoutTypePrefix(e.what()));
    }
    std::vector<vdbi::SeparationConstraint> constraints;
    for (const std::string& text : s.separate) {
        constraints.emplace_back();
        parseConstraint(text, constraints.back()); // checked by the validator
    }
    try {
        vdbi::validateConstraints(constraints);
    } catch (const openvdb::Exception& e) {
        throw UsageError("--separate: " + withoutTypePrefix(e.what()));
    }
}

// ---------------------------------------------------------------------------------------
// File system checks before any work

std::string
systemMessage(int errnum)
{
    return std::strerror(errnum);
}

/// The folder a file will be written to ("." for a bare name).
fs::path
folderOf(const std::string& path)
{
    const fs::path parent = fs::path(path).parent_path();
    return parent.empty() ? fs::path(".") : parent;
}

void
checkWritableFolder(const std::string& file, const fs::path& folder)
{
    std::error_code ec;
    if (!fs::exists(folder, ec)) {
        throw CheckError(file + ": folder " + folder.string() + " does not exist");
    }
    if (!fs::is_directory(folder, ec)) {
        throw CheckError(file + ": " + folder.string() + " is not a folder");
    }
    if (::access(folder.c_str(), W_OK | X_OK) != 0) {
        throw CheckError(file + ": folder " + folder.string() + " is not writable: "
            + systemMessage(errno));
    }
}

bool
isSameFile(const std::string& a, const std::string& b)
{
    std::error_code ec;
    return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec);
}

/// An output file: its folder must exist and be writable, it must not be the input nor an
/// existing folder.
void
checkOutputFile(const std::string& file, const Settings& s)
{
    checkWritableFolder(file, folderOf(file));
    std::error_code ec;
    if (fs::is_directory(file, ec)) throw CheckError(file + ": is a folder");
    if (isSameFile(file, s.input)) throw CheckError(file + ": is the input file");
}

void
checkFiles(const Settings& s)
{
    std::error_code ec;
    const fs::file_status status = fs::status(s.input, ec);
    if (!fs::exists(status)) throw CheckError(s.input + ": " + systemMessage(ENOENT));
    if (fs::is_directory(status)) throw CheckError(s.input + ": is a folder, not a file");
    if (std::FILE* f = std::fopen(s.input.c_str(), "rb")) {
        std::fclose(f);
    } else {
        throw CheckError(s.input + ": cannot open for reading: " + systemMessage(errno));
    }
    if (fs::is_regular_file(status) && fs::file_size(s.input, ec) == 0) {
        throw CheckError(s.input + ": empty file");
    }

    if (!s.output.empty()) checkOutputFile(s.output, s);
    if (!s.reportPath.empty()) {
        checkOutputFile(s.reportPath, s);
        if (!s.output.empty() && (s.reportPath == s.output || isSameFile(s.reportPath, s.output)))
        {
            throw CheckError(s.reportPath + ": is also the mesh output");
        }
    }
    if (!s.perLabelDir.empty()) {
        // An existing folder must be writable; a missing one is created later, so its
        // nearest existing ancestor must be.
        fs::path dir(s.perLabelDir);
        if (fs::exists(dir, ec)) {
            if (!fs::is_directory(dir, ec)) {
                throw CheckError(s.perLabelDir + ": exists and is not a folder");
            }
            checkWritableFolder(s.perLabelDir, dir);
        } else {
            fs::path ancestor = fs::absolute(dir, ec).parent_path();
            while (!ancestor.empty() && !fs::exists(ancestor, ec)) {
                ancestor = ancestor.parent_path();
            }
            checkWritableFolder(s.perLabelDir, ancestor);
        }
    }
}

// ---------------------------------------------------------------------------------------
// Progress and report

/// Prints stage names when stderr is a terminal: the CLI's own (reading, writing) and the
/// library's (critical elements, ..., remeshing), which it announces through start().
class Progress : public openvdb::util::NullInterrupter
{
public:
    Progress() : mEnabled(::isatty(STDERR_FILENO) == 1) {}
    bool isEnabled() const { return mEnabled; }
    void start(const char* name) override
    {
        if (mEnabled && name) std::cerr << PROGRAM << ": " << name << std::endl;
    }
    void stage(const std::string& name) { start(name.c_str()); }

private:
    bool mEnabled;
};

void
writeReport(const std::string& path, const vdbi::RunReport& report)
{
    vdbi::writeFileAtomically(path,
        [&](std::ostream& os) { vdbi::writeRunReportJson(os, report); }, /*binary=*/false);
}

// ---------------------------------------------------------------------------------------

double
secondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void
run(const Settings& s)
{
    checkFiles(s);

    std::unique_ptr<tbb::global_control> threadLimit;
    if (s.threads > 0) {
        threadLimit = std::make_unique<tbb::global_control>(
            tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(s.threads));
    }

    Progress progress;
    vdbi::RunReport report;
    report.program = PROGRAM;
    report.version = VDBI_VERSION;
    report.input = s.input;
    const auto start = std::chrono::steady_clock::now();

    auto clock = std::chrono::steady_clock::now();
    progress.stage("reading " + s.input);
    vdbi::ReadOptions readOptions;
    readOptions.gridName = s.gridName;
    const openvdb::Int32Grid::Ptr grid = vdbi::readLabelVolume(s.input, readOptions);
    report.stages.emplace_back("read", secondsSince(clock));

    vdbi::Options options;
    options.repair.priority = vdbi::LabelPriority(s.priority);
    for (const std::string& text : s.separate) {
        options.repair.constraints.emplace_back();
        parseConstraint(text, options.repair.constraints.back());
    }
    options.repair.interrupter = progress.isEnabled() ? &progress : nullptr;
    options.remesh = !s.noRemesh;
    options.pointKeys = false; // for stitching tiles; the writers do not use them
    options.edgeLength = s.edgeLength;
    options.iterations = s.iterations;

    vdbi::Result result = vdbi::extractInterfaces(*grid, options);
    report.statistics = result.statistics;
    report.stages.insert(report.stages.end(), result.statistics.stageSeconds.begin(),
        result.statistics.stageSeconds.end());
    // The mesh is still written (every other guarantee holds), but not silently.
    const std::string warning = vdbi::runWarning(result.statistics);
    if (!warning.empty()) std::cerr << PROGRAM << ": warning: " << warning << std::endl;

    clock = std::chrono::steady_clock::now();
    if (!s.output.empty()) {
        progress.stage("writing " + s.output);
        vdbi::writeInterfaceMesh(result.mesh, s.output);
    }
    if (!s.perLabelDir.empty()) {
        progress.stage("writing per-label surfaces to " + s.perLabelDir);
        std::error_code ec;
        fs::create_directories(s.perLabelDir, ec);
        if (ec) {
            OPENVDB_THROW(openvdb::IoError, s.perLabelDir << ": cannot create folder: "
                << ec.message());
        }
        vdbi::writePerLabelSurfaces(result.mesh, s.perLabelDir, s.perLabelFormat,
            grid->background());
    }
    if (!s.output.empty() || !s.perLabelDir.empty()) {
        report.stages.emplace_back("write", secondsSince(clock));
    }
    report.totalSeconds = secondsSince(start);
    report.peakMemoryBytes = vdbi::peakResidentMemoryBytes();

    if (s.stats) vdbi::printRunReport(std::cout, report);
    if (!s.reportPath.empty()) writeReport(s.reportPath, report);
    std::cout << std::flush;
    if (!std::cout) OPENVDB_THROW(openvdb::IoError, "stdout: write failed");
}

int
usageError(const std::string& message)
{
    std::cerr << PROGRAM << ": " << message << "\n"
              << USAGE_LINE << "\n"
              << "Run 'vdb_interfaces --help' for all options.\n";
    return 2;
}

int
runtimeError(const std::string& message)
{
    std::cerr << PROGRAM << ": " << message << std::endl;
    return 1;
}

/// @brief On SIGINT, SIGTERM or SIGHUP: remove the temporary files of unfinished writes,
/// then exit with 128 + the signal number.
/// @details The signals are blocked in every thread (threads started later, TBB's included,
/// inherit the mask) and taken by one thread with sigwait(), so the cleanup runs as ordinary
/// code rather than in a signal handler.
void
removeTemporariesOnSignal()
{
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    sigaddset(&signals, SIGHUP);
    if (pthread_sigmask(SIG_BLOCK, &signals, nullptr) != 0) return;
    std::thread([signals]() {
        int signal = 0;
        if (sigwait(&signals, &signal) != 0) return;
        vdbi::removeAllTemporaryFiles();
        const char message[] = "vdb_interfaces: interrupted\n";
        [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, message,
            sizeof message - 1);
        std::_Exit(128 + signal);
    }).detach();
}

} // namespace

int
main(int argc, char* argv[])
{
    vdbi::restartWithHugePages(argv); // before any thread or signal mask: see HugePages.h
    removeTemporariesOnSignal();
    openvdb::initialize();

    Settings settings;
    CLI::App app(DESCRIPTION, PROGRAM);
    configure(app, settings);
    try {
        app.parse(argc, argv);
        checkCombination(settings);
    } catch (const CLI::Success& e) {
        return app.exit(e); // --help, --version: stdout, status 0
    } catch (const CLI::ParseError& e) {
        return usageError(e.what());
    } catch (const UsageError& e) {
        return usageError(e.what());
    }

    try {
        run(settings);
    } catch (const CheckError& e) {
        return runtimeError(e.what());
    } catch (const openvdb::Exception& e) {
        return runtimeError(withoutTypePrefix(e.what()));
    } catch (const std::bad_alloc&) {
        return runtimeError("out of memory");
    } catch (const std::exception& e) {
        return runtimeError(e.what());
    }
    return 0;
}
