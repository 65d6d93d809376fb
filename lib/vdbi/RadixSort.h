// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/RadixSort.h
/// @brief A stable radix sort for keys packed from several unsigned fields (grid cells,
/// edges between two points): what the stages sort most, millions of entries at a time.

#ifndef VDBI_RADIX_SORT_HAS_BEEN_INCLUDED
#define VDBI_RADIX_SORT_HAS_BEEN_INCLUDED

#include <cstddef>
#include <cstdint>
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
/// makes the buffer (left uninitialized by a DefaultInitAllocator).
template<int FIELDS, int FIELD_BITS, typename Vector, typename KeyOf>
void
sortByPackedKey(Vector& entries, const KeyOf& keyOf)
{
    static_assert(FIELD_BITS < 64 && FIELDS * FIELD_BITS <= 64, "the key has 64 bits");
    if (entries.size() < 2) return;
    constexpr std::uint64_t FIELD_MASK = (std::uint64_t(1) << FIELD_BITS) - 1;
    const std::uint64_t firstKey = keyOf(entries[0]);
    std::uint64_t differ = 0;
    for (const auto& e : entries) differ |= keyOf(e) ^ firstKey;
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
    // The buckets' starts for every pass, counted in one read of the entries.
    std::vector<std::size_t> start(std::size_t(passes) * buckets, 0);
    for (const auto& e : entries) {
        const std::uint64_t c = compact(keyOf(e));
        for (int pass = 0; pass < passes; ++pass) {
            ++start[std::size_t(pass) * buckets + ((c >> (pass * digitBits)) & (buckets - 1))];
        }
    }
    Vector buffer;
    buffer.resize(entries.size());
    for (int pass = 0; pass < passes; ++pass) {
        std::size_t* first = start.data() + std::size_t(pass) * buckets;
        std::size_t sum = 0;
        for (std::size_t b = 0; b < buckets; ++b) sum += std::exchange(first[b], sum);
        for (const auto& e : entries) {
            buffer[first[(compact(keyOf(e)) >> (pass * digitBits)) & (buckets - 1)]++] = e;
        }
        entries.swap(buffer);
    }
}

} // namespace vdbi

#endif // VDBI_RADIX_SORT_HAS_BEEN_INCLUDED
