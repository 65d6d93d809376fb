// SPDX-License-Identifier: Apache-2.0

#include <vdbi/VoxReader.h>

#include "support/TestData.h"
#include "support/TestFiles.h"

#include <openvdb/Exceptions.h>

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using vdbi_test::Bytes;
using vdbi_test::expectError;
using vdbi_test::readBytes;
using vdbi_test::writeBytes;

void
putInt32(Bytes& bytes, std::size_t offset, std::int32_t value)
{
    std::uint32_t u;
    std::memcpy(&u, &value, 4);
    for (int i = 0; i < 4; ++i) bytes[offset + i] = (u >> (8 * i)) & 0xff;
}

void
appendInt32(Bytes& bytes, std::int32_t value)
{
    bytes.resize(bytes.size() + 4);
    putInt32(bytes, bytes.size() - 4, value);
}

Bytes
chunk(const char* id, const Bytes& content, const Bytes& children = Bytes())
{
    Bytes bytes(id, id + 4);
    appendInt32(bytes, std::int32_t(content.size()));
    appendInt32(bytes, std::int32_t(children.size()));
    bytes.insert(bytes.end(), content.begin(), content.end());
    bytes.insert(bytes.end(), children.begin(), children.end());
    return bytes;
}

Bytes
sizeChunk(int x, int y, int z)
{
    Bytes content;
    appendInt32(content, x);
    appendInt32(content, y);
    appendInt32(content, z);
    return chunk("SIZE", content);
}

Bytes
xyziChunk(const std::vector<std::array<unsigned char, 4>>& voxels)
{
    Bytes content;
    appendInt32(content, std::int32_t(voxels.size()));
    for (const auto& v : voxels) content.insert(content.end(), v.begin(), v.end());
    return chunk("XYZI", content);
}

Bytes
voxFile(const std::vector<Bytes>& children, std::int32_t version = 150)
{
    Bytes all;
    for (const Bytes& c : children) all.insert(all.end(), c.begin(), c.end());
    Bytes bytes{'V', 'O', 'X', ' '};
    appendInt32(bytes, version);
    const Bytes main = chunk("MAIN", Bytes(), all);
    bytes.insert(bytes.end(), main.begin(), main.end());
    return bytes;
}

std::set<openvdb::Int32>
storedLabels(const openvdb::Int32Grid& grid)
{
    std::set<openvdb::Int32> labels;
    for (auto it = grid.cbeginValueOn(); it; ++it) labels.insert(*it);
    return labels;
}

} // namespace

class TestVoxReader : public ::testing::Test
{
protected:
    void SetUp() override
    {
        mKnight = readBytes(vdbi_test::dataPath("chr_knight.vox"));
        ASSERT_EQ(mKnight.size(), 2688u);
    }
    /// Writes @a bytes to a file of the temporary folder and returns its path.
    std::string write(const std::string& name, const Bytes& bytes) const
    {
        const std::string path = mFolder.file(name);
        writeBytes(path, bytes);
        return path;
    }

    // chr_knight.vox: MAIN at 8, SIZE at 20, XYZI at 44 (count at 56, voxels from 60).
    static constexpr std::size_t SIZE_OFFSET = 20, XYZI_OFFSET = 44, FIRST_VOXEL = 60;

    vdbi_test::TempFolder mFolder;
    Bytes mKnight;
};

TEST_F(TestVoxReader, testKnight)
{
    const auto grid = vdbi::readVox(vdbi_test::dataPath("chr_knight.vox"));
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->activeVoxelCount(), 398u);
    EXPECT_EQ(storedLabels(*grid).size(), 21u);
    EXPECT_EQ(grid->background(), 0);
    EXPECT_EQ(grid->tree().activeTileCount(), 0u);
    // The first XYZI records, at the file's own x, y, z.
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(0, 10, 10)), 247);
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(0, 10, 9)), 247);
    EXPECT_EQ(grid->evalActiveVoxelBoundingBox(),
              openvdb::CoordBBox(openvdb::Coord(0, 7, 0), openvdb::Coord(17, 14, 14)));
    EXPECT_TRUE(grid->transform().isIdentity());
    EXPECT_EQ(grid->voxelSize(), openvdb::Vec3d(1.0));
}

