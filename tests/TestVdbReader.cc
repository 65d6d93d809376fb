// SPDX-License-Identifier: Apache-2.0

#include <vdbi/VdbReader.h>

#include "support/TestData.h"
#include "support/TestFiles.h"

#include <openvdb/Exceptions.h>
#include <openvdb/io/File.h>
#include <openvdb/points/PointDataGrid.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using vdbi_test::Bytes;
using vdbi_test::expectError;
using vdbi_test::readBytes;
using vdbi_test::writeBytes;

void
writeGrids(const std::string& path, const openvdb::GridPtrVec& grids)
{
    openvdb::io::File file(path);
    file.write(grids);
    file.close();
}

/// Labels with voxels, an active tile, an inactive non-background voxel and background 7.
template<typename GridT>
typename GridT::Ptr
makeLabels(const std::string& name, typename GridT::ValueType scale)
{
    using ValueT = typename GridT::ValueType;
    auto grid = GridT::create(ValueT(7 * scale));
    grid->setName(name);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
    auto& tree = grid->tree();
    tree.setValue(openvdb::Coord(1, 2, 3), ValueT(1 * scale));
    tree.setValue(openvdb::Coord(-4, 0, 9), ValueT(-2 * scale));
    tree.setValueOff(openvdb::Coord(30, 30, 30), ValueT(5 * scale));
    tree.addTile(/*level=*/2, openvdb::Coord(128, 0, 0), ValueT(3 * scale), /*active=*/true);
    return grid;
}

/// The Int32 values and states @a grid should have after conversion from makeLabels().
void
expectLabels(const openvdb::Int32Grid& grid, const std::string& name)
{
    EXPECT_EQ(grid.getName(), name);
    EXPECT_EQ(grid.background(), 7);
    EXPECT_EQ(grid.voxelSize(), openvdb::Vec3d(0.5));
    const auto& tree = grid.tree();
    EXPECT_EQ(tree.getValue(openvdb::Coord(1, 2, 3)), 1);
    EXPECT_EQ(tree.getValue(openvdb::Coord(-4, 0, 9)), -2);
    EXPECT_EQ(tree.getValue(openvdb::Coord(30, 30, 30)), 5);
    EXPECT_FALSE(tree.isValueOn(openvdb::Coord(30, 30, 30)));
    EXPECT_EQ(tree.getValue(openvdb::Coord(135, 7, 127)), 3);
    EXPECT_EQ(tree.getValue(openvdb::Coord(0, 0, 0)), 7);
    EXPECT_EQ(tree.activeTileCount(), 1u); // the tile stays a tile
    EXPECT_EQ(tree.activeVoxelCount(), 2u + 128u * 128u * 128u);
}

} // namespace

class TestVdbReader : public ::testing::Test
{
protected:
    void SetUp() override
    {
        openvdb::initialize();
    }

    std::string path(const std::string& name) const { return mFolder.file(name); }

    vdbi_test::TempFolder mFolder;
};

TEST_F(TestVdbReader, testInt32RoundTrip)
{
    const std::string path = this->path("labels.vdb");
    auto density = openvdb::FloatGrid::create(0.25f);
    density->setName("density");
    auto labels = makeLabels<openvdb::Int32Grid>("labels", 1);
    labels->insertMeta("author", openvdb::StringMetadata("test"));
    writeGrids(path, {density, labels});

    // The first Int32 grid, though a float grid comes first; its metadata kept.
    const auto grid = vdbi::readVdb(path);
    ASSERT_TRUE(grid);
    expectLabels(*grid, "labels");
    EXPECT_EQ(grid->metaValue<std::string>("author"), "test");
    EXPECT_TRUE(grid->tree().hasSameTopology(labels->tree()));
    expectLabels(*vdbi::readVdb(path, "labels"), "labels");
}

