// SPDX-License-Identifier: Apache-2.0
/// @file TestCli.cc
/// @brief Runs the built vdb_interfaces binary on good input: what it writes and prints, and
/// that an interruption leaves no partial file. Bad input: TestBadInput.cc.

#include "support/TestData.h"
#include "support/TestFiles.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <csignal>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#ifdef VDBI_CLI_PATH

namespace fs = std::filesystem;

namespace {

using vdbi_test::listFolder;
using vdbi_test::contains;
using vdbi_test::shellQuote;

std::string
readAll(const fs::path& path)
{
    return vdbi_test::readText(path.string());
}

struct CliResult
{
    int status = -1;
    std::string out, err;
};

} // namespace

class TestCli : public ::testing::Test
{
protected:
    void SetUp() override
    {
        std::random_device rd;
        const fs::path root = fs::temp_directory_path()
            / ("vdbi_cli_" + std::to_string(::getpid()) + "_" + std::to_string(rd()));
        mWork = root / "work";
        mCapture = root / "capture";
        fs::create_directories(mWork);
        fs::create_directories(mCapture);
        mRoot = root;
        mKnight = vdbi_test::dataPath("chr_knight.vox");
    }
    void TearDown() override
    {
        std::error_code ec;
        fs::remove_all(mRoot, ec);
    }

    /// Runs the CLI in the work folder with stdin closed.
    CliResult run(const std::vector<std::string>& args) const
    {
        std::string command = "cd " + shellQuote(mWork.string()) + " && "
            + shellQuote(VDBI_CLI_PATH);
        for (const std::string& arg : args) command += " " + shellQuote(arg);
        command += " </dev/null >" + shellQuote((mCapture / "out").string())
            + " 2>" + shellQuote((mCapture / "err").string());
        CliResult result;
        const int raw = std::system(command.c_str());
        result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
        result.out = readAll(mCapture / "out");
        result.err = readAll(mCapture / "err");
        return result;
    }

    std::string work(const std::string& name) const { return (mWork / name).string(); }

    fs::path mRoot, mWork, mCapture;
    std::string mKnight;
};

TEST_F(TestCli, testHelp)
{
    for (const std::string flag : {"--help", "-h"}) {
        const CliResult r = run({flag});
        EXPECT_EQ(r.status, 0);
        EXPECT_TRUE(r.err.empty()) << r.err;
        const std::vector<std::string> expected = {"-o,--output", "--per-label ",
            "--per-label-format", "--grid", "--threads", "--priority", "--separate",
            "--edge-length", "--iterations", "--no-remesh", "--stats", "--report",
            "-h,--help", "--version", ".vdb", ".vox", ".mhd", ".mha", ".ply", ".obj", ".vtp",
            "Int64", "stl", "BoundaryLabels", "patch_A_B", "--remesh", "Exit status"};
        for (const std::string& e : expected) EXPECT_TRUE(contains(r.out, e)) << e;
    }
}

TEST_F(TestCli, testVersion)
{
    const CliResult r = run({"--version"});
    EXPECT_EQ(r.status, 0);
    EXPECT_EQ(r.out.rfind("vdb_interfaces ", 0), 0u) << r.out;
    ASSERT_GT(r.out.size(), 16u);
    EXPECT_TRUE(std::isdigit(static_cast<unsigned char>(r.out[15]))) << r.out;
    EXPECT_EQ(r.out.back(), '\n');
    EXPECT_TRUE(r.err.empty());
}

