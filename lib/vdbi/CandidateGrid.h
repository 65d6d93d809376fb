// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/CandidateGrid.h
/// @brief A uniform grid over the triangles of an InterfaceMesh that yields the pairs of
/// triangles near enough to meet, for patch separation (PatchSeparation.h).

#ifndef VDBI_CANDIDATE_GRID_HAS_BEEN_INCLUDED
#define VDBI_CANDIDATE_GRID_HAS_BEEN_INCLUDED

#include <vdbi/InterfaceMesh.h>

#include <openvdb/Types.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace vdbi {

/// Pairs (first < second) of triangle indices.
using TrianglePairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

/// Whether triangles f and g meet (the test is the caller's).
using MeetTest = std::function<bool(std::uint32_t f, std::uint32_t g)>;

/// The cell of @a p in a grid of cubes 1 / @a inverse wide.
openvdb::Vec3i cellOf(const openvdb::Vec3d& p, double inverse);

/// Bits per axis of a cellKey().
constexpr int CELL_KEY_BITS = 21;

/// A cell as one key, CELL_KEY_BITS per axis (x highest): far apart cells may share a key,
/// which only makes more candidates to test.
std::uint64_t cellKey(const openvdb::Vec3i& c);

/// @brief Calls @a body(index) for every entry of @a entries (sorted pairs of cellKey() and
/// an index) in the cells [@a low, @a high].
/// @details z is the key's lowest part: a column of cells along z is one run of keys, found
/// by one binary search (at 4 voxels a guard's box spans ~10 cells along each axis). A
/// column whose z range wraps around the key's 21 bits is looked up cell by cell. Entries
/// come by x, then y, then z, in their order.
template<typename Body>
void
forEachEntryInCells(const std::vector<std::pair<std::uint64_t, std::uint32_t>>& entries,
                    const openvdb::Vec3i& low, const openvdb::Vec3i& high, const Body& body)
{
    using Iterator = std::vector<std::pair<std::uint64_t, std::uint32_t>>::const_iterator;
    // Columns come in ascending keys but where a key wraps: the search for the next starts
    // where the last ended, with steps that double (a few entries away, not log n).
    Iterator hint = entries.begin();
    for (int x = low[0]; x <= high[0]; ++x) {
        for (int y = low[1]; y <= high[1]; ++y) {
            auto scan = [&](int from, int to) {
                const std::uint64_t first = cellKey(openvdb::Vec3i(x, y, from));
                const std::uint64_t last = cellKey(openvdb::Vec3i(x, y, to));
                const auto key = std::make_pair(first, std::uint32_t(0));
                Iterator begin = entries.begin(), end = entries.end();
                if (hint != end && *hint < key) {
                    begin = hint + 1;
                    for (std::ptrdiff_t step = 1; end - begin > step; step *= 2) {
                        if (!(begin[step] < key)) {
                            end = begin + step;
                            break;
                        }
                        begin += step + 1;
                    }
                } else if (hint != entries.begin() && !(hint[-1] < key)) {
                    end = hint;
                } else {
                    begin = end = hint;
                }
                Iterator it = std::lower_bound(begin, end, key);
                for (; it != entries.end() && it->first <= last; ++it) body(it->second);
                hint = it;
            };
            if (cellKey(openvdb::Vec3i(x, y, low[2])) <= cellKey(openvdb::Vec3i(x, y, high[2]))) {
                scan(low[2], high[2]);
            } else {
                for (int z = low[2]; z <= high[2]; ++z) scan(z, z);
            }
        }
    }
}

/// The cells [@a low, @a high] (of cubes 1 / @a inverse wide) that the bounding box of
/// triangle @a f, widened by @a margin, overlaps.
void triangleCells(const InterfaceMesh& mesh, std::size_t f, double margin, double inverse,
                   openvdb::Vec3i& low, openvdb::Vec3i& high);

/// @brief Triangles bucketed by the grid cells their bounding boxes overlap, built once.
/// @details No vertex moves farther than a margin from where it was when the grid was built,
/// so every box is widened by that margin: two triangles that can ever meet share a cell.
/// A pair sharing several cells is taken in the lowest one: there, along every axis, one of
/// the two boxes starts. Every entry keeps the axes along which its triangle's box starts in
/// its cell, so that test reads nothing but the entries being walked. The first round walks
/// the cells, later ones look up the cells of a few triangles.
/// A cell is as wide as the widened box of a triangle with edges of @a cellSize, so that such
/// a box overlaps about 8 cells: narrower cells make more entries to sort than they save pair
/// tests. The output is the same for any number of threads.
class CandidateGrid
{
public:
    CandidateGrid(const InterfaceMesh& mesh, double cellSize, double margin, bool threaded);

