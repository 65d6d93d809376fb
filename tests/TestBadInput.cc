// SPDX-License-Identifier: Apache-2.0
/// @file TestBadInput.cc
/// @brief The bad-input matrix: one row per broken file or bad command line. Every row runs
/// the built vdb_interfaces and checks the exit status (2 for a bad command line, 1 for a
/// runtime error), that stderr names the file and the problem, and that the work folder
/// holds exactly what it held before: no output, no temporary, no changed input.

#include "support/TestData.h"
#include "support/TestFiles.h"

#include <openvdb/openvdb.h>
#include <openvdb/points/PointDataGrid.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#ifdef VDBI_CLI_PATH

namespace fs = std::filesystem;

namespace {

using Bytes = std::string;
using vdbi_test::contains;
using vdbi_test::shellQuote;

Bytes
readAll(const fs::path& path)
{
    return vdbi_test::readText(path.string());
}

void
writeAll(const fs::path& path, const Bytes& bytes)
{
    vdbi_test::writeText(path.string(), bytes);
}

/// Every entry below @a dir with its contents ("" for a folder).
std::map<std::string, Bytes>
folderContents(const fs::path& dir)
{
    std::map<std::string, Bytes> contents;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
        const std::string name = fs::relative(entry.path(), dir).string();
        contents[name] = entry.is_regular_file() ? readAll(entry.path()) : Bytes();
    }
    return contents;
}

//////////////////////////////////////// .vox files

Bytes
int32Bytes(std::int32_t value)
{
    Bytes bytes(4, '\0');
    const auto u = static_cast<std::uint32_t>(value);
    for (int i = 0; i < 4; ++i) bytes[i] = char((u >> (8 * i)) & 0xff);
    return bytes;
}

/// A chunk whose header declares @a contentSize (normally the content's size).
Bytes
voxChunk(const char* id, const Bytes& content, const Bytes& children, std::int32_t contentSize)
{
    return std::string(id, 4) + int32Bytes(contentSize)
        + int32Bytes(std::int32_t(children.size())) + content + children;
}

Bytes
voxChunk(const char* id, const Bytes& content, const Bytes& children = Bytes())
{
    return voxChunk(id, content, children, std::int32_t(content.size()));
}

Bytes
voxSize(std::int32_t x, std::int32_t y, std::int32_t z)
{
    return voxChunk("SIZE", int32Bytes(x) + int32Bytes(y) + int32Bytes(z));
}

/// An XYZI chunk declaring @a count voxels, holding @a voxels (x, y, z, colour index each).
Bytes
voxXyzi(std::int32_t count, const std::vector<std::array<unsigned char, 4>>& voxels)
{
    Bytes content = int32Bytes(count);
    for (const auto& v : voxels) content += std::string(v.begin(), v.end());
    return voxChunk("XYZI", content);
}

/// A whole file: magic, version, then MAIN with @a models as children.
Bytes
voxFile(const Bytes& models, const char* magic = "VOX ", std::int32_t version = 150)
{
    return std::string(magic, 4) + int32Bytes(version) + voxChunk("MAIN", Bytes(), models);
}

const std::vector<std::array<unsigned char, 4>> TWO_VOXELS = {{0, 0, 0, 1}, {1, 0, 0, 2}};

//////////////////////////////////////// MetaImage files

/// A header for @a dimSize of @a type, its elements in @a dataFile.
std::string
mhdHeader(const std::string& dimSize, const std::string& type, const std::string& dataFile,
          bool compressed = false)
{
    return "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
           "CompressedData = " + std::string(compressed ? "True" : "False") + "\n"
           "DimSize = " + dimSize + "\nElementType = " + type + "\n"
           "ElementDataFile = " + dataFile + "\n";
}

//////////////////////////////////////// .vdb files

void
writeGrids(const fs::path& path, const openvdb::GridPtrVec& grids)
{
    openvdb::io::File file(path.string());
    file.write(grids);
    file.close();
}

openvdb::Int32Grid::Ptr
smallLabels()
{
    auto grid = openvdb::Int32Grid::create(0);
    grid->setName("labels");
    for (int i = 0; i < 3000; ++i) {
        grid->tree().setValue(openvdb::Coord(i % 40, i % 7, i / 40), 1 + i % 5);
    }
    return grid;
}

