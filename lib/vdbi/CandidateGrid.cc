// SPDX-License-Identifier: Apache-2.0

#include <vdbi/CandidateGrid.h>

#include <vdbi/ParallelRanges.h>
#include <vdbi/RadixSort.h>
#include <vdbi/TriangleCrossing.h>

#include <cmath>

namespace vdbi {

namespace {

/// Triangles (entries) per parallel task, and cells: the output is the same for any number
/// of threads.
constexpr std::size_t CHUNK = 4096, CELL_CHUNK = 1024;

/// Calls @a body(c, begin, end) for chunk c = [begin, end) of [0, count) in chunks of fixed
/// size, in parallel or not.
template<typename Body>
void
forEachChunk(std::size_t count, std::size_t chunk, bool threaded, const Body& body)
{
    forEachRange((count + chunk - 1) / chunk, 1, threaded, [&](std::size_t begin, std::size_t end) {
        for (std::size_t c = begin; c < end; ++c) {
            body(c, c * chunk, std::min(count, (c + 1) * chunk));
        }
    });
}

TrianglePairs
concatenate(const std::vector<TrianglePairs>& parts)
{
    TrianglePairs all;
    for (const TrianglePairs& part : parts) all.insert(all.end(), part.begin(), part.end());
    return all;
}

/// A triangle's entry in a cell its box overlaps.
struct Entry
{
    std::uint64_t key;
    std::uint32_t triangle;
    std::uint8_t starts;
};

} // namespace


openvdb::Vec3i
cellOf(const openvdb::Vec3d& p, double inverse)
{
    return openvdb::Vec3i(int(std::floor(p[0] * inverse)), int(std::floor(p[1] * inverse)),
                          int(std::floor(p[2] * inverse)));
}


std::uint64_t
cellKey(const openvdb::Vec3i& c)
{
    const std::uint64_t mask = (std::uint64_t(1) << CELL_KEY_BITS) - 1;
    return (std::uint64_t(c[0]) & mask) << (2 * CELL_KEY_BITS)
        | (std::uint64_t(c[1]) & mask) << CELL_KEY_BITS
        | (std::uint64_t(c[2]) & mask);
}


void
triangleCells(const InterfaceMesh& mesh, std::size_t f, double margin, double inverse,
              openvdb::Vec3i& low, openvdb::Vec3i& high)
{
    const openvdb::Vec3I& t = mesh.triangles[f];
    openvdb::Vec3d lo = mesh.points[t[0]], hi = lo;
    for (int i = 1; i < 3; ++i) {
        lo = openvdb::math::minComponent(lo, mesh.points[t[i]]);
        hi = openvdb::math::maxComponent(hi, mesh.points[t[i]]);
    }
    low = cellOf(lo - openvdb::Vec3d(margin), inverse);
    high = cellOf(hi + openvdb::Vec3d(margin), inverse);
}


CandidateGrid::CandidateGrid(const InterfaceMesh& mesh, double cellSize, double margin,
                             bool threaded)
    : mInverse(1.0 / (cellSize + 2.0 * margin))
    , mLow(mesh.triangles.size()), mHigh(mesh.triangles.size())
{
    const std::size_t count = mesh.triangles.size();
    // The entries of triangle f: [first[f], first[f + 1]).
    std::vector<std::uint64_t> first(count + 1, 0);
    forEachChunk(count, CHUNK, threaded, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t f = begin; f < end; ++f) {
            triangleCells(mesh, f, margin, mInverse, mLow[f], mHigh[f]);
            const openvdb::Vec3i size = mHigh[f] - mLow[f] + openvdb::Vec3i(1);
            first[f + 1] = std::uint64_t(size[0]) * size[1] * size[2];
        }
    });
    for (std::size_t f = 0; f < count; ++f) first[f + 1] += first[f];

    // Every cell a triangle's box overlaps, made triangle by triangle and sorted by cell key
    // keeping that order: by (cell key, triangle) on any number of threads. Left unset until
    // the threads fill it, as hundreds of MB are zeroed by one thread otherwise.
    std::vector<Entry, DefaultInitAllocator<Entry>> entries(first[count]);
    forEachChunk(count, CHUNK, threaded, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t f = begin; f < end; ++f) {
            std::uint64_t j = first[f];
            forEachCell(std::uint32_t(f), [&](const openvdb::Vec3i& c, std::uint8_t starts) {
                entries[j++] = {cellKey(c), std::uint32_t(f), starts};
            });
        }
    });
    sortByPackedKey<3, CELL_KEY_BITS>(entries, [](const Entry& e) { return e.key; }, threaded);

    for (std::size_t j = 0; j < entries.size(); ++j) {
        if (j > 0 && entries[j].key == entries[j - 1].key) continue;
        mCellKeys.push_back(entries[j].key);
        mCellStart.push_back(j);
    }
    mCellStart.push_back(entries.size());
    mCellTriangles.resize(entries.size());
    mCellStarts.resize(entries.size());
    forEachChunk(entries.size(), CHUNK, threaded,
                 [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t j = begin; j < end; ++j) {
            mCellTriangles[j] = entries[j].triangle;
            mCellStarts[j] = entries[j].starts;
        }
    });
}


TrianglePairs
CandidateGrid::allMeetingPairs(const MeetTest& meet, bool threaded) const
{
    const std::size_t cellCount = mCellKeys.size();
    std::vector<TrianglePairs> perChunk((cellCount + CELL_CHUNK - 1) / CELL_CHUNK);
    auto search = [&](std::size_t chunk, std::size_t begin, std::size_t end) {
        for (std::size_t c = begin; c < end; ++c) {
            for (auto i = mCellStart[c]; i < mCellStart[c + 1]; ++i) {
                const std::uint32_t f = mCellTriangles[i];
                for (auto j = i + 1; j < mCellStart[c + 1]; ++j) {
                    const std::uint32_t g = mCellTriangles[j];
                    if (isLowestSharedCell(mCellStarts[i], mCellStarts[j]) && meet(f, g)) {
                        perChunk[chunk].emplace_back(f, g);
                    }
                }
            }
        }
    };
    forEachChunk(cellCount, CELL_CHUNK, threaded, search);
    return concatenate(perChunk);
}


TrianglePairs
CandidateGrid::meetingPairs(const std::vector<char>& active, const MeetTest& meet,
                            bool threaded) const
{
    const std::size_t count = active.size();
    std::vector<TrianglePairs> perChunk((count + CHUNK - 1) / CHUNK);
    auto search = [&](std::size_t c, std::size_t begin, std::size_t end) {
        for (std::uint32_t f = std::uint32_t(begin); f < end; ++f) {
            if (!active[f]) continue;
            forEachNeighbour(f, [&](std::uint32_t g) {
                // Two active triangles: taken from the smaller one.
                if (active[g] && g < f) return;
                if (meet(f, g)) perChunk[c].emplace_back(std::min(f, g), std::max(f, g));
            });
        }
    };
    forEachChunk(count, CHUNK, threaded, search);
    return concatenate(perChunk);
}

TrianglePairs
findMeetingPairs(const InterfaceMesh& mesh, double cellSize, bool threaded)
{
    const CandidateGrid grid(mesh, cellSize, 0.0, threaded);
    TrianglePairs pairs = grid.allMeetingPairs([&mesh](std::uint32_t f, std::uint32_t g) {
        return trianglesMeet(mesh.points, mesh.triangles[f], mesh.triangles[g]);
    }, threaded);
    std::sort(pairs.begin(), pairs.end());
    return pairs;
}

} // namespace vdbi
