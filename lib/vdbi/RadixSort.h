// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/RadixSort.h
/// @brief A stable radix sort for keys packed from several unsigned fields (grid cells,
/// edges between two points): what the stages sort most, millions of entries at a time.

#ifndef VDBI_RADIX_SORT_HAS_BEEN_INCLUDED
#define VDBI_RADIX_SORT_HAS_BEEN_INCLUDED

#include <vdbi/ParallelRanges.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace vdbi {

/// @brief Sorts @a entries by @a keyOf(entry), a key of FIELDS fields of FIELD_BITS bits each
/// (the first field highest), keeping entries with equal keys in the order they had.
/// @details A least-significant-digit radix sort over the low bits of each field, above which
/// all keys agree: a cell key of a sample volume varies in about 8 of the 21 bits per axis,
/// so 2 passes of 12-bit digits sort it instead of n log n comparisons (frog at 2 voxels:
/// 11 candidate grids of about 2.5 M entries). Entries made in ascending order of an index
/// end up in the order of (key, index) that std::sort of pairs gives. @a Vector's resize()
/// makes the buffer (left uninitialized by a DefaultInitAllocator). With @a threaded, runs
/// of the entries are counted and moved in parallel; the order is the same.
template<int FIELDS, int FIELD_BITS, typename Vector, typename KeyOf>
void
sortByPackedKey(Vector& entries, const KeyOf& keyOf, bool threaded = false)
{
    static_assert(FIELD_BITS < 64 && FIELDS * FIELD_BITS <= 64, "the key has 64 bits");
    const std::size_t n = entries.size();
    if (n < 2) return;
    constexpr std::uint64_t FIELD_MASK = (std::uint64_t(1) << FIELD_BITS) - 1;
    // Fixed runs of entries, each counted and moved by one task: every entry goes where the
    // serial sort puts it, on any number of threads.
    const std::size_t runs = threaded && n >= (std::size_t(1) << 16) ? 16 : 1;
    const std::size_t runLength = (n + runs - 1) / runs;
    auto forEachRun = [&](const std::function<void(std::size_t run, std::size_t begin,
                                                   std::size_t end)>& body) {
        forEachRange(runs, 1, threaded, [&](std::size_t first, std::size_t last) {
            for (std::size_t r = first; r < last; ++r) {
                body(r, std::min(n, r * runLength), std::min(n, (r + 1) * runLength));
            }
        });
    };
    const std::uint64_t firstKey = keyOf(entries[0]);
    std::vector<std::uint64_t> runDiffer(runs, 0);
    forEachRun([&](std::size_t r, std::size_t begin, std::size_t end) {
        std::uint64_t differ = 0;
        for (std::size_t i = begin; i < end; ++i) differ |= keyOf(entries[i]) ^ firstKey;
        runDiffer[r] = differ;
    });
    std::uint64_t differ = 0;
    for (const std::uint64_t d : runDiffer) differ |= d;
    // Per field (the first highest): how many of its low bits differ anywhere, and their
    // offset in the compact key.
    int width[FIELDS], offset[FIELDS], total = 0;
    for (int f = FIELDS - 1; f >= 0; --f) {
        std::uint64_t bits = (differ >> ((FIELDS - 1 - f) * FIELD_BITS)) & FIELD_MASK;
        width[f] = 0;
        for (; bits != 0; bits >>= 1) ++width[f];
        offset[f] = total;
        total += width[f];
    }
    if (total == 0) return; // one key
    auto compact = [&](std::uint64_t key) {
        std::uint64_t c = 0;
        for (int f = 0; f < FIELDS; ++f) {
            const std::uint64_t field = (key >> ((FIELDS - 1 - f) * FIELD_BITS)) & FIELD_MASK;
            c |= (field & ((std::uint64_t(1) << width[f]) - 1)) << offset[f];
        }
        return c;
    };
    // Digits of at most 12 bits: 4096 buckets, whose write positions stay in the L1 cache.
    const int passes = (total + 11) / 12, digitBits = (total + passes - 1) / passes;
    const std::size_t buckets = std::size_t(1) << digitBits;
    // Per run, where its entries of each bucket go: counted before each pass, as a pass
    // moves entries from run to run.
    std::vector<std::size_t> start(runs * buckets);
    Vector buffer;
    buffer.resize(n);
    for (int pass = 0; pass < passes; ++pass) {
        const int shift = pass * digitBits;
        std::fill(start.begin(), start.end(), 0);
        forEachRun([&](std::size_t r, std::size_t begin, std::size_t end) {
            std::size_t* count = start.data() + r * buckets;
            for (std::size_t i = begin; i < end; ++i) {
                ++count[(compact(keyOf(entries[i])) >> shift) & (buckets - 1)];
            }
        });
        // A bucket's entries of one run follow those of the runs before it.
        std::size_t sum = 0;
        for (std::size_t b = 0; b < buckets; ++b) {
            for (std::size_t r = 0; r < runs; ++r) sum += std::exchange(start[r * buckets + b], sum);
        }
        forEachRun([&](std::size_t r, std::size_t begin, std::size_t end) {
            std::size_t* next = start.data() + r * buckets;
            for (std::size_t i = begin; i < end; ++i) {
                const auto& e = entries[i];
                buffer[next[(compact(keyOf(e)) >> shift) & (buckets - 1)]++] = e;
            }
        });
        entries.swap(buffer);
    }
}

} // namespace vdbi

#endif // VDBI_RADIX_SORT_HAS_BEEN_INCLUDED
