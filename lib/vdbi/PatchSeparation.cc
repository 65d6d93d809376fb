// SPDX-License-Identifier: Apache-2.0

#include <vdbi/PatchSeparation.h>

#include <vdbi/TriangleCrossing.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace vdbi {

namespace {

using Vec3d = openvdb::Vec3d;

/// Triangle @a t as trianglesCross() takes it, turned around (two corners swapped) if @a flip.
CornerTriangle
cornerTriangle(const PointArray& points, const openvdb::Vec3I& t, bool flip)
{
    const int i = flip ? 2 : 1, j = flip ? 1 : 2;
    return CornerTriangle(toPoint(points[t[0]]), toPoint(points[t[i]]), toPoint(points[t[j]]),
                          int(t[0]), int(t[i]), int(t[j]));
}

/// Does @a t run along an edge of @a s in the same direction as @a s?
bool
runsAlongSameWay(const openvdb::Vec3I& s, const openvdb::Vec3I& t)
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (s[i] == t[j] && s[(i + 1) % 3] == t[(j + 1) % 3]) return true;
        }
    }
    return false;
}

/// @brief Do triangles @a s and @a t meet other than in the corners and edges they share?
/// @details trianglesCross() (TriangleCrossing.h), which reads a fold of two triangles
/// sharing an edge from normals turned by almost 180 degrees: that holds for two triangles
/// running along the edge in opposite directions, as within a consistently oriented patch.
/// Every patch is oriented by its own label pair, so a triangle of another patch running
/// along the edge the same way is turned around first. A triangle without area has no plane
/// to test the other against, so it is passed second.
bool
trianglesMeet(const PointArray& points, const openvdb::Vec3I& s, const openvdb::Vec3I& t)
{
    CornerTriangle first = cornerTriangle(points, s, false);
    CornerTriangle second = cornerTriangle(points, t, runsAlongSameWay(s, t));
    if (first.normal.sqrnorm() == 0.0) std::swap(first, second);
    return trianglesCross(first, second);
}

/// Calls @a body(c, begin, end) for chunk c = [begin, end) of [0, count) in chunks of fixed
/// size, in parallel or not.
template<typename Body>
void
forEachChunk(std::size_t count, std::size_t chunk, bool threaded, const Body& body)
{
    const std::size_t chunks = (count + chunk - 1) / chunk;
    auto run = [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t c = r.begin(); c < r.end(); ++c) {
            body(c, c * chunk, std::min(count, (c + 1) * chunk));
        }
    };
    const tbb::blocked_range<std::size_t> all(0, chunks, 1);
    if (threaded) tbb::parallel_for(all, run);
    else run(all);
}

/// @brief Triangles bucketed by the grid cells their bounding boxes overlap, built once.
/// @details No vertex moves farther than a margin from where it was when the grid was built,
/// so every box is widened by that margin: two triangles that can ever meet share a cell.
/// Both ways are stored (the triangles of every cell, the cells of every triangle), so a
/// round looks up no cell.
class CandidateGrid
{
public:
    CandidateGrid(const InterfaceMesh& mesh, double cellSize, double margin, bool threaded)
        : mInverse(1.0 / cellSize)
    {
        const std::size_t count = mesh.triangles.size();
        mLow.resize(count);
        mHigh.resize(count);
        mTriangleCellStart.assign(count + 1, 0);
        forEachChunk(count, CHUNK, threaded, [&](std::size_t, std::size_t begin, std::size_t end) {
            for (std::size_t f = begin; f < end; ++f) {
                const openvdb::Vec3I& t = mesh.triangles[f];
                Vec3d lo = mesh.points[t[0]], hi = lo;
                for (int i = 1; i < 3; ++i) {
                    lo = openvdb::math::minComponent(lo, mesh.points[t[i]]);
                    hi = openvdb::math::maxComponent(hi, mesh.points[t[i]]);
                }
                mLow[f] = cell(lo - Vec3d(margin));
                mHigh[f] = cell(hi + Vec3d(margin));
                const openvdb::Vec3i size = mHigh[f] - mLow[f] + openvdb::Vec3i(1);
                mTriangleCellStart[f + 1] = std::uint64_t(size[0]) * size[1] * size[2];
            }
        });
        for (std::size_t f = 0; f < count; ++f) mTriangleCellStart[f + 1] += mTriangleCellStart[f];

        // (cell key, triangle) of every cell a triangle's box overlaps, sorted: the pairs are
        // unique, so the order does not depend on the sort.
        std::vector<std::pair<std::uint64_t, std::uint32_t>> entries(mTriangleCellStart[count]);
        forEachChunk(count, CHUNK, threaded, [&](std::size_t, std::size_t begin, std::size_t end) {
            for (std::size_t f = begin; f < end; ++f) {
                std::uint64_t j = mTriangleCellStart[f];
                forEachCell(f, [&](std::uint64_t key) { entries[j++] = {key, std::uint32_t(f)}; });
            }
        });
        if (threaded) tbb::parallel_sort(entries.begin(), entries.end());
        else std::sort(entries.begin(), entries.end());

        mCellTriangles.resize(entries.size());
        mTriangleCells.resize(entries.size());
        std::vector<std::uint64_t> fill(mTriangleCellStart.begin(), mTriangleCellStart.end() - 1);
        for (std::size_t j = 0; j < entries.size(); ++j) {
            if (j == 0 || entries[j].first != entries[j - 1].first) {
                mCellKeys.push_back(entries[j].first);
                mCellStart.push_back(j);
            }
            const std::uint32_t f = entries[j].second;
            mCellTriangles[j] = f;
            mTriangleCells[fill[f]++] = std::uint32_t(mCellKeys.size() - 1);
        }
        mCellStart.push_back(entries.size());
    }