TEST_F(TestVoxReader, testSampleTable)
{
    // tests/data/README.md: size, voxels, distinct labels.
    struct Row { const char* file; int x, y, z; openvdb::Index64 voxels; std::size_t labels; };
    const Row rows[] = {
        {"chr_knight.vox", 20, 21, 20, 398, 21},
        {"monu1.vox", 126, 126, 118, 156942, 8},
        {"monu16.vox", 117, 117, 126, 194300, 12},
        {"menger.vox", 81, 81, 81, 160000, 1},
    };
    for (const Row& row : rows) {
        SCOPED_TRACE(row.file);
        const auto grid = vdbi::readVox(vdbi_test::dataPath(row.file));
        EXPECT_EQ(grid->activeVoxelCount(), row.voxels);
        const auto labels = storedLabels(*grid);
        EXPECT_EQ(labels.size(), row.labels);
        EXPECT_EQ(labels.count(0), 0u); // the background is never stored
        EXPECT_GE(*labels.begin(), 1);
        EXPECT_LE(*labels.rbegin(), 255);
        const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
        EXPECT_TRUE(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(row.x - 1, row.y - 1,
            row.z - 1)).isInside(box));
    }
    // menger fills its whole SIZE box.
    EXPECT_EQ(vdbi::readVox(vdbi_test::dataPath("menger.vox"))->evalActiveVoxelBoundingBox(),
              openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(80)));
}

TEST_F(TestVoxReader, testMonu16PackHoldsOneModel)
{
    const Bytes bytes = readBytes(vdbi_test::dataPath("monu16.vox"));
    // PACK is the first child of MAIN; its content is the model count.
    ASSERT_EQ(std::string(bytes.begin() + 20, bytes.begin() + 24), "PACK");
    EXPECT_EQ(bytes[32] | (bytes[33] << 8) | (bytes[34] << 16) | (bytes[35] << 24), 1);
    EXPECT_EQ(vdbi::readVox(vdbi_test::dataPath("monu16.vox"))->activeVoxelCount(), 194300u);
}

TEST_F(TestVoxReader, testFirstModelOnly)
{
    Bytes pack;
    appendInt32(pack, 2);
    const Bytes file = voxFile({chunk("PACK", pack),
        sizeChunk(4, 4, 4), xyziChunk({{{0, 0, 0, 5}}, {{3, 2, 1, 7}}}),
        sizeChunk(2, 2, 2), xyziChunk({{{1, 1, 1, 9}}})});
    const auto grid = vdbi::readVoxBuffer(file.data(), file.size(), "two-models");
    EXPECT_EQ(grid->activeVoxelCount(), 2u);
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(0, 0, 0)), 5);
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(3, 2, 1)), 7);
    EXPECT_FALSE(grid->tree().isValueOn(openvdb::Coord(1, 1, 1)));
}

TEST_F(TestVoxReader, testSkipsOtherChunksAndVersion200)
{
    Bytes rgba(1024, 0x7f);
    Bytes node{1, 2, 3, 4, 5, 6, 7, 8};
    const Bytes file = voxFile({chunk("nTRN", node, chunk("nSHP", node)), chunk("MATL", node),
        sizeChunk(3, 3, 3), chunk("LAYR", Bytes()), chunk("????", node),
        // Index 0 means "empty" and stays background; duplicates: the last record wins.
        xyziChunk({{{0, 1, 2, 200}}, {{2, 2, 2, 0}}, {{1, 1, 1, 3}}, {{1, 1, 1, 4}}}),
        chunk("RGBA", rgba), chunk("rOBJ", node), chunk("IMAP", Bytes(256, 1))}, 200);
    const auto grid = vdbi::readVoxBuffer(file.data(), file.size(), "v200");
    EXPECT_EQ(grid->activeVoxelCount(), 2u);
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(0, 1, 2)), 200);
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(1, 1, 1)), 4);
    EXPECT_FALSE(grid->tree().isValueOn(openvdb::Coord(2, 2, 2)));

    // An empty model is a valid, empty grid; bytes after MAIN are ignored.
    Bytes empty = voxFile({sizeChunk(1, 1, 1), xyziChunk({})});
    empty.push_back(42);
    EXPECT_EQ(vdbi::readVoxBuffer(empty.data(), empty.size(), "empty")->activeVoxelCount(), 0u);
}

TEST_F(TestVoxReader, testMissingEmptyAndDirectory)
{
    const std::string missing = mFolder.file("missing.vox");
    expectError<openvdb::IoError>([&] { vdbi::readVox(missing); }, missing, "no such file");
    const std::string empty = this->write("empty.vox", Bytes());
    expectError<openvdb::IoError>([&] { vdbi::readVox(empty); }, empty, "empty");
    const std::string dir = mFolder.file("folder.vox");
    fs::create_directories(dir);
    expectError<openvdb::IoError>([&] { vdbi::readVox(dir); }, dir, "directory");
}