void
truncateFile(const fs::path& path, double fraction)
{
    fs::resize_file(path, std::uintmax_t(double(fs::file_size(path)) * fraction));
}

//////////////////////////////////////// the matrix

/// One bad input. The CLI runs in a fresh work folder holding knight.vox (a valid input) and
/// whatever @a makeFiles adds; paths in @a args and @a file are relative to that folder.
struct BadInputCase
{
    const char* name;
    void (*makeFiles)(const fs::path& work);
    std::vector<std::string> args;
    int status;          ///< 2: bad command line; 1: runtime error
    std::string file;    ///< named by the message; empty when the problem has no file
    std::string problem; ///< a part of the message that says what is wrong
    /// Run the CLI as an unprivileged user when the test runs as root, who writes through
    /// any mode bits (see TestBadInput.testRow).
    bool needsUnprivileged = false;
};

/// gtest prints a failing row by its name rather than as bytes.
void
PrintTo(const BadInputCase& row, std::ostream* os)
{
    *os << row.name;
}

void
noFiles(const fs::path&)
{
}

std::vector<BadInputCase>
badInputCases()
{
    const int USAGE = 2, RUNTIME = 1;
    std::vector<BadInputCase> rows = {
        // Files that are not there or hold nothing.
        {"missingFile", noFiles, {"absent.vox", "-o", "out.ply"}, RUNTIME, "absent.vox",
            "No such file or directory"},
        {"emptyFile", [](const fs::path& w) { writeAll(w / "empty.vox", ""); },
            {"empty.vox", "-o", "out.ply", "--report", "r.json"}, RUNTIME, "empty.vox",
            "empty file"},
        {"inputIsFolder", [](const fs::path& w) { fs::create_directory(w / "dir.vdb"); },
            {"dir.vdb", "-o", "out.ply"}, RUNTIME, "dir.vdb", "is a folder"},

        // .vdb
        {"truncatedVdb",
            [](const fs::path& w) {
                writeGrids(w / "cut.vdb", {smallLabels()});
                truncateFile(w / "cut.vdb", 0.5);
            },
            {"cut.vdb", "-o", "out.ply"}, RUNTIME, "cut.vdb", "truncated"},
        {"notAVdb", [](const fs::path& w) { writeAll(w / "text.vdb", "just some text\n"); },
            {"text.vdb", "-o", "out.ply"}, RUNTIME, "text.vdb", "cannot read as a .vdb"},
        {"vdbWithoutGrids", [](const fs::path& w) { writeGrids(w / "none.vdb", {}); },
            {"none.vdb", "-o", "out.ply"}, RUNTIME, "none.vdb", "no grids"},
        {"vdbFloatLevelSet",
            [](const fs::path& w) {
                auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
                    5.f, openvdb::Vec3f(0.f), 1.f);
                sphere->setName("sphere");
                writeGrids(w / "sphere.vdb", {sphere});
            },
            {"sphere.vdb", "-o", "out.ply"}, RUNTIME, "sphere.vdb",
            "not an exact int32 label"},
        {"vdbVec3Grid",
            [](const fs::path& w) {
                auto velocity = openvdb::Vec3fGrid::create();
                velocity->setName("velocity");
                velocity->tree().setValue(openvdb::Coord(0), openvdb::Vec3f(1.f));
                writeGrids(w / "velocity.vdb", {velocity});
            },
            {"velocity.vdb", "-o", "out.ply"}, RUNTIME, "velocity.vdb", "'velocity' (vec3s)"},
        {"vdbPointData",
            [](const fs::path& w) {
                auto points = openvdb::points::PointDataGrid::create();
                points->setName("points");
                writeGrids(w / "points.vdb", {points});
            },
            {"points.vdb", "-o", "out.ply"}, RUNTIME, "points.vdb", "'points' (ptdataidx32)"},
        {"vdbGridNameAbsent",
            [](const fs::path& w) { writeGrids(w / "labels.vdb", {smallLabels()}); },
            {"labels.vdb", "--grid", "segmentation", "-o", "out.ply"}, RUNTIME, "labels.vdb",
            "no grid named 'segmentation'"},
        {"vdbAbsurdTiles",
            [](const fs::path& w) {
                // 8 root tiles of 4096^3 voxels: a tiny file, 2 TiB as voxels.
                auto grid = openvdb::Int32Grid::create(0);
                grid->setName("huge");
                grid->tree().sparseFill(openvdb::CoordBBox(openvdb::Coord(0),
                    openvdb::Coord(8191)), 1);
                writeGrids(w / "huge.vdb", {grid});
            },
            {"huge.vdb", "-o", "out.ply"}, RUNTIME, "huge.vdb", "549755813888 voxels"},

        // .vox
        {"truncatedVox",
            [](const fs::path& w) {
                writeAll(w / "cut.vox", readAll(w / "knight.vox").substr(0, 1000));
            },
            {"cut.vox", "-o", "out.ply"}, RUNTIME, "cut.vox", "truncated"},
        {"voxBadMagic",
            [](const fs::path& w) {
                writeAll(w / "magic.vox", voxFile(voxSize(2, 2, 2) + voxXyzi(2, TWO_VOXELS),
                    "VOXL"));
            },
            {"magic.vox", "-o", "out.ply"}, RUNTIME, "magic.vox", "bad magic 'VOXL'"},
        {"voxGarbage",
            [](const fs::path& w) { writeAll(w / "garbage.vox", "not a MagicaVoxel file"); },
            {"garbage.vox", "-o", "out.ply"}, RUNTIME, "garbage.vox", "bad magic"},
        {"voxBadVersion",
            [](const fs::path& w) {
                writeAll(w / "version.vox", voxFile(voxSize(2, 2, 2) + voxXyzi(2, TWO_VOXELS),
                    "VOX ", 999));
            },
            {"version.vox", "-o", "out.ply"}, RUNTIME, "version.vox",
            "unsupported .vox version 999"},
        {"voxNegativeChunkSize",
            [](const fs::path& w) {
                const Bytes size = voxChunk("SIZE", int32Bytes(2) + int32Bytes(2)
                    + int32Bytes(2), Bytes(), -12);
                writeAll(w / "negative.vox", voxFile(size + voxXyzi(2, TWO_VOXELS)));
            },
            {"negative.vox", "-o", "out.ply"}, RUNTIME, "negative.vox",
            "negative size (content -12"},
        {"voxHugeChunkSize",
            [](const fs::path& w) {
                const Bytes size = voxChunk("SIZE", int32Bytes(2) + int32Bytes(2)
                    + int32Bytes(2), Bytes(), 2147483647);
                writeAll(w / "huge.vox", voxFile(size + voxXyzi(2, TWO_VOXELS)));
            },
            {"huge.vox", "-o", "out.ply"}, RUNTIME, "huge.vox", "declares 2147483647 bytes"},
        {"voxXyziCountBeyondChunk",
            [](const fs::path& w) {
                writeAll(w / "count.vox", voxFile(voxSize(2, 2, 2) + voxXyzi(1000, TWO_VOXELS)));
            },
            {"count.vox", "-o", "out.ply"}, RUNTIME, "count.vox", "voxel count 1000"},
        {"voxVoxelOutsideSize",
            [](const fs::path& w) {
                writeAll(w / "outside.vox", voxFile(voxSize(2, 2, 2)
                    + voxXyzi(2, {{0, 0, 0, 1}, {0, 9, 0, 1}})));
            },
            {"outside.vox", "-o", "out.ply"}, RUNTIME, "outside.vox",
            "(0, 9, 0) lies outside the model SIZE 2 x 2 x 2"},

        // MetaImage
        {"mhdMissingDimSize",
            [](const fs::path& w) {
                writeAll(w / "a.mhd", "NDims = 3\nElementType = MET_UCHAR\n"
                    "ElementDataFile = a.raw\n");
                writeAll(w / "a.raw", Bytes(8, '\1'));
            },
            {"a.mhd", "-o", "out.ply"}, RUNTIME, "a.mhd", "missing DimSize"},
        {"mhdMissingElementType",
            [](const fs::path& w) {
                writeAll(w / "a.mhd", "NDims = 3\nDimSize = 2 2 2\nElementDataFile = a.raw\n");
                writeAll(w / "a.raw", Bytes(8, '\1'));
            },
            {"a.mhd", "-o", "out.ply"}, RUNTIME, "a.mhd", "missing ElementType"},
        {"mhdMissingElementDataFile",
            [](const fs::path& w) {
                writeAll(w / "a.mhd", "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\n");
            },
            {"a.mhd", "-o", "out.ply"}, RUNTIME, "a.mhd", "no ElementDataFile line"},
        {"mhdUnknownElementType",
            [](const fs::path& w) {
                writeAll(w / "a.mhd", mhdHeader("2 2 2", "MET_FLOAT", "a.raw"));
                writeAll(w / "a.raw", Bytes(32, '\0'));
            },
            {"a.mhd", "-o", "out.ply"}, RUNTIME, "a.mhd",
            "element type MET_FLOAT is not supported"},
        {"mhdDimSizeProductOverflows",
            [](const fs::path& w) {
                writeAll(w / "a.mhd", mhdHeader("2000000000 2000000000 2000000000", "MET_INT",
                    "a.raw"));
                writeAll(w / "a.raw", Bytes(64, '\1'));
            },
            {"a.mhd", "-o", "out.ply"}, RUNTIME, "a.mhd",
            "2000000000 x 2000000000 x 2000000000 of MET_INT overflows"},
        {"mhdDimSizeBeyondInt32",
            [](const fs::path& w) {
                writeAll(w / "a.mhd", mhdHeader("3000000000 1 1", "MET_UCHAR", "a.raw"));
                writeAll(w / "a.raw", Bytes(64, '\1'));
            },
            {"a.mhd", "-o", "out.ply"}, RUNTIME, "a.mhd",
            "DimSize 3000000000 is beyond the int32 index range"},
        {"mhdDimSizeExceedsData",
            [](const fs::path& w) {
                writeAll(w / "a.mhd", mhdHeader("100000 100000 100000", "MET_UCHAR", "a.raw"));
                writeAll(w / "a.raw", Bytes(64, '\1'));
            },
            {"a.mhd", "-o", "out.ply"}, RUNTIME, "a.mhd",
            "64 bytes of raw data, the header says 1000000000000000"},
        {"mhdRawShorterThanHeader",
            [](const fs::path& w) {
                writeAll(w / "a.mhd", mhdHeader("4 4 4", "MET_SHORT", "a.raw"));
                writeAll(w / "a.raw", Bytes(100, '\1'));
            },
            {"a.mhd", "-o", "out.ply"}, RUNTIME, "a.mhd",
            "truncated: 100 bytes of raw data, the header says 128"},
        {"mhdRawMissing",
            [](const fs::path& w) {
                writeAll(w / "a.mhd", mhdHeader("4 4 4", "MET_SHORT", "gone.raw"));
            },
            {"a.mhd", "-o", "out.ply"}, RUNTIME, "a.mhd", "gone.raw: no such file"},
        {"truncatedMha",
            [](const fs::path& w) {
                writeAll(w / "a.mha", mhdHeader("8 8 8", "MET_UCHAR", "LOCAL")
                    + Bytes(500, '\1'));
            },
            {"a.mha", "-o", "out.ply"}, RUNTIME, "a.mha",
            "truncated: 500 bytes of raw data, the header says 512"},
        {"truncatedZraw",
            [](const fs::path& w) {
                fs::copy_file(vdbi_test::dataPath("frogtissue.mhd"), w / "frog.mhd");
                fs::copy_file(vdbi_test::dataPath("frogtissue.zraw"), w / "frogtissue.zraw");
                truncateFile(w / "frogtissue.zraw", 0.5);
            },
            {"frog.mhd", "-o", "out.ply"}, RUNTIME, "frog.mhd", "truncated"},
        {"zrawAbsurdDimSize",
            [](const fs::path& w) {
                // Deflate inflates at most 1032 times: these bytes cannot hold 10^15.
                writeAll(w / "a.mhd", mhdHeader("100000 100000 100000", "MET_UCHAR",
                    "frogtissue.zraw", /*compressed=*/true));
                fs::copy_file(vdbi_test::dataPath("frogtissue.zraw"), w / "frogtissue.zraw");
            },
            {"a.mhd", "-o", "out.ply"}, RUNTIME, "a.mhd", "needs 1000000000000000 bytes"},

        // The command line.
        {"unknownFlag", noFiles, {"--bogus", "knight.vox", "-o", "out.ply"}, USAGE, "",
            "--bogus"},
        {"unknownShortFlag", noFiles, {"-x", "knight.vox", "-o", "out.ply"}, USAGE, "", "-x"},
        {"missingOutputValue", noFiles, {"knight.vox", "-o"}, USAGE, "", "--output"},
        {"missingThreadsValue", noFiles, {"knight.vox", "-o", "out.ply", "--threads"}, USAGE, "",
            "--threads"},
        {"missingInput", noFiles, {"-o", "out.ply"}, USAGE, "", "INPUT is required"},
        {"nothingToDo", noFiles, {"knight.vox"}, USAGE, "",
            "give at least one of -o/--output, --per-label, --stats, --report"},
        {"edgeLengthNotANumber", noFiles,
            {"knight.vox", "-o", "out.ply", "--edge-length", "abc"}, USAGE, "",
            "--edge-length: expected a number, got 'abc'"},
        {"edgeLengthWithUnit", noFiles,
            {"knight.vox", "-o", "out.ply", "--edge-length", "1.5mm"}, USAGE, "",
            "expected a number, got '1.5mm'"},
        {"edgeLengthNan", noFiles, {"knight.vox", "-o", "out.ply", "--edge-length", "nan"},
            USAGE, "", "expected a number, got 'nan'"},
        {"edgeLengthZero", noFiles, {"knight.vox", "-o", "out.ply", "--edge-length", "0"},
            USAGE, "", "--edge-length: must be greater than 0, got 0"},
        {"edgeLengthNegative", noFiles, {"knight.vox", "-o", "out.ply", "--edge-length=-0.5"},
            USAGE, "", "must be greater than 0, got -0.5"},
        {"remeshAndNoRemesh", noFiles, {"knight.vox", "--stats", "--remesh", "--no-remesh"},
            USAGE, "", "excludes"},
        {"edgeLengthWithoutRemeshing", noFiles,
            {"knight.vox", "--stats", "--no-remesh", "--edge-length", "2"}, USAGE, "",
            "excludes"},
        {"iterationsWithoutRemeshing", noFiles,
            {"knight.vox", "--stats", "--iterations", "2", "--no-remesh"}, USAGE, "", "excludes"},
        {"threadsZero", noFiles, {"knight.vox", "-o", "out.ply", "--threads", "0"}, USAGE, "",
            "--threads: must be at least 1, got 0"},
        {"threadsNotANumber", noFiles, {"knight.vox", "-o", "out.ply", "--threads", "two"},
            USAGE, "", "expected an integer, got 'two'"},
        {"iterationsNegative", noFiles, {"knight.vox", "-o", "out.ply", "--iterations", "-1"},
            USAGE, "", "--iterations: must be at least 0"},
        {"priorityNotALabel", noFiles, {"knight.vox", "-o", "out.ply", "--priority", "3,x"},
            USAGE, "", "expected an integer label, got 'x'"},
        {"priorityTwice", noFiles, {"knight.vox", "-o", "out.ply", "--priority", "3,4,3"},
            USAGE, "", "--priority: label 3"},
        {"constraintWithoutSeparator", noFiles,
            {"knight.vox", "-o", "out.ply", "--separate", "1,2"}, USAGE, "",
            "expected A,B:C with integer labels"},
        {"constraintColonFirst", noFiles,
            {"knight.vox", "-o", "out.ply", "--separate", "1:2,3"}, USAGE, "", "got '1:2,3'"},
        {"constraintSemicolon", noFiles,
            {"knight.vox", "-o", "out.ply", "--separate", "1;2:3"}, USAGE, "", "got '1;2:3'"},
        {"constraintNotNumbers", noFiles,
            {"knight.vox", "-o", "out.ply", "--separate", "a,b:c"}, USAGE, "", "got 'a,b:c'"},
        {"constraintNoSeparatorLabel", noFiles,
            {"knight.vox", "-o", "out.ply", "--separate", "1,2:"}, USAGE, "", "got '1,2:'"},
        {"constraintNoFirstLabel", noFiles,
            {"knight.vox", "-o", "out.ply", "--separate", ",2:3"}, USAGE, "", "got ',2:3'"},
        {"constraintTwoSeparators", noFiles,
            {"knight.vox", "-o", "out.ply", "--separate", "1,2:3:4"}, USAGE, "",
            "got '1,2:3:4'"},
        {"constraintSameLabels", noFiles,
            {"knight.vox", "-o", "out.ply", "--separate", "4,4:2"}, USAGE, "",
            "'4,4:2': the two separated labels must differ"},
        {"constraintSeparatorIsSeparated", noFiles,
            {"knight.vox", "-o", "out.ply", "--separate", "4,2:2"}, USAGE, "",
            "'4,2:2': the separator must differ"},
        {"secondConstraintBad", noFiles,
            {"knight.vox", "--separate", "1,2:3", "-o", "out.ply", "--separate", "5,5:1"}, USAGE,
            "", "'5,5:1'"},
        {"unknownOutputFormat", noFiles, {"knight.vox", "-o", "out.stl"}, USAGE, "out.stl",
            "unknown output format '.stl' (expected .ply, .obj or .vtp)"},
        {"outputWithoutExtension", noFiles, {"knight.vox", "-o", "out"}, USAGE, "out",
            "unknown output format (no extension)"},
        {"unknownInputFormat", [](const fs::path& w) { writeAll(w / "labels.txt", "1 2 3\n"); },
            {"labels.txt", "-o", "out.ply"}, USAGE, "labels.txt", "unknown input format '.txt'"},
        {"inputWithoutExtension", [](const fs::path& w) { writeAll(w / "labels", "1 2 3\n"); },
            {"labels", "-o", "out.ply"}, USAGE, "labels", "unknown input format (no extension)"},
        {"unknownPerLabelFormat", noFiles,
            {"knight.vox", "--per-label", "dir", "--per-label-format", "obj"}, USAGE, "",
            "--per-label-format: obj"},
        {"perLabelFormatAlone", noFiles,
            {"knight.vox", "-o", "out.ply", "--per-label-format", "ply"}, USAGE, "",
            "--per-label-format requires --per-label"},
        {"gridForVox", noFiles, {"knight.vox", "-o", "out.ply", "--grid", "labels"}, USAGE,
            "knight.vox", "--grid: applies to .vdb input only"},

        // Where the output goes.
        {"outputFolderMissing", noFiles, {"knight.vox", "-o", "missing/out.ply"}, RUNTIME,
            "missing/out.ply", "folder missing does not exist"},
        {"reportFolderMissing", noFiles, {"knight.vox", "--report", "missing/r.json"}, RUNTIME,
            "missing/r.json", "folder missing does not exist"},
        {"outputFolderNotWritable",
            [](const fs::path& w) {
                fs::create_directory(w / "locked");
                fs::permissions(w / "locked", fs::perms::owner_read | fs::perms::owner_exec
                    | fs::perms::group_read | fs::perms::group_exec | fs::perms::others_read
                    | fs::perms::others_exec);
            },
            {"knight.vox", "-o", "locked/out.ply"}, RUNTIME, "locked/out.ply",
            "folder locked is not writable: Permission denied", /*needsUnprivileged=*/true},
        {"perLabelFolderNotWritable",
            [](const fs::path& w) {
                fs::create_directory(w / "locked");
                fs::permissions(w / "locked", fs::perms::owner_read | fs::perms::owner_exec
                    | fs::perms::group_read | fs::perms::group_exec | fs::perms::others_read
                    | fs::perms::others_exec);
            },
            {"knight.vox", "--per-label", "locked/surfaces"}, RUNTIME, "locked/surfaces",
            "is not writable: Permission denied", /*needsUnprivileged=*/true},
        {"outputIsFolder", [](const fs::path& w) { fs::create_directory(w / "out.ply"); },
            {"knight.vox", "-o", "out.ply"}, RUNTIME, "out.ply", "is a folder"},
        {"perLabelFolderIsFile", [](const fs::path& w) { writeAll(w / "taken", "x"); },
            {"knight.vox", "--per-label", "taken"}, RUNTIME, "taken",
            "exists and is not a folder"},
        {"outputIsInputByLink",
            [](const fs::path& w) { fs::create_symlink("knight.vox", w / "alias.ply"); },
            {"knight.vox", "-o", "alias.ply"}, RUNTIME, "alias.ply", "is the input file"},
        {"reportIsInput", noFiles, {"knight.vox", "--report", "knight.vox"}, RUNTIME,
            "knight.vox", "is the input file"},
        {"reportIsOutput", noFiles, {"knight.vox", "-o", "out.ply", "--report", "out.ply"},
            RUNTIME, "out.ply", "is also the mesh output"},
    };
    return rows;
}