    /// @brief Calls @a body(g) once for every triangle g != @a f sharing a cell with @a f.
    template<typename Body>
    void forEachNeighbour(std::uint32_t f, const Body& body) const
    {
        for (auto k = mTriangleCellStart[f]; k < mTriangleCellStart[f + 1]; ++k) {
            const std::uint32_t cellIndex = mTriangleCells[k];
            for (auto j = mCellStart[cellIndex]; j < mCellStart[cellIndex + 1]; ++j) {
                const std::uint32_t g = mCellTriangles[j];
                if (g == f) continue;
                // A pair sharing several cells is taken in the lowest one.
                openvdb::Vec3i lo;
                for (int i = 0; i < 3; ++i) lo[i] = std::max(mLow[f][i], mLow[g][i]);
                if (key(lo) == mCellKeys[cellIndex]) body(g);
            }
        }
    }

    /// @brief Every pair (first < second) of meeting triangles of different patches
    /// (@a patchOf) sharing a cell with at least one of them active, once each, in the order
    /// of the active triangle they were found from.
    std::vector<std::pair<std::uint32_t, std::uint32_t>>
    meetingPairs(const InterfaceMesh& mesh, const std::vector<char>& active,
                 const std::vector<std::uint32_t>& patchOf, bool threaded) const
    {
        const std::size_t count = active.size();
        std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> perChunk(
            (count + CHUNK - 1) / CHUNK);
        auto search = [&](std::size_t c, std::size_t begin, std::size_t end) {
            for (std::uint32_t f = std::uint32_t(begin); f < end; ++f) {
                if (!active[f]) continue;
                forEachNeighbour(f, [&](std::uint32_t g) {
                    // Two active triangles: taken from the smaller one.
                    if (patchOf[g] == patchOf[f] || (active[g] && g < f)) return;
                    if (trianglesMeet(mesh.points, mesh.triangles[f], mesh.triangles[g])) {
                        perChunk[c].emplace_back(std::min(f, g), std::max(f, g));
                    }
                });
            }
        };
        forEachChunk(count, CHUNK, threaded, search);
        std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
        for (const auto& chunk : perChunk) pairs.insert(pairs.end(), chunk.begin(), chunk.end());
        return pairs;
    }

private:
    /// Triangles per parallel task: the output is the same for any number of threads.
    static constexpr std::size_t CHUNK = 4096;

    openvdb::Vec3i cell(const Vec3d& p) const
    {
        return openvdb::Vec3i(int(std::floor(p[0] * mInverse)), int(std::floor(p[1] * mInverse)),
                              int(std::floor(p[2] * mInverse)));
    }
    static std::uint64_t key(const openvdb::Vec3i& c)
    {
        const std::uint64_t mask = (std::uint64_t(1) << 21) - 1;
        return (std::uint64_t(c[0]) & mask) << 42 | (std::uint64_t(c[1]) & mask) << 21
            | (std::uint64_t(c[2]) & mask);
    }
    template<typename Body>
    void forEachCell(std::size_t f, const Body& body) const
    {
        for (int x = mLow[f][0]; x <= mHigh[f][0]; ++x) {
            for (int y = mLow[f][1]; y <= mHigh[f][1]; ++y) {
                for (int z = mLow[f][2]; z <= mHigh[f][2]; ++z) {
                    body(key(openvdb::Vec3i(x, y, z)));
                }
            }
        }
    }

    double mInverse;
    std::vector<openvdb::Vec3i> mLow, mHigh;
    /// The cells, ascending by key: the triangles in cell c are mCellTriangles[mCellStart[c]
    /// .. mCellStart[c + 1]), ascending.
    std::vector<std::uint64_t> mCellKeys, mCellStart;
    std::vector<std::uint32_t> mCellTriangles;
    /// The cells of triangle f: mTriangleCells[mTriangleCellStart[f] .. [f + 1]), ascending.
    std::vector<std::uint64_t> mTriangleCellStart;
    std::vector<std::uint32_t> mTriangleCells;
};

} // namespace