TEST_F(TestVoxReader, testBadFiles)
{
    const auto patched = [&](std::size_t offset, std::int32_t value) {
        Bytes bytes = mKnight;
        putInt32(bytes, offset, value);
        return bytes;
    };
    struct Case { std::string name; Bytes bytes; std::string word; };
    std::vector<Case> cases = {
        {"truncated.vox", Bytes(mKnight.begin(), mKnight.begin() + 1000), "truncated"},
        {"header-only.vox", Bytes(mKnight.begin(), mKnight.begin() + 8), "no MAIN"},
        {"short.vox", Bytes(mKnight.begin(), mKnight.begin() + 5), "truncated"},
        {"magic.vox", mKnight, "bad magic"},
        {"version.vox", patched(4, 151), "version 151"},
        {"negative.vox", patched(XYZI_OFFSET + 4, -1), "negative size"},
        {"negative-children.vox", patched(XYZI_OFFSET + 8, -16), "negative size"},
        {"huge.vox", patched(XYZI_OFFSET + 4, 0x7ffffff0), "declares 2147483632 bytes"},
        {"huge-main.vox", patched(16, 0x7fffffff), "truncated"},
        {"count.vox", patched(FIRST_VOXEL - 4, 1000), "truncated XYZI chunk"},
        {"negative-count.vox", patched(FIRST_VOXEL - 4, -3), "negative voxel count"},
        {"outside.vox", mKnight, "outside the model SIZE"},
        {"size-zero.vox", patched(SIZE_OFFSET + 12 + 4, 0), "positive"},
        {"no-size.vox", mKnight, "before any SIZE"},
        {"no-xyzi.vox", mKnight, "no XYZI"},
        {"not-main.vox", mKnight, "expects the MAIN chunk"},
    };
    cases[3].bytes[2] = 'Y';
    cases[11].bytes[FIRST_VOXEL] = 20; // x = 20 in a model 20 wide
    std::memcpy(&cases[13].bytes[SIZE_OFFSET], "SIZF", 4);
    std::memcpy(&cases[14].bytes[XYZI_OFFSET], "XYZJ", 4);
    std::memcpy(&cases[15].bytes[8], "MAIM", 4);
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::string path = this->write(c.name, c.bytes);
        expectError<openvdb::IoError>([&] { vdbi::readVox(path); }, path, c.word);
    }
    // A SIZE without its XYZI, with no model at all.
    const Bytes noModel = voxFile({chunk("RGBA", Bytes(1024, 0))});
    expectError<openvdb::IoError>(
        [&] { vdbi::readVoxBuffer(noModel.data(), noModel.size(), "mem.vox"); },
        "mem.vox", "no SIZE");
    const Bytes twoSizes = voxFile({sizeChunk(2, 2, 2), sizeChunk(2, 2, 2)});
    expectError<openvdb::IoError>(
        [&] { vdbi::readVoxBuffer(twoSizes.data(), twoSizes.size(), "mem.vox"); },
        "mem.vox", "follows another SIZE");
    expectError<openvdb::IoError>([&] { vdbi::readVoxBuffer(nullptr, 0, "null"); }, "null",
        "empty");
}

TEST_F(TestVoxReader, testEveryTruncationAndByteFlipFailsCleanly)
{
    // Every proper prefix cuts the MAIN chunk short.
    for (std::size_t size = 0; size < mKnight.size(); ++size) {
        EXPECT_THROW(vdbi::readVoxBuffer(mKnight.data(), size, "prefix"), openvdb::IoError)
            << size;
    }
    // A damaged byte anywhere either still parses or raises IoError: never anything else.
    std::size_t failures = 0;
    for (std::size_t i = 0; i < mKnight.size(); ++i) {
        Bytes bytes = mKnight;
        bytes[i] ^= 0xa5;
        try {
            const auto grid = vdbi::readVoxBuffer(bytes.data(), bytes.size(), "flip");
            EXPECT_LE(grid->activeVoxelCount(), 398u);
        } catch (const openvdb::IoError&) {
            ++failures;
        }
    }
    // The header, MAIN, SIZE and XYZI headers are all checked.
    EXPECT_GE(failures, 40u);
}
