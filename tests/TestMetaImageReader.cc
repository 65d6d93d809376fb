// SPDX-License-Identifier: Apache-2.0

#include <vdbi/MetaImageReader.h>

#include "support/TestData.h"
#include "support/TestFiles.h"

#include <openvdb/Exceptions.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using vdbi_test::Bytes;
using vdbi_test::expectError;
using vdbi_test::readBytes;
using vdbi_test::writeBytes;
using vdbi_test::writeText;
using vdbi::MetaElementType;

const MetaElementType ALL_TYPES[] = {MetaElementType::UChar, MetaElementType::Char,
    MetaElementType::UShort, MetaElementType::Short, MetaElementType::UInt,
    MetaElementType::Int};

/// The extreme values of @a type and a spread of others, zeros (background) in between.
std::int64_t
sampleValue(MetaElementType type, std::size_t i)
{
    std::int64_t lo = 0, hi = 0;
    switch (type) {
        case MetaElementType::UChar: hi = 255; break;
        case MetaElementType::Char: lo = -128; hi = 127; break;
        case MetaElementType::UShort: hi = 65535; break;
        case MetaElementType::Short: lo = -32768; hi = 32767; break;
        // MET_UINT labels must fit int32: the reader rejects larger ones (tested below).
        case MetaElementType::UInt: hi = std::numeric_limits<std::int32_t>::max(); break;
        case MetaElementType::Int: lo = std::numeric_limits<std::int32_t>::min();
            hi = std::numeric_limits<std::int32_t>::max(); break;
    }
    if (i % 3 == 0) return 0;
    if (i == 1) return hi;
    if (i == 2) return lo == 0 ? 1 : lo;
    const std::int64_t span = hi - lo + 1;
    return lo + std::int64_t((i * 2654435761u) % std::uint64_t(span));
}

/// @a values as elements of @a type in the given byte order.
Bytes
encode(const std::vector<std::int64_t>& values, MetaElementType type, bool msb)
{
    const int size = vdbi::metaElementBytes(type);
    Bytes bytes;
    for (const std::int64_t value : values) {
        const std::uint64_t u = std::uint64_t(value);
        for (int b = 0; b < size; ++b) {
            const int shift = 8 * (msb ? size - 1 - b : b);
            bytes.push_back((u >> shift) & 0xff);
        }
    }
    return bytes;
}

/// A zlib stream of stored (uncompressed) deflate blocks: exercises the reader's inflate
/// path without the test depending on zlib.
Bytes
zlibStored(const Bytes& raw)
{
    Bytes out{0x78, 0x01};
    std::size_t offset = 0;
    do {
        const std::size_t length = std::min<std::size_t>(raw.size() - offset, 65535);
        const bool isLast = offset + length == raw.size();
        out.push_back(isLast ? 1 : 0);
        out.push_back(length & 0xff);
        out.push_back(length >> 8);
        out.push_back(~length & 0xff);
        out.push_back((~length >> 8) & 0xff);
        out.insert(out.end(), raw.begin() + offset, raw.begin() + offset + length);
        offset += length;
    } while (offset < raw.size());
    std::uint32_t a = 1, b = 0;
    for (const unsigned char c : raw) {
        a = (a + c) % 65521;
        b = (b + a) % 65521;
    }
    const std::uint32_t adler = (b << 16) | a;
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back((adler >> shift) & 0xff);
    return out;
}

std::set<openvdb::Int32>
storedLabels(const openvdb::Int32Grid& grid)
{
    std::set<openvdb::Int32> labels;
    for (auto it = grid.cbeginValueOn(); it; ++it) labels.insert(*it);
    return labels;
}

} // namespace

class TestMetaImageReader : public ::testing::Test
{
protected:
    std::string path(const std::string& name) const { return mFolder.file(name); }