TEST_F(TestCli, testWritesEveryFormat)
{
    const CliResult r = run({mKnight, "-o", "knight.ply", "--report", "report.json"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << "stderr is not a terminal, so no progress: " << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_EQ(readAll(work("knight.ply")).rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);

    const std::string report = readAll(work("report.json"));
    for (const std::string key : {"\"program\"", "\"version\"", "\"input\"", "\"labels\"",
             "\"critical_faces\"", "\"critical_edges\"", "\"critical_vertices\"",
             "\"singular_vertices\"", "\"subdivision\"", "\"subdivided_voxels\"",
             "\"relabelled_subvoxels\"", "\"patches\"", "\"triangles\"", "\"vertices\"",
             "\"meeting_triangle_pairs\"", "\"far_voxel_face_centres\"", "\"stages\"",
             "\"total_seconds\"", "\"peak_memory_bytes\""})
    {
        EXPECT_TRUE(contains(report, key)) << key << " in " << report;
    }
    EXPECT_EQ(report.front(), '{');
    EXPECT_EQ(report.substr(report.size() - 2), "}\n");

    ASSERT_EQ(run({mKnight, "-o", "knight.obj"}).status, 0);
    EXPECT_TRUE(contains(readAll(work("knight.obj")), "\ng patch_"));
    ASSERT_EQ(run({mKnight, "-o", "knight.vtp"}).status, 0);
    EXPECT_TRUE(contains(readAll(work("knight.vtp")), "Name=\"BoundaryLabels\""));

    EXPECT_EQ(listFolder(mWork), (std::vector<std::string>{"knight.obj", "knight.ply",
        "knight.vtp", "report.json"}));
}

TEST_F(TestCli, testStats)
{
    const CliResult r = run({mKnight, "--stats"});
    ASSERT_EQ(r.status, 0) << r.err;
    for (const std::string line : {"labels", "critical faces", "critical edges",
             "critical vertices", "singular vertices", "subdivided voxels",
             "relabelled subvoxels", "patches", "triangles", "vertices", "meeting pairs",
             "far face centres", "seconds", "read", "total", "peak memory"})
    {
        EXPECT_TRUE(contains(r.out, line)) << line << " in " << r.out;
    }
    EXPECT_TRUE(listFolder(mWork).empty());
}

TEST_F(TestCli, testPerLabel)
{
    // The folder and its parent are created.
    const CliResult r = run({mKnight, "--per-label", "surfaces/knight", "--report", "r.json"});
    ASSERT_EQ(r.status, 0) << r.err;
    std::size_t files = 0;
    for (const auto& entry : fs::directory_iterator(work("surfaces/knight"))) {
        const std::string name = entry.path().filename().string();
        EXPECT_EQ(name.rfind("label_", 0), 0u) << name;
        EXPECT_EQ(entry.path().extension(), ".stl") << name;
        EXPECT_NE(name, "label_0.stl") << "the background is skipped";
        // Binary STL: 84 bytes of header and count, then 50 per triangle.
        const auto size = entry.file_size();
        EXPECT_TRUE(size > 84 && (size - 84) % 50 == 0) << name << " " << size;
        ++files;
    }
    EXPECT_GT(files, 1u);

    ASSERT_EQ(run({mKnight, "--per-label", "ply", "--per-label-format", "PLY"}).status, 0);
    for (const auto& entry : fs::directory_iterator(work("ply"))) {
        EXPECT_EQ(entry.path().extension(), ".ply");
    }
}

TEST_F(TestCli, testThreadsGiveIdenticalFiles)
{
    for (const std::string ext : {".ply", ".obj", ".vtp"}) {
        ASSERT_EQ(run({mKnight, "--threads", "1", "-o", "one" + ext}).status, 0);
        ASSERT_EQ(run({mKnight, "--threads", "2", "-o", "two" + ext}).status, 0);
        const std::string one = readAll(work("one" + ext)), two = readAll(work("two" + ext));
        EXPECT_FALSE(one.empty());
        EXPECT_TRUE(one == two) << ext << " differs between 1 and 2 threads";
    }
}

TEST_F(TestCli, testInterruptLeavesNoTemporary)
{
    // SIGINT while the temporary output exists: the CLI removes it and exits with 130. If
    // the run finished first, the output is complete and the status 0.
    const std::string script = "cd " + shellQuote(mWork.string()) + " && { "
        + shellQuote(VDBI_CLI_PATH) + " " + shellQuote(vdbi_test::dataPath("menger.vox"))
        + " --no-remesh -o menger.obj 2>" + shellQuote((mCapture / "err").string()) + " & pid=$!; "
        + "while [ ! -e menger.obj.tmp-$pid ] && kill -0 $pid 2>/dev/null; do sleep 0.002; "
        + "done; kill -INT $pid 2>/dev/null; wait $pid; echo $? >"
        + shellQuote((mCapture / "status").string()) + "; }";
    ASSERT_EQ(std::system(script.c_str()), 0);
    const int status = std::stoi(readAll(mCapture / "status"));
    const std::vector<std::string> files = listFolder(mWork);
    if (status == 130) {
        EXPECT_EQ(readAll(mCapture / "err"), "vdb_interfaces: interrupted\n");
        EXPECT_TRUE(files.empty() || files == std::vector<std::string>{"menger.obj"});
    } else {
        EXPECT_EQ(status, 0);
        EXPECT_EQ(files, std::vector<std::string>{"menger.obj"});
    }
    if (!files.empty()) {
        // Present means complete: the last line is a face.
        const std::string obj = readAll(work("menger.obj"));
        EXPECT_EQ(obj.substr(obj.rfind('\n', obj.size() - 2) + 1, 2), "f ");
    }
}

/// The number after "key": in a JSON report.
std::size_t
jsonCount(const std::string& report, const std::string& key)
{
    const std::size_t at = report.find("\"" + key + "\": ");
    return at == std::string::npos ? 0 : std::stoul(report.substr(at + key.size() + 4));
}

TEST_F(TestCli, testRemeshingByDefault)
{
    ASSERT_EQ(run({mKnight, "--report", "default.json", "-o", "default.ply"}).status, 0);
    ASSERT_EQ(run({mKnight, "--report", "remeshed.json", "--remesh", "-o", "remeshed.ply"})
                  .status, 0);
    ASSERT_EQ(run({mKnight, "--report", "raw.json", "--no-remesh"}).status, 0);
    ASSERT_EQ(run({mKnight, "--report", "coarse.json", "--edge-length", "3"}).status, 0);
    const std::string raw = readAll(work("raw.json"));
    const std::string remeshed = readAll(work("remeshed.json"));
    const std::string coarse = readAll(work("coarse.json"));
    EXPECT_FALSE(contains(raw, "\"name\": \"remeshing\""));
    EXPECT_TRUE(contains(readAll(work("default.json")), "\"name\": \"remeshing\""));
    EXPECT_TRUE(contains(remeshed, "\"name\": \"remeshing\""));
    EXPECT_TRUE(contains(coarse, "\"name\": \"remeshing\""));
    // --remesh says what the default does.
    EXPECT_TRUE(readAll(work("default.ply")) == readAll(work("remeshed.ply")));
    // Same repair, so the same patches; a longer target edge gives fewer triangles.
    EXPECT_EQ(jsonCount(remeshed, "patches"), jsonCount(raw, "patches"));
    EXPECT_EQ(jsonCount(coarse, "patches"), jsonCount(raw, "patches"));
    EXPECT_GT(jsonCount(remeshed, "triangles"), 0u);
    EXPECT_NE(jsonCount(remeshed, "triangles"), jsonCount(raw, "triangles"));
    EXPECT_LT(jsonCount(coarse, "triangles"), jsonCount(remeshed, "triangles"));
}

TEST_F(TestCli, testTerminateDuringExtraction)
{
    // SIGTERM 0.3 s into a run on the frog (seconds of CPU on one thread, the outputs come
    // last): status 128 + 15, nothing written, not even the per-label folder. On a loaded
    // machine the signal may come before the CLI handles it (it restarts itself first, see
    // HugePages.h): killed silently, so it is tried again later.
    std::string err;
    int status = 0;
    for (const char* delay : {"0.3", "0.6", "1.0"}) {
        const std::string script = "cd " + shellQuote(mWork.string()) + " && { "
            + shellQuote(VDBI_CLI_PATH) + " " + shellQuote(vdbi_test::dataPath("frogtissue.mhd"))
            + " --threads 1 -o frog.ply --per-label frog --report frog.json 2>"
            + shellQuote((mCapture / "err").string()) + " & pid=$!; sleep " + delay
            + "; kill -TERM $pid; wait $pid; echo $? >"
            + shellQuote((mCapture / "status").string()) + "; }";
        ASSERT_EQ(std::system(script.c_str()), 0);
        status = std::stoi(readAll(mCapture / "status"));
        err = readAll(mCapture / "err");
        if (!(status == 128 + SIGTERM && err.empty())) break;
    }
    EXPECT_EQ(status, 128 + SIGTERM);
    EXPECT_EQ(err, "vdb_interfaces: interrupted\n");
    EXPECT_TRUE(listFolder(mWork).empty());
}

TEST_F(TestCli, testTerminateDuringRemeshing)
{
    // stderr a terminal (script(1) gives one), so the CLI prints its stages; SIGTERM as soon
    // as "remeshing" shows (tens of CPU seconds on the frog at one thread, so no race with its
    // end): status 128 + 15, the progress so far, "interrupted", and no file at all.
    if (std::system("command -v script >/dev/null 2>&1") != 0) {
        GTEST_SKIP() << "script(1) is not installed (util-linux's bsdutils)";
    }
    const std::string log = (mCapture / "log").string(), pid = (mCapture / "pid").string();
    const std::string cli = "echo $$ >" + shellQuote(pid) + "; exec " + shellQuote(VDBI_CLI_PATH)
        + " " + shellQuote(vdbi_test::dataPath("frogtissue.mhd"))
        + " --threads 1 --remesh -o frog.ply --report frog.json";
    const std::string script = "cd " + shellQuote(mWork.string()) + " && { script -qec "
        + shellQuote(cli) + " /dev/null >" + shellQuote(log) + " 2>&1 </dev/null & spid=$!; "
        + "until grep -q 'vdb_interfaces: remeshing' " + shellQuote(log) + "; do "
        + "kill -0 $spid 2>/dev/null || break; sleep 0.02; done; kill -TERM $(cat "
        + shellQuote(pid) + "); wait $spid; echo $? >" + shellQuote((mCapture / "status").string())
        + "; }";
    ASSERT_EQ(std::system(script.c_str()), 0);
    EXPECT_EQ(std::stoi(readAll(mCapture / "status")), 128 + SIGTERM);
    const std::string text = readAll(mCapture / "log");
    EXPECT_TRUE(contains(text, "vdb_interfaces: critical elements")) << text;
    EXPECT_TRUE(contains(text, "vdb_interfaces: extraction")) << text;
    EXPECT_TRUE(contains(text, "vdb_interfaces: remeshing\r\nvdb_interfaces: interrupted"))
        << text;
    EXPECT_TRUE(listFolder(mWork).empty());
}

TEST_F(TestCli, testOptionsAccepted)
{
    // Every option with a valid value.
    const CliResult r = run({"--priority", "1,2", mKnight, "--separate", "1,2:3", "--separate",
        "4,5:6", "--edge-length", "2", "--iterations", "3", "--remesh", "--threads", "2",
        "-o", "out.ply"});
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(work("out.ply")));
}

#endif // VDBI_CLI_PATH