std::size_t
separatePatches(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                const SeparationSettings& settings)
{
    const std::size_t pointCount = mesh.points.size(), triangleCount = mesh.triangles.size();
    std::vector<std::uint32_t> patchOf(triangleCount);
    for (std::uint32_t p = 0; p < mesh.patches.size(); ++p) {
        const InterfacePatch& patch = mesh.patches[p];
        for (std::size_t t = 0; t < patch.triangleCount; ++t) patchOf[patch.firstTriangle + t] = p;
    }
    // Triangles around every point, CSR.
    std::vector<std::uint32_t> start(pointCount + 1, 0), around(3 * triangleCount);
    for (const openvdb::Vec3I& t : mesh.triangles) for (int i = 0; i < 3; ++i) ++start[t[i] + 1];
    for (std::size_t v = 0; v < pointCount; ++v) start[v + 1] += start[v];
    {
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::uint32_t f = 0; f < triangleCount; ++f) {
            for (int i = 0; i < 3; ++i) around[fill[mesh.triangles[f][i]]++] = f;
        }
    }
    auto faceNormal = [&](std::uint32_t f) {
        const openvdb::Vec3I& t = mesh.triangles[f];
        return (mesh.points[t[1]] - mesh.points[t[0]]).cross(mesh.points[t[2]] - mesh.points[t[0]]);
    };
    const CandidateGrid grid(mesh, settings.cellSize, settings.maxMove, settings.threaded);
    // Pairs that meet among the triangles around v and those near them (TriangleCrossing.h's
    // test, pairs within one patch too): a move may not add any.
    auto meetingsAround = [&](std::uint32_t v) {
        std::size_t count = 0;
        const std::uint32_t *first = around.data() + start[v], *last = around.data() + start[v + 1];
        for (const std::uint32_t* i = first; i != last; ++i) {
            const std::uint32_t f = *i;
            grid.forEachNeighbour(f, [&](std::uint32_t g) {
                // A pair of two triangles around v is counted from the smaller one.
                if (g < f && std::find(first, last, g) != last) return;
                count += trianglesMeet(mesh.points, mesh.triangles[f], mesh.triangles[g]);
            });
        }
        return count;
    };
    const PointArray origin = mesh.points;
    std::vector<char> active(triangleCount, 1);
    std::vector<int> push(pointCount, 0);
    std::vector<std::uint32_t> pushed;
    std::vector<Vec3d> before;
    std::size_t crossing = 0;
    for (int round = 0; round < settings.rounds; ++round) {
        crossing = 0;
        pushed.clear();
        for (const auto& [f, g] : grid.meetingPairs(mesh, active, patchOf, settings.threaded)) {
            ++crossing;
            const InterfacePatch &pf = mesh.patches[patchOf[f]], &pg = mesh.patches[patchOf[g]];
            Label shared;
            if (pf.a == pg.a || pf.a == pg.b) shared = pf.a;
            else if (pf.b == pg.a || pf.b == pg.b) shared = pf.b;
            else continue;
            // The normal points from a into b: away from the shared label is against it when
            // the shared label is b.
            for (const std::uint32_t h : {f, g}) {
                const InterfacePatch& patch = h == f ? pf : pg;
                const int away = shared == patch.b ? -1 : 1;
                for (int i = 0; i < 3; ++i) {
                    const std::uint32_t v = mesh.triangles[h][i];
                    if (!movable[v]) continue;
                    if (push[v] == 0) pushed.push_back(v);
                    push[v] += away;
                }
            }
        }
        if (crossing == 0) break;
        std::fill(active.begin(), active.end(), 0);
        std::sort(pushed.begin(), pushed.end());
        bool moved = false;
        for (const std::uint32_t v : pushed) {
            const int direction = push[v];
            push[v] = 0;
            if (direction == 0) continue;
            Vec3d normal(0.0);
            for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) normal += faceNormal(around[i]);
            const double length = normal.length();
            if (!(length > 0.0)) continue;
            const Vec3d old = mesh.points[v];
            const Vec3d next = old + normal * (settings.step * (direction > 0 ? 1.0 : -1.0)
                                                / length);
            if ((next - origin[v]).length() > settings.maxMove) continue;
            before.clear();
            for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) {
                before.push_back(faceNormal(around[i]));
            }
            const std::size_t meetings = meetingsAround(v);
            mesh.points[v] = next;
            bool turned = false;
            for (std::uint32_t i = start[v]; i < start[v + 1] && !turned; ++i) {
                turned = !(faceNormal(around[i]).dot(before[i - start[v]]) > 0.0);
            }
            if (turned || meetingsAround(v) > meetings) {
                mesh.points[v] = old;
                continue;
            }
            for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) active[around[i]] = 1;
            moved = true;
        }
        if (!moved) break;
    }
    return crossing;
}

} // namespace vdbi