    /// The frog header with @a from replaced by @a to, its data file named absolutely.
    std::string frogHeader(const std::string& from = "", const std::string& to = "") const
    {
        const Bytes bytes = readBytes(vdbi_test::dataPath("frogtissue.mhd"));
        std::string text(bytes.begin(), bytes.end());
        const std::string dataLine = "ElementDataFile = frogtissue.zraw";
        text.replace(text.find(dataLine), dataLine.size(),
            "ElementDataFile = " + vdbi_test::dataPath("frogtissue.zraw"));
        if (!from.empty()) {
            const std::size_t at = text.find(from);
            EXPECT_NE(at, std::string::npos) << from;
            text.replace(at, from.size(), to);
        }
        return text;
    }

    /// Writes a volume with the given layout as name.mha (LOCAL) or name.mhd + name.raw.
    std::string writeVolume(const std::string& name, const std::array<int, 3>& dims,
                            const std::vector<std::int64_t>& values, MetaElementType type,
                            bool msb, bool compressed, bool single,
                            const std::string& extraKeys = "") const
    {
        Bytes data = encode(values, type, msb);
        if (compressed) data = zlibStored(data);
        std::ostringstream header;
        header << "ObjectType = Image\nNDims = 3\nBinaryData = True\n"
            << "BinaryDataByteOrderMSB = " << (msb ? "True" : "False") << "\n"
            << "CompressedData = " << (compressed ? "True" : "False") << "\n";
        if (compressed) header << "CompressedDataSize = " << data.size() << "\n";
        header << "TransformMatrix = 1 0 0 0 1 0 0 0 1\nOffset = -3 0.5 12\n"
            << "ElementSpacing = 0.5 2 0.25\n" << extraKeys
            << "DimSize = " << dims[0] << " " << dims[1] << " " << dims[2] << "\n"
            << "ElementType = " << vdbi::metaElementTypeName(type) << "\n";
        if (single) {
            header << "ElementDataFile = LOCAL\n";
            const std::string text = header.str();
            Bytes file(text.begin(), text.end());
            file.insert(file.end(), data.begin(), data.end());
            writeBytes(this->path(name + ".mha"), file);
            return this->path(name + ".mha");
        }
        header << "ElementDataFile = " << name << ".raw\n";
        writeText(this->path(name + ".mhd"), header.str());
        writeBytes(this->path(name + ".raw"), data);
        return this->path(name + ".mhd");
    }

    vdbi_test::TempFolder mFolder;
};

TEST_F(TestMetaImageReader, testFrog)
{
    const auto grid = vdbi::readMetaImage(vdbi_test::dataPath("frogtissue.mhd"));
    ASSERT_TRUE(grid);
    // tests/data/README.md; label 0 is the background (30,803,043 voxels) and not stored.
    const std::map<openvdb::Int32, openvdb::Index64> expected = {{1, 35279}, {2, 19172},
        {3, 38129}, {4, 37146}, {5, 16085}, {6, 37030}, {7, 27807}, {8, 39181}, {9, 51297},
        {10, 204672}, {11, 47626}, {12, 24263}, {13, 440722}, {14, 3891}, {15, 133880},
        {16, 252}, {17, 38}, {20, 29}, {21, 4}, {23, 6}, {24, 239}, {25, 121}, {26, 16},
        {27, 32}, {29, 40}};
    std::map<openvdb::Int32, openvdb::Index64> counts;
    for (auto it = grid->cbeginValueOn(); it; ++it) ++counts[*it];
    EXPECT_EQ(counts, expected);
    EXPECT_EQ(grid->activeVoxelCount(), 31960000u - 30803043u);
    EXPECT_EQ(grid->background(), 0);
    EXPECT_EQ(grid->tree().activeTileCount(), 0u);
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(0, 0, 0)), 0);
    // Nothing outside DimSize 500 x 470 x 136.
    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    EXPECT_TRUE(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(499, 469, 135))
        .isInside(box));
    // Spacing 1 1 1.5, Offset 0: voxel centres at ijk * spacing.
    EXPECT_EQ(grid->voxelSize(), openvdb::Vec3d(1.0, 1.0, 1.5));
    EXPECT_EQ(grid->indexToWorld(openvdb::Coord(2, 3, 4)), openvdb::Vec3d(2.0, 3.0, 6.0));
}

