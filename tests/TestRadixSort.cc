// SPDX-License-Identifier: Apache-2.0
// sortByPackedKey(): the order std::sort gives to (key, index) pairs made by ascending index,
// for cell keys (3 fields of 21 bits, negative coordinates wrapping) and edge keys (2 of 32).

#include <vdbi/CandidateGrid.h>
#include <vdbi/RadixSort.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

class TestRadixSort : public ::testing::Test {};

namespace {

using Entries = std::vector<std::pair<std::uint64_t, std::uint32_t>>;

/// @a count entries (cellKey of a random cell in [-spread, spread)^3 around @a centre, index).
Entries
randomCells(std::size_t count, int spread, const openvdb::Vec3i& centre, std::uint32_t seed)
{
    std::mt19937 random(seed);
    std::uniform_int_distribution<int> offset(-spread, spread - 1);
    Entries entries;
    for (std::uint32_t i = 0; i < count; ++i) {
        const openvdb::Vec3i c = centre + openvdb::Vec3i(offset(random), offset(random),
                                                         offset(random));
        entries.emplace_back(vdbi::cellKey(c), i);
    }
    return entries;
}

/// Whether the radix sort of @a entries, in one thread and in parallel, gives what std::sort
/// does.
void
expectSortedLikeStd(const Entries& entries)
{
    Entries expected = entries;
    std::sort(expected.begin(), expected.end());
    for (const bool threaded : {false, true}) {
        Entries sorted = entries;
        vdbi::sortByPackedKey<3, vdbi::CELL_KEY_BITS>(
            sorted, [](const auto& e) { return e.first; }, threaded);
        EXPECT_EQ(sorted, expected) << (threaded ? "threaded" : "serial");
    }
}

} // namespace

TEST_F(TestRadixSort, cellKeysSortLikeStdSort)
{
    // Few cells (many equal keys: the order of equal keys is tested), a sample volume's
    // spread, cells across 0 on every axis (keys wrap to the top of their 21 bits), and the
    // whole key range (6 passes). Over 2^16 entries, the threaded sort works in runs, which
    // each pass fills anew.
    for (std::uint32_t seed = 1; seed <= 4; ++seed) {
        expectSortedLikeStd(randomCells(10000, 2, openvdb::Vec3i(100, 50, 7), seed));
        expectSortedLikeStd(randomCells(200000, 128, openvdb::Vec3i(300, 300, 300), seed));
        expectSortedLikeStd(randomCells(200000, 64, openvdb::Vec3i(0, 0, 0), seed));
        expectSortedLikeStd(randomCells(200000, 1 << 20, openvdb::Vec3i(0, 0, 0), seed));
    }
}

TEST_F(TestRadixSort, fewEntriesOrOneKeyStayAsTheyAre)
{
    Entries none;
    vdbi::sortByPackedKey<3, 21>(none, [](const auto& e) { return e.first; });
    EXPECT_TRUE(none.empty());
    const Entries one{{42, 7}};
    Entries sorted = one;
    vdbi::sortByPackedKey<3, 21>(sorted, [](const auto& e) { return e.first; });
    EXPECT_EQ(sorted, one);
    // One key for all: the order of the indices stays, whatever it was.
    const Entries same{{5, 3}, {5, 1}, {5, 2}};
    sorted = same;
    vdbi::sortByPackedKey<3, 21>(sorted, [](const auto& e) { return e.first; });
    EXPECT_EQ(sorted, same);
}

TEST_F(TestRadixSort, equalKeysKeepTheirOrder)
{
    // Indices descending: a sort by (key, index) would turn equal keys around, a stable one
    // does not.
    Entries entries{{9, 5}, {3, 4}, {9, 3}, {3, 2}, {1, 1}, {9, 0}};
    vdbi::sortByPackedKey<3, 21>(entries, [](const auto& e) { return e.first; });
    const Entries expected{{1, 1}, {3, 4}, {3, 2}, {9, 5}, {9, 3}, {9, 0}};
    EXPECT_EQ(entries, expected);
}

TEST_F(TestRadixSort, edgeKeysSortLikeStdSort)
{
    // Keys of edges between points (two 32-bit fields): point indices up to 3 M, as in the
    // frog's raw extraction, then over the whole 32 bits.
    for (const std::uint32_t largest : {3000000u, 0xFFFFFFFFu}) {
        std::mt19937 random(largest);
        std::uniform_int_distribution<std::uint32_t> point(0, largest);
        std::vector<std::uint64_t> keys;
        for (int i = 0; i < 200000; ++i) {
            const std::uint32_t u = point(random), v = point(random);
            keys.push_back(std::uint64_t(std::min(u, v)) << 32 | std::max(u, v));
        }
        std::vector<std::uint64_t> expected = keys;
        std::sort(expected.begin(), expected.end());
        for (const bool threaded : {false, true}) {
            std::vector<std::uint64_t> sorted = keys;
            vdbi::sortByPackedKey<2, 32>(sorted, [](std::uint64_t k) { return k; }, threaded);
            EXPECT_EQ(sorted, expected) << (threaded ? "threaded" : "serial");
        }
    }
}