bool
isRoot()
{
    return ::geteuid() == 0;
}

/// The prefix that runs a command as user and group nobody (65534).
const char* const AS_NOBODY = "setpriv --reuid=65534 --regid=65534 --clear-groups -- ";

} // namespace

class TestBadInput : public ::testing::TestWithParam<BadInputCase>
{
protected:
    static void SetUpTestSuite() { openvdb::initialize(); }

    void SetUp() override
    {
        std::random_device rd;
        mRoot = fs::temp_directory_path()
            / ("vdbi_bad_" + std::to_string(::getpid()) + "_" + std::to_string(rd()));
        mWork = mRoot / "work";
        fs::create_directories(mWork);
        fs::create_directories(mRoot / "capture");
        // Readable for the unprivileged user of some rows.
        fs::permissions(mRoot, fs::perms::others_read | fs::perms::others_exec,
            fs::perm_options::add);
        fs::copy_file(vdbi_test::dataPath("chr_knight.vox"), mWork / "knight.vox");
    }
    void TearDown() override
    {
        std::error_code ec;
        fs::remove_all(mRoot, ec);
    }

    /// Runs @a command in the work folder; its exit status (-1 if it did not exit).
    int shell(const std::string& command) const
    {
        const std::string line = "cd " + shellQuote(mWork.string()) + " && " + command
            + " </dev/null >" + shellQuote((mRoot / "capture" / "out").string()) + " 2>"
            + shellQuote((mRoot / "capture" / "err").string());
        const int raw = std::system(line.c_str());
        return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    }