TEST_F(TestMetaImageReader, testRoundTripEveryLayout)
{
    const std::array<int, 3> dims{{7, 5, 3}};
    for (const MetaElementType type : ALL_TYPES) {
        std::vector<std::int64_t> values(dims[0] * dims[1] * dims[2]);
        for (std::size_t i = 0; i < values.size(); ++i) values[i] = sampleValue(type, i);
        for (const bool msb : {false, true}) {
            for (const bool compressed : {false, true}) {
                for (const bool single : {false, true}) {
                    const std::string name = std::string(vdbi::metaElementTypeName(type))
                        + (msb ? "_msb" : "_lsb") + (compressed ? "_z" : "_raw")
                        + (single ? "_mha" : "_mhd");
                    SCOPED_TRACE(name);
                    const auto grid = vdbi::readMetaImage(
                        this->writeVolume(name, dims, values, type, msb, compressed, single));
                    openvdb::Index64 nonZero = 0;
                    std::size_t i = 0;
                    for (int z = 0; z < dims[2]; ++z) {
                        for (int y = 0; y < dims[1]; ++y) {
                            for (int x = 0; x < dims[0]; ++x, ++i) {
                                const openvdb::Coord ijk(x, y, z);
                                EXPECT_EQ(grid->tree().getValue(ijk), values[i]) << ijk;
                                EXPECT_EQ(grid->tree().isValueOn(ijk), values[i] != 0) << ijk;
                                nonZero += values[i] != 0;
                            }
                        }
                    }
                    EXPECT_EQ(grid->activeVoxelCount(), nonZero);
                    EXPECT_EQ(grid->voxelSize(), openvdb::Vec3d(0.5, 2.0, 0.25));
                    EXPECT_EQ(grid->indexToWorld(openvdb::Coord(1, 2, 4)),
                              openvdb::Vec3d(-2.5, 4.5, 13.0));
                }
            }
        }
    }
}

TEST_F(TestMetaImageReader, testLargeVolumeCrossesBlocks)
{
    // 600,000 MET_INT elements: several 1 MiB read blocks, each ending inside a row.
    const std::array<int, 3> dims{{1000, 300, 2}};
    std::vector<std::int64_t> values(std::size_t(dims[0]) * dims[1] * dims[2], 0);
    std::mt19937 random(7);
    for (std::size_t i = 0; i < values.size(); i += 1 + random() % 13) {
        values[i] = std::int64_t(random() % 2000) - 1000;
    }
    openvdb::Index64 nonZero = 0;
    for (const std::int64_t v : values) nonZero += v != 0;
    for (const bool compressed : {false, true}) {
        const auto grid = vdbi::readMetaImage(this->writeVolume(compressed ? "bigz" : "big",
            dims, values, MetaElementType::Int, /*msb=*/true, compressed, /*single=*/false));
        EXPECT_EQ(grid->activeVoxelCount(), nonZero);
        std::size_t mismatches = 0, i = 0;
        for (int z = 0; z < dims[2]; ++z) {
            for (int y = 0; y < dims[1]; ++y) {
                for (int x = 0; x < dims[0]; ++x, ++i) {
                    mismatches += grid->tree().getValue(openvdb::Coord(x, y, z)) != values[i];
                }
            }
        }
        EXPECT_EQ(mismatches, 0u);
    }
}