TEST_F(TestVdbReader, testExactConversions)
{
    const std::string path = this->path("all.vdb");
    auto bools = openvdb::BoolGrid::create(false);
    bools->setName("mask");
    bools->tree().setValue(openvdb::Coord(1, 1, 1), true);
    bools->tree().addTile(2, openvdb::Coord(0, 128, 0), true, true);
    writeGrids(path, {makeLabels<openvdb::Int64Grid>("wide", 1),
        makeLabels<openvdb::FloatGrid>("single", 1.f),
        makeLabels<openvdb::DoubleGrid>("double", 1.0), bools});

    // Without a name and without an Int32 grid: the first convertible grid.
    expectLabels(*vdbi::readVdb(path), "wide");
    expectLabels(*vdbi::readVdb(path, "wide"), "wide");
    expectLabels(*vdbi::readVdb(path, "single"), "single");
    expectLabels(*vdbi::readVdb(path, "double"), "double");
    const auto mask = vdbi::readVdb(path, "mask");
    EXPECT_EQ(mask->background(), 0);
    EXPECT_EQ(mask->tree().getValue(openvdb::Coord(1, 1, 1)), 1);
    EXPECT_EQ(mask->tree().getValue(openvdb::Coord(5, 130, 5)), 1);
    EXPECT_EQ(mask->tree().getValue(openvdb::Coord(2, 1, 1)), 0);
    EXPECT_EQ(mask->tree().activeTileCount(), 1u);
    EXPECT_EQ(mask->activeVoxelCount(), 1u + 128u * 128u * 128u);

    // The extreme int32 values survive float -> int (double holds them exactly).
    auto extremes = openvdb::DoubleGrid::create(0.0);
    extremes->tree().setValue(openvdb::Coord(0), 2147483647.0);
    extremes->tree().setValue(openvdb::Coord(1), -2147483648.0);
    writeGrids(this->path("extremes.vdb"), {extremes});
    const auto exact = vdbi::readVdb(this->path("extremes.vdb"));
    EXPECT_EQ(exact->tree().getValue(openvdb::Coord(0)), 2147483647);
    EXPECT_EQ(exact->tree().getValue(openvdb::Coord(1)), -2147483648);
}

TEST_F(TestVdbReader, testLossyGridsRejected)
{
    struct Case { std::string name; openvdb::GridBase::Ptr grid; std::string value; };
    auto fraction = makeLabels<openvdb::FloatGrid>("fraction", 1.f);
    fraction->tree().setValue(openvdb::Coord(2, 2, 2), 2.5f);
    auto inactive = makeLabels<openvdb::DoubleGrid>("inactive", 1.0);
    inactive->tree().setValueOff(openvdb::Coord(40, 0, 0), 0.125);
    auto background = openvdb::FloatGrid::create(0.5f);
    background->setName("background");
    auto wide = makeLabels<openvdb::Int64Grid>("wide", 1);
    wide->tree().setValue(openvdb::Coord(9, 9, 9), std::int64_t(1) << 40);
    auto nan = openvdb::FloatGrid::create(0.f);
    nan->setName("nan");
    nan->tree().setValue(openvdb::Coord(0), std::numeric_limits<float>::quiet_NaN());
    auto big = openvdb::DoubleGrid::create(0.0);
    big->setName("big");
    big->tree().setValue(openvdb::Coord(0), 2147483648.0);
    const std::vector<Case> cases = {{"fraction", fraction, "2.5"},
        {"inactive", inactive, "0.125"}, {"background", background, "0.5"},
        {"wide", wide, "1099511627776"}, {"nan", nan, "nan"}, {"big", big, "2.14748e+09"}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::string path = this->path(c.name + ".vdb");
        writeGrids(path, {c.grid});
        expectError<openvdb::TypeError>([&] { vdbi::readVdb(path); }, path,
            {"'" + c.name + "'", c.value, "not an exact int32"});
    }
}

