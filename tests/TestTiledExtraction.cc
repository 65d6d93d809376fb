// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Interfaces.h>
#include <vdbi/LabelVolumeReader.h>

#include "support/RawExtraction.h"
#include "support/TestData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <vector>

using openvdb::Coord;
using openvdb::CoordBBox;

class TestTiledExtraction : public ::testing::Test {};

namespace {

/// A triangle as its label pair and corner keys, rotated so the smallest key comes first
/// (orientation kept): equal records are the same oriented triangle of the same patch.
using TriangleRecord = std::array<std::int64_t, 11>;

void
appendRecords(const vdbi::InterfaceMesh& m, std::vector<TriangleRecord>& out)
{
    for (const auto& p : m.patches) {
        for (std::size_t t = p.firstTriangle; t < p.firstTriangle + p.triangleCount; ++t) {
            std::array<vdbi::VertexKey, 3> k = {m.pointKeys[m.triangles[t][0]],
                m.pointKeys[m.triangles[t][1]], m.pointKeys[m.triangles[t][2]]};
            const int first = int(std::min_element(k.begin(), k.end()) - k.begin());
            std::rotate(k.begin(), k.begin() + first, k.end());
            TriangleRecord r{p.a, p.b};
            for (int i = 0; i < 3; ++i) for (int a = 0; a < 3; ++a) r[2 + 3 * i + a] = k[i][a];
            out.push_back(r);
        }
    }
}

std::vector<TriangleRecord>
tiledRecords(const openvdb::Int32Grid& grid, const std::vector<CoordBBox>& tiles)
{
    std::vector<TriangleRecord> records;
    for (const CoordBBox& tile : tiles) {
        vdbi::Options options;
        options.region = tile;
        appendRecords(vdbi_test::extractRaw(grid, options).mesh, records);
    }
    std::sort(records.begin(), records.end());
    return records;
}

std::vector<CoordBBox>
splitInto(const CoordBBox& box, const Coord& cut)
{
    std::vector<CoordBBox> tiles;
    for (int n = 0; n < 8; ++n) {
        Coord lo = box.min(), hi = box.max();
        for (int a = 0; a < 3; ++a) {
            if (n & (1 << a)) lo[a] = cut[a];
            else hi[a] = cut[a] - 1;
        }
        tiles.emplace_back(lo, hi);
    }
    return tiles;
}

} // namespace

// Boxes that tile the grid, each read with a halo, give exactly the whole grid's triangles
// (same patches, same oriented triangles on the same integer keys): the raw patches of
// neighbouring boxes stitch by their keys. Checked on frog with cuts through its middle,
// and on a random volume with many critical elements right at the cuts.
TEST_F(TestTiledExtraction, testTilesStitchIntoTheWhole)
{
    const auto frog = vdbi::readLabelVolume(vdbi_test::dataPath("frogtissue.mhd"));
    CoordBBox box = frog->evalActiveVoxelBoundingBox();
    box.expand(1);
    std::vector<TriangleRecord> whole;
    appendRecords(vdbi_test::extractRaw(*frog).mesh, whole);
    std::sort(whole.begin(), whole.end());
    const auto tiled = tiledRecords(*frog, splitInto(box, Coord(250, 235, 68)));
    EXPECT_EQ(tiled.size(), whole.size());
    EXPECT_TRUE(tiled == whole);

    auto noise = openvdb::Int32Grid::create(0);
    unsigned state = 5;
    for (int x = 0; x < 24; ++x) for (int y = 0; y < 24; ++y) for (int z = 0; z < 24; ++z) {
        state = state * 1664525u + 1013904223u;
        noise->tree().setValue(Coord(x, y, z), int((state >> 16) % 4u));
    }
    std::vector<TriangleRecord> wholeNoise;
    appendRecords(vdbi_test::extractRaw(*noise).mesh, wholeNoise);
    std::sort(wholeNoise.begin(), wholeNoise.end());
    for (const Coord& cut : {Coord(12, 12, 12), Coord(7, 16, 9), Coord(8, 8, 8)}) {
        const auto t = tiledRecords(*noise, splitInto(CoordBBox(Coord(-1), Coord(24)), cut));
        EXPECT_TRUE(t == wholeNoise) << "cut " << cut;
    }
}