    std::string captured(const char* stream) const { return readAll(mRoot / "capture" / stream); }

    fs::path mRoot, mWork;
};

TEST_P(TestBadInput, testRow)
{
    const BadInputCase& row = GetParam();
    row.makeFiles(mWork);
    const std::map<std::string, Bytes> before = folderContents(mWork);

    std::string prefix;
    if (row.needsUnprivileged) {
        // Root writes through mode 0555, so the row would test nothing: the CLI runs as
        // nobody instead, after checking that nobody cannot write there indeed.
        if (isRoot()) prefix = AS_NOBODY;
        const int probe = shell(prefix + "touch locked/probe");
        if (probe != 1) {
            fs::remove(mWork / "locked" / "probe");
            GTEST_SKIP() << "cannot make a folder unwritable for the CLI here (touch as "
                << (isRoot() ? "nobody through setpriv" : "this user") << " gave " << probe
                << ")";
        }
        // A build below /root (mode 0700) cannot be loaded by nobody at all.
        const int runs = shell(prefix + shellQuote(VDBI_CLI_PATH) + " --version");
        if (runs != 0) {
            GTEST_SKIP() << "the CLI cannot run as nobody here (status " << runs
                << ": its build folder is not readable by nobody), so no unwritable folder";
        }
    }
    std::string command = prefix + shellQuote(VDBI_CLI_PATH);
    for (const std::string& arg : row.args) command += " " + shellQuote(arg);
    const int status = shell(command);
    const std::string err = captured("err");
    RecordProperty("stderr", err); // in --gtest_output=xml: every row's message to review

    EXPECT_EQ(status, row.status) << err;
    EXPECT_TRUE(captured("out").empty()) << captured("out");
    if (row.status == 2) {
        EXPECT_EQ(err.rfind("vdb_interfaces: ", 0), 0u) << err;
        EXPECT_TRUE(contains(err, row.file)) << row.file << " in " << err;
        EXPECT_TRUE(contains(err, "Usage: vdb_interfaces")) << err;
    } else {
        // One line, "vdb_interfaces: FILE: problem", without OpenVDB's "IoError: ".
        EXPECT_EQ(err.rfind("vdb_interfaces: " + row.file + ": ", 0), 0u) << err;
        EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
        EXPECT_FALSE(contains(err, "Error: ")) << err;
    }
    EXPECT_TRUE(contains(err, row.problem)) << "'" << row.problem << "' in " << err;
    EXPECT_EQ(folderContents(mWork), before)
        << "a failed run left an output or a temporary, or changed a file";
}

INSTANTIATE_TEST_SUITE_P(Rows, TestBadInput, ::testing::ValuesIn(badInputCases()),
    [](const ::testing::TestParamInfo<BadInputCase>& info) { return info.param.name; });

#endif // VDBI_CLI_PATH