    /// @brief Calls @a body(g) once for every triangle g != @a f sharing a cell with @a f.
    template<typename Body>
    void forEachNeighbour(std::uint32_t f, const Body& body) const
    {
        forEachCell(f, [&](const openvdb::Vec3i& c, std::uint8_t starts) {
            const std::size_t cellIndex = std::size_t(
                std::lower_bound(mCellKeys.begin(), mCellKeys.end(), cellKey(c))
                - mCellKeys.begin());
            for (auto j = mCellStart[cellIndex]; j < mCellStart[cellIndex + 1]; ++j) {
                const std::uint32_t g = mCellTriangles[j];
                if (g != f && isLowestSharedCell(starts, mCellStarts[j])) body(g);
            }
        });
    }

    /// @brief Calls @a body(g) for every triangle g whose box shares a cell with the box
    /// [@a low, @a high], once per shared cell.
    template<typename Body>
    void forEachInBox(const openvdb::Vec3d& low, const openvdb::Vec3d& high, const Body& body) const
    {
        const openvdb::Vec3i lo = cellOf(low, mInverse), hi = cellOf(high, mInverse);
        for (int x = lo[0]; x <= hi[0]; ++x) {
            for (int y = lo[1]; y <= hi[1]; ++y) {
                for (int z = lo[2]; z <= hi[2]; ++z) {
                    const std::uint64_t key = cellKey(openvdb::Vec3i(x, y, z));
                    const auto cell = std::lower_bound(mCellKeys.begin(), mCellKeys.end(), key);
                    if (cell == mCellKeys.end() || *cell != key) continue;
                    const std::size_t c = std::size_t(cell - mCellKeys.begin());
                    for (auto j = mCellStart[c]; j < mCellStart[c + 1]; ++j) body(mCellTriangles[j]);
                }
            }
        }
    }

    /// The cells [@a low, @a high] that the (widened) box of triangle @a f overlaps.
    void cellRange(std::uint32_t f, openvdb::Vec3i& low, openvdb::Vec3i& high) const
    {
        low = mLow[f];
        high = mHigh[f];
    }
    /// The width of a cell.
    double cellWidth() const { return 1.0 / mInverse; }

    /// @brief Every pair (first < second) of triangles sharing a cell that @a meet accepts,
    /// once each, in the order of the cells.
    TrianglePairs allMeetingPairs(const MeetTest& meet, bool threaded) const;

    /// @brief Every pair (first < second) of triangles sharing a cell, at least one of them
    /// @a active, that @a meet accepts, once each, in the order of the active triangle they
    /// were found from.
    TrianglePairs meetingPairs(const std::vector<char>& active, const MeetTest& meet,
                               bool threaded) const;

private:
    /// Bits 0, 1, 2 of an entry's starts: its box starts in the cell along x, y, z.
    static constexpr std::uint8_t ALL_AXES = 7;

    /// Whether a cell is the lowest that two boxes share, from the starts of their entries
    /// there: along every axis one of them starts in it.
    static bool isLowestSharedCell(std::uint8_t starts, std::uint8_t otherStarts)
    {
        return (starts | otherStarts) == ALL_AXES;
    }

    /// Calls @a body(c, starts) for every cell c of the box of triangle @a f, with the axes
    /// along which the box starts there.
    template<typename Body>
    void forEachCell(std::uint32_t f, const Body& body) const
    {
        const openvdb::Vec3i &lo = mLow[f], &hi = mHigh[f];
        for (int x = lo[0]; x <= hi[0]; ++x) {
            for (int y = lo[1]; y <= hi[1]; ++y) {
                for (int z = lo[2]; z <= hi[2]; ++z) {
                    body(openvdb::Vec3i(x, y, z),
                         std::uint8_t((x == lo[0]) | (y == lo[1]) << 1 | (z == lo[2]) << 2));
                }
            }
        }
    }

    double mInverse;
    /// The cells of the box of every triangle.
    std::vector<openvdb::Vec3i> mLow, mHigh;
    /// The cells, ascending by key: the triangles in cell c are mCellTriangles[mCellStart[c]
    /// .. mCellStart[c + 1]), ascending, their boxes starting there along mCellStarts.
    std::vector<std::uint64_t> mCellKeys, mCellStart;
    std::vector<std::uint32_t, DefaultInitAllocator<std::uint32_t>> mCellTriangles;
    std::vector<std::uint8_t, DefaultInitAllocator<std::uint8_t>> mCellStarts;
};

/// @brief Every pair (first < second) of triangles of @a mesh that meet other than in the
/// corners and edges they share (trianglesMeet() of TriangleCrossing.h), ascending.
/// @details One search over the whole mesh, on a grid of cells about @a cellSize wide (the
/// edge length): what is left of the crossings that separation removes, counted afresh.
TrianglePairs findMeetingPairs(const InterfaceMesh& mesh, double cellSize, bool threaded);

} // namespace vdbi

#endif // VDBI_CANDIDATE_GRID_HAS_BEEN_INCLUDED