TEST_F(TestVdbReader, testOtherTypesRejected)
{
    auto velocity = openvdb::Vec3fGrid::create();
    velocity->setName("velocity");
    velocity->tree().setValue(openvdb::Coord(0), openvdb::Vec3f(1.f));
    auto mask = openvdb::MaskGrid::create();
    mask->setName("region");
    auto points = openvdb::points::PointDataGrid::create();
    points->setName("points");
    const std::string path = this->path("others.vdb");
    writeGrids(path, {velocity, mask, points});
    expectError<openvdb::TypeError>([&] { vdbi::readVdb(path); }, path,
        {"no grid of an integer-valued type", "'velocity' (vec3s)", "'region' (mask)",
         "'points' (ptdataidx32)"});
    expectError<openvdb::TypeError>([&] { vdbi::readVdb(path, "velocity"); }, path,
        {"'velocity'", "vec3s"});
    // A wrong name lists what there is.
    expectError<openvdb::ValueError>([&] { vdbi::readVdb(path, "labels"); }, path,
        {"no grid named 'labels'", "'velocity' (vec3s)", "'region' (mask)"});

    // Only a vec3 and a float grid of non-integer values.
    auto density = openvdb::FloatGrid::create(0.f);
    density->setName("density");
    density->tree().setValue(openvdb::Coord(3), 0.75f);
    const std::string floats = this->path("floats.vdb");
    writeGrids(floats, {velocity, density});
    expectError<openvdb::TypeError>([&] { vdbi::readVdb(floats); }, floats,
        {"'density'", "0.75"});

    const std::string none = this->path("none.vdb");
    writeGrids(none, {});
    expectError<openvdb::TypeError>([&] { vdbi::readVdb(none); }, none, {"no grids"});
}

TEST_F(TestVdbReader, testTilesBeyondMemoryRefused)
{
    // The stages turn tiles into voxels: 8 root tiles of 4096^3 (2 TiB as int32 voxels) are
    // refused with their voxel count; an internal node's tile of 128^3 is read as a tile.
    auto huge = openvdb::Int32Grid::create(0);
    huge->setName("huge");
    huge->tree().sparseFill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(8191)), 3);
    const std::string path = this->path("huge.vdb");
    writeGrids(path, {huge});
    expectError<openvdb::ValueError>([&] { vdbi::readVdb(path); }, path,
        {"'huge'", "549755813888 voxels", "GiB"});

    auto tile = openvdb::Int32Grid::create(0);
    tile->tree().addTile(/*level=*/2, openvdb::Coord(0), 3, /*active=*/true);
    writeGrids(path, {tile});
    const auto grid = vdbi::readVdb(path);
    EXPECT_EQ(grid->activeVoxelCount(), 128u * 128u * 128u);
    EXPECT_EQ(grid->tree().leafCount(), 0u);
}

TEST_F(TestVdbReader, testBadFiles)
{
    const std::string missing = this->path("missing.vdb");
    expectError<openvdb::IoError>([&] { vdbi::readVdb(missing); }, missing, {"no such file"});
    const std::string empty = this->path("empty.vdb");
    writeBytes(empty, Bytes());
    expectError<openvdb::IoError>([&] { vdbi::readVdb(empty); }, empty, {"empty"});
    const std::string dir = this->path("folder.vdb");
    fs::create_directories(dir);
    expectError<openvdb::IoError>([&] { vdbi::readVdb(dir); }, dir, {"directory"});
    const std::string notVdb = this->path("knight.vdb");
    writeBytes(notVdb, readBytes(vdbi_test::dataPath("chr_knight.vox")));
    expectError<openvdb::IoError>([&] { vdbi::readVdb(notVdb); }, notVdb, {"cannot read"});

    // Truncated: anywhere in the header, the descriptors or the data.
    const std::string good = this->path("good.vdb");
    auto labels = makeLabels<openvdb::Int32Grid>("labels", 1);
    for (int i = 0; i < 2000; ++i) labels->tree().setValue(openvdb::Coord(i, i % 7, -i), i);
    writeGrids(good, {labels});
    const Bytes bytes = readBytes(good);
    ASSERT_GT(bytes.size(), 1000u);
    std::vector<std::size_t> sizes{3, 40, 200, bytes.size() - 100, bytes.size() - 1};
    for (std::size_t size = 1; size < bytes.size(); size += 997) sizes.push_back(size);
    for (const std::size_t size : sizes) {
        SCOPED_TRACE(size);
        const std::string cut = this->path("cut.vdb");
        writeBytes(cut, Bytes(bytes.begin(), bytes.begin() + size));
        expectError<openvdb::IoError>([&] { vdbi::readVdb(cut); }, cut, {"cannot read"});
    }
}