TEST_F(TestMetaImageReader, testHeaderParsing)
{
    // Keys in any case, CRLF line ends, synonyms, unknown keys, LOCAL data after the header.
    const std::string text = "objecttype = image\r\nNDIMS=3\r\nCenterOfRotation = 0 0 0\r\n"
        "dimsize = 4 5 6\r\nElementSize = 2 2 3\r\nPosition = 1 -2 +3.5\r\n"
        "ElementByteOrderMSB = true\r\nHeaderSize = -1\r\nAnatomicalOrientation = RAI\r\n"
        "ElementNumberOfChannels = 1\r\nelementtype = met_ushort\r\n"
        "ElementDataFile = local\r\n\x01\x02";
    std::istringstream in(text);
    const vdbi::MetaImageHeader header = vdbi::parseMetaImageHeader(in, "h.mha");
    EXPECT_EQ(header.dimSize, (std::array<std::int32_t, 3>{{4, 5, 6}}));
    EXPECT_EQ(header.elementType, MetaElementType::UShort);
    EXPECT_EQ(header.spacing, (std::array<double, 3>{{2.0, 2.0, 3.0}}));
    EXPECT_EQ(header.offset, (std::array<double, 3>{{1.0, -2.0, 3.5}}));
    EXPECT_TRUE(header.isMSB);
    EXPECT_FALSE(header.isCompressed);
    EXPECT_EQ(header.headerSize, -1);
    EXPECT_TRUE(header.isLocal());
    EXPECT_EQ(header.voxelCount(), 120u);
    EXPECT_EQ(header.dataBytes(), 240u);
    EXPECT_EQ(header.headerBytes, text.size() - 2);
    EXPECT_EQ(in.get(), 1); // the stream stops at the first data byte

    // ElementSpacing wins over ElementSize, whatever the order.
    std::istringstream both("ElementSpacing = 1 1 2\nElementSize = 5 5 5\nDimSize = 1 1 1\n"
        "ElementType = MET_CHAR\nElementDataFile = x.raw\n");
    EXPECT_EQ(vdbi::parseMetaImageHeader(both, "b.mhd").spacing,
              (std::array<double, 3>{{1.0, 1.0, 2.0}}));
}

TEST_F(TestMetaImageReader, testHeaderSizeAndTrailingBytes)
{
    const std::array<int, 3> dims{{3, 2, 2}};
    std::vector<std::int64_t> values(12);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = std::int64_t(i % 4);
    const Bytes data = encode(values, MetaElementType::Short, false);
    const std::string header = "NDims = 3\nDimSize = 3 2 2\nElementType = MET_SHORT\n";

    // HeaderSize: bytes to skip in the data file; the data file may be longer.
    // (Sized up front: GCC 12 warns falsely about insert() at the end of a vector.)
    Bytes skipped(16 + data.size() + 1, 0xee);
    std::copy(data.begin(), data.end(), skipped.begin() + 16);
    skipped.back() = 0x55;
    writeBytes(this->path("skip.raw"), skipped);
    writeText(this->path("skip.mhd"), header + "HeaderSize = 16\nElementDataFile = skip.raw\n");
    // HeaderSize = -1: the data are the last bytes of the file.
    Bytes tail(5 + data.size(), 0xee);
    std::copy(data.begin(), data.end(), tail.begin() + 5);
    writeBytes(this->path("tail.raw"), tail);
    writeText(this->path("tail.mhd"), header + "HeaderSize = -1\nElementDataFile = tail.raw\n");
    // A data file name with a space is a name, not a pattern.
    writeBytes(this->path("with space.raw"), data);
    writeText(this->path("space.mhd"), header + "ElementDataFile = with space.raw\n");
    for (const char* name : {"skip.mhd", "tail.mhd", "space.mhd"}) {
        SCOPED_TRACE(name);
        const auto grid = vdbi::readMetaImage(this->path(name));
        EXPECT_EQ(grid->activeVoxelCount(), 9u);
        EXPECT_EQ(grid->tree().getValue(openvdb::Coord(2, 1, 1)), 3);
        EXPECT_EQ(grid->tree().getValue(openvdb::Coord(1, 0, 0)), 1);
        EXPECT_TRUE(grid->transform().isIdentity());
    }
}

TEST_F(TestMetaImageReader, testMissingEmptyAndDirectory)
{
    const std::string missing = this->path("missing.mhd");
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(missing); }, missing,
        "no such file");
    const std::string empty = this->path("empty.mha");
    writeText(empty, "");
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(empty); }, empty, "empty");
    const std::string dir = this->path("folder.mhd");
    fs::create_directories(dir);
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(dir); }, dir, "directory");
    // The data file is missing, or a folder.
    const std::string noData = this->path("nodata.mhd");
    writeText(noData, "DimSize = 2 2 2\nElementType = MET_UCHAR\nElementDataFile = gone.raw\n");
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(noData); }, noData, "no such file");
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(noData); }, noData, "gone.raw");
}

