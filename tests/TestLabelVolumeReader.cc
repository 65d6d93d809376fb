// SPDX-License-Identifier: Apache-2.0

#include <vdbi/LabelVolumeReader.h>

#include "support/TestData.h"
#include "support/TestFiles.h"

#include <openvdb/Exceptions.h>
#include <openvdb/io/File.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>

namespace fs = std::filesystem;

using vdbi_test::expectError;

class TestLabelVolumeReader : public ::testing::Test
{
protected:
    std::string path(const std::string& name) const { return mFolder.file(name); }

    vdbi_test::TempFolder mFolder;
};

TEST_F(TestLabelVolumeReader, testDispatchByExtension)
{
    EXPECT_EQ(vdbi::readLabelVolume(vdbi_test::dataPath("chr_knight.vox"))->activeVoxelCount(),
              398u);
    const auto frog = vdbi::readLabelVolume(vdbi_test::dataPath("frogtissue.mhd"));
    EXPECT_EQ(frog->activeVoxelCount(), 1156957u);
    EXPECT_EQ(frog->voxelSize(), openvdb::Vec3d(1.0, 1.0, 1.5));

    // Extensions in any case.
    fs::copy_file(vdbi_test::dataPath("chr_knight.vox"), this->path("KNIGHT.VOX"));
    EXPECT_EQ(vdbi::readLabelVolume(this->path("KNIGHT.VOX"))->activeVoxelCount(), 398u);

    {
        std::ofstream out(this->path("cube.MHA"), std::ios::binary);
        out << "NDims = 3\nDimSize = 2 2 2\nElementType = MET_CHAR\nElementSpacing = 2 2 2\n"
               "Offset = 10 20 30\nElementDataFile = LOCAL\n";
        const char data[8] = {0, 1, 0, 0, 0, 0, 0, -9};
        out.write(data, 8);
    }
    const auto cube = vdbi::readLabelVolume(this->path("cube.MHA"));
    EXPECT_EQ(cube->activeVoxelCount(), 2u);
    EXPECT_EQ(cube->tree().getValue(openvdb::Coord(1, 0, 0)), 1);
    EXPECT_EQ(cube->tree().getValue(openvdb::Coord(1, 1, 1)), -9);
    EXPECT_EQ(cube->indexToWorld(openvdb::Coord(1, 1, 1)), openvdb::Vec3d(12, 22, 32));

    openvdb::initialize();
    auto first = openvdb::Int32Grid::create(0);
    first->setName("first");
    first->tree().setValue(openvdb::Coord(1), 4);
    auto second = openvdb::Int32Grid::create(0);
    second->setName("second");
    second->tree().setValue(openvdb::Coord(2), 5);
    second->tree().setValue(openvdb::Coord(3), 6);
    openvdb::io::File(this->path("two.Vdb")).write({first, second});
    EXPECT_EQ(vdbi::readLabelVolume(this->path("two.Vdb"))->getName(), "first");
    vdbi::ReadOptions options;
    options.gridName = "second";
    const auto named = vdbi::readLabelVolume(this->path("two.Vdb"), options);
    EXPECT_EQ(named->getName(), "second");
    EXPECT_EQ(named->activeVoxelCount(), 2u);
}

TEST_F(TestLabelVolumeReader, testBadPaths)
{
    const std::string unknown = this->path("labels.nrrd");
    std::ofstream(unknown) << "NRRD0004\n";
    expectError<openvdb::ValueError>([&] { vdbi::readLabelVolume(unknown); }, unknown,
        "unknown extension '.nrrd'");
    const std::string none = this->path("labels");
    expectError<openvdb::ValueError>([&] { vdbi::readLabelVolume(none); }, none,
        "unknown extension (none)");

    for (const char* name : {"missing.vdb", "missing.vox", "missing.mhd", "missing.mha"}) {
        const std::string missing = this->path(name);
        expectError<openvdb::IoError>([&] { vdbi::readLabelVolume(missing); }, missing,
            "no such file");
    }

    const std::string empty = this->path("empty.vox");
    std::ofstream(empty).close();
    expectError<openvdb::IoError>([&] { vdbi::readLabelVolume(empty); }, empty, "empty");

    vdbi::ReadOptions options;
    options.gridName = "labels";
    const std::string knight = vdbi_test::dataPath("chr_knight.vox");
    expectError<openvdb::ValueError>([&] { vdbi::readLabelVolume(knight, options); }, knight,
        ".vdb files only");
}