TEST_F(TestMetaImageReader, testBadHeaders)
{
    struct Case { std::string name, from, to, word; };
    const std::vector<Case> ioErrors = {
        {"nodimsize.mhd", "DimSize = 500 470 136\n", "", "missing DimSize"},
        {"notype.mhd", "ElementType = MET_UCHAR\n", "", "missing ElementType"},
        {"ndims.mhd", "NDims = 3", "NDims = 2", "NDims"},
        {"fewdims.mhd", "DimSize = 500 470 136", "DimSize = 500 470", "expects 3 values"},
        {"baddim.mhd", "DimSize = 500 470 136", "DimSize = 500 4x0 136", "not a number"},
        {"zerodim.mhd", "DimSize = 500 470 136", "DimSize = 500 0 136", "not positive"},
        {"spacing.mhd", "ElementSpacing = 1 1 1.5", "ElementSpacing = 1 -1 1.5", "positive"},
        {"nanspacing.mhd", "ElementSpacing = 1 1 1.5", "ElementSpacing = 1 nan 1", "finite"},
        {"rotated.mhd", "TransformMatrix = 1 0 0 0 1 0 0 0 1",
            "TransformMatrix = 0 1 0 1 0 0 0 0 1", "identity"},
        {"channels.mhd", "ObjectType = Image", "ElementNumberOfChannels = 3", "Channels"},
        {"ascii.mhd", "BinaryData = True", "BinaryData = False", "ASCII"},
        {"object.mhd", "ObjectType = Image", "ObjectType = Mesh", "ObjectType"},
        {"msb.mhd", "BinaryDataByteOrderMSB = False", "BinaryDataByteOrderMSB = Maybe",
            "True or False"},
        {"list.mhd", "ElementDataFile = ", "ElementDataFile = LIST\n#", "not supported"},
        {"pattern.mhd", "ElementDataFile = ", "ElementDataFile = slice%03d.raw 1 136 1\n#",
            "not supported"},
        {"noequals.mhd", "Offset = 0 0 0", "Offset 0 0 0", "Key = Value"},
        {"nodatafile.mhd", "ElementDataFile = ", "Comment = ", "no ElementDataFile"},
    };
    for (const Case& c : ioErrors) {
        SCOPED_TRACE(c.name);
        writeText(this->path(c.name), this->frogHeader(c.from, c.to));
        expectError<openvdb::IoError>([&] { vdbi::readMetaImage(this->path(c.name)); },
            this->path(c.name), c.word);
    }
    const std::string flt = this->path("float.mhd");
    writeText(flt, this->frogHeader("MET_UCHAR", "MET_FLOAT"));
    expectError<openvdb::TypeError>([&] { vdbi::readMetaImage(flt); }, flt, "MET_FLOAT");

    const std::vector<Case> valueErrors = {
        {"overflow.mhd", "DimSize = 500 470 136", "DimSize = 2000000000 2000000000 2000000000",
            "overflow"},
        {"int32.mhd", "DimSize = 500 470 136", "DimSize = 500 3000000000 136", "int32"},
        {"huge.mhd", "DimSize = 500 470 136", "DimSize = 1 1 99999999999999999999",
            "out of range"},
    };
    for (const Case& c : valueErrors) {
        SCOPED_TRACE(c.name);
        writeText(this->path(c.name), this->frogHeader(c.from, c.to));
        expectError<openvdb::ValueError>([&] { vdbi::readMetaImage(this->path(c.name)); },
            this->path(c.name), c.word);
    }

    // Not a header at all: a binary file, a file of one endless line.
    const std::string binary = this->path("knight.mha");
    writeBytes(binary, readBytes(vdbi_test::dataPath("chr_knight.vox")));
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(binary); }, binary, "binary");
    const std::string line = this->path("line.mha");
    writeText(line, std::string(100000, 'a'));
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(line); }, line, "longer than");
}

TEST_F(TestMetaImageReader, testShortData)
{
    // Raw file shorter than DimSize says: found before anything is allocated.
    const std::string raw = this->path("short.mhd");
    writeText(raw, "NDims = 3\nDimSize = 100 100 100\nElementType = MET_USHORT\n"
        "ElementDataFile = short.raw\n");
    writeBytes(this->path("short.raw"), Bytes(1999999, 1));
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(raw); }, raw, "truncated");
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(raw); }, raw, "2000000");
    // Also for absurd sizes that fit in 64 bits.
    const std::string absurd = this->path("absurd.mha");
    writeText(absurd, "DimSize = 2000000000 2000000000 1\nElementType = MET_INT\n"
        "ElementDataFile = LOCAL\n\x01\x02\x03\x04");
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(absurd); }, absurd, "truncated");

    // Truncated .zraw: the stream ends early.
    const Bytes zraw = readBytes(vdbi_test::dataPath("frogtissue.zraw"));
    ASSERT_EQ(zraw.size(), 262087u);
    writeBytes(this->path("half.zraw"), Bytes(zraw.begin(), zraw.begin() + zraw.size() / 2));
    const std::string half = this->path("half.mhd");
    writeText(half, this->frogHeader(vdbi_test::dataPath("frogtissue.zraw"), "half.zraw"));
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(half); }, half, "truncated");
    // DimSize beyond what the compressed bytes can hold (deflate expands at most 1032 times):
    // refused up front, the sizes named.
    const std::string bomb = this->path("bomb.mhd");
    writeText(bomb, this->frogHeader("DimSize = 500 470 136", "DimSize = 100000 100000 100000"));
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(bomb); }, bomb,
        "needs 1000000000000000 bytes, more than the 262087 bytes");
    // A complete stream of too few elements.
    const std::string few = this->path("few.mhd");
    writeText(few, this->frogHeader("DimSize = 500 470 136", "DimSize = 500 470 137"));
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(few); }, few,
        "compressed stream ends early");
    // Damaged compressed bytes.
    Bytes damaged = zraw;
    for (std::size_t i = 100000; i < 100100; ++i) damaged[i] ^= 0x5a;
    writeBytes(this->path("damaged.zraw"), damaged);
    const std::string bad = this->path("damaged.mhd");
    writeText(bad, this->frogHeader(vdbi_test::dataPath("frogtissue.zraw"), "damaged.zraw"));
    expectError<openvdb::IoError>([&] { vdbi::readMetaImage(bad); }, bad, "compressed data");

    // Trailing garbage after a complete stream is fine.
    Bytes longer = zraw;
    longer.insert(longer.end(), 1000, 0xab);
    writeBytes(this->path("longer.zraw"), longer);
    const std::string trailing = this->path("trailing.mhd");
    writeText(trailing, this->frogHeader(vdbi_test::dataPath("frogtissue.zraw"),
        "longer.zraw"));
    EXPECT_EQ(vdbi::readMetaImage(trailing)->activeVoxelCount(), 1156957u);
}

TEST_F(TestMetaImageReader, testUIntBeyondInt32)
{
    const std::vector<std::int64_t> values{0, 5, 0x80000000LL, 0};
    const std::string path = this->writeVolume("uint", {{2, 2, 1}}, values,
        MetaElementType::UInt, false, false, true);
    expectError<openvdb::ValueError>([&] { vdbi::readMetaImage(path); }, path, "2147483648");
}

TEST_F(TestMetaImageReader, testEveryTruncationFailsCleanly)
{
    std::vector<std::int64_t> values(4 * 3 * 2);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = std::int64_t(i);
    for (const bool compressed : {false, true}) {
        const std::string good = this->writeVolume(compressed ? "tz" : "t", {{4, 3, 2}},
            values, MetaElementType::Short, false, compressed, true);
        const Bytes bytes = readBytes(good);
        EXPECT_EQ(vdbi::readMetaImage(good)->activeVoxelCount(), 23u);
        for (std::size_t size = 0; size < bytes.size(); ++size) {
            const std::string path = this->path("cut.mha");
            writeBytes(path, Bytes(bytes.begin(), bytes.begin() + size));
            // A cut inside "ElementType = MET_SHORT" gives a TypeError ("MET_SH"); the
            // compressed stream's Adler-32 trailer is checked too.
            EXPECT_THROW(vdbi::readMetaImage(path), openvdb::Exception) << size;
        }
    }
}
