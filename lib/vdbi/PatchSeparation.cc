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
/// round looks up no cell. A pair sharing several cells is taken in the lowest one: there,
/// along every axis, one of the two boxes starts. Every entry keeps the axes along which its
/// triangle's box starts in its cell, so that test reads nothing of the other triangle but
/// the entry next to its index.
class CandidateGrid
{
public:
    CandidateGrid(const InterfaceMesh& mesh, double cellSize, double margin, bool threaded)
        : mInverse(1.0 / cellSize)
    {
        const std::size_t count = mesh.triangles.size();
        std::vector<openvdb::Vec3i> low(count), high(count);
        mTriangleCellStart.assign(count + 1, 0);
        forEachChunk(count, CHUNK, threaded, [&](std::size_t, std::size_t begin, std::size_t end) {
            for (std::size_t f = begin; f < end; ++f) {
                const openvdb::Vec3I& t = mesh.triangles[f];
                Vec3d lo = mesh.points[t[0]], hi = lo;
                for (int i = 1; i < 3; ++i) {
                    lo = openvdb::math::minComponent(lo, mesh.points[t[i]]);
                    hi = openvdb::math::maxComponent(hi, mesh.points[t[i]]);
                }
                low[f] = cell(lo - Vec3d(margin));
                high[f] = cell(hi + Vec3d(margin));
                const openvdb::Vec3i size = high[f] - low[f] + openvdb::Vec3i(1);
                mTriangleCellStart[f + 1] = std::uint64_t(size[0]) * size[1] * size[2];
            }
        });
        for (std::size_t f = 0; f < count; ++f) mTriangleCellStart[f + 1] += mTriangleCellStart[f];

        // Every cell a triangle's box overlaps, sorted by (cell key, triangle): these are
        // unique, so the order does not depend on the sort.
        std::vector<Entry> entries(mTriangleCellStart[count]);
        forEachChunk(count, CHUNK, threaded, [&](std::size_t, std::size_t begin, std::size_t end) {
            for (std::size_t f = begin; f < end; ++f) {
                std::uint64_t j = mTriangleCellStart[f];
                for (int x = low[f][0]; x <= high[f][0]; ++x) {
                    for (int y = low[f][1]; y <= high[f][1]; ++y) {
                        for (int z = low[f][2]; z <= high[f][2]; ++z) {
                            const int starts = (x == low[f][0]) | (y == low[f][1]) << 1
                                | (z == low[f][2]) << 2;
                            entries[j++] = {key(openvdb::Vec3i(x, y, z)), std::uint32_t(f),
                                            std::uint8_t(starts)};
                        }
                    }
                }
            }
        });
        if (threaded) tbb::parallel_sort(entries.begin(), entries.end());
        else std::sort(entries.begin(), entries.end());

        mCellTriangles.resize(entries.size());
        mCellStarts.resize(entries.size());
        mTriangleCells.resize(entries.size());
        mTriangleStarts.resize(entries.size());
        std::vector<std::uint64_t> fill(mTriangleCellStart.begin(), mTriangleCellStart.end() - 1);
        for (std::size_t j = 0; j < entries.size(); ++j) {
            if (j == 0 || entries[j].key != entries[j - 1].key) mCellStart.push_back(j);
            const std::uint32_t f = entries[j].triangle;
            mCellTriangles[j] = f;
            mCellStarts[j] = entries[j].starts;
            mTriangleCells[fill[f]] = std::uint32_t(mCellStart.size() - 1);
            mTriangleStarts[fill[f]++] = entries[j].starts;
        }
        mCellStart.push_back(entries.size());
    }

    /// @brief Calls @a body(g) once for every triangle g != @a f sharing a cell with @a f.
    template<typename Body>
    void forEachNeighbour(std::uint32_t f, const Body& body) const
    {
        for (auto k = mTriangleCellStart[f]; k < mTriangleCellStart[f + 1]; ++k) {
            const std::uint32_t cellIndex = mTriangleCells[k];
            const std::uint8_t starts = mTriangleStarts[k];
            for (auto j = mCellStart[cellIndex]; j < mCellStart[cellIndex + 1]; ++j) {
                const std::uint32_t g = mCellTriangles[j];
                if (g != f && (starts | mCellStarts[j]) == ALL_AXES) body(g);
            }
        }
    }

    /// @brief Every pair (first < second) of meeting triangles, of one patch or of two,
    /// sharing a cell with at least one of them active, once each, in the order of the
    /// active triangle they were found from.
    std::vector<std::pair<std::uint32_t, std::uint32_t>>
    meetingPairs(const InterfaceMesh& mesh, const std::vector<char>& active, bool threaded) const
    {
        const std::size_t count = active.size();
        std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> perChunk(
            (count + CHUNK - 1) / CHUNK);
        auto search = [&](std::size_t c, std::size_t begin, std::size_t end) {
            for (std::uint32_t f = std::uint32_t(begin); f < end; ++f) {
                if (!active[f]) continue;
                forEachNeighbour(f, [&](std::uint32_t g) {
                    // Two active triangles: taken from the smaller one.
                    if (active[g] && g < f) return;
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
    /// Bits 0, 1, 2: the box starts in the cell along x, y, z.
    static constexpr std::uint8_t ALL_AXES = 7;

    struct Entry
    {
        std::uint64_t key;
        std::uint32_t triangle;
        std::uint8_t starts;
        bool operator<(const Entry& other) const
        {
            return key < other.key || (key == other.key && triangle < other.triangle);
        }
    };

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

    double mInverse;
    /// The cells, ascending by key: the triangles in cell c are mCellTriangles[mCellStart[c]
    /// .. mCellStart[c + 1]), ascending, their boxes starting there along mCellStarts.
    std::vector<std::uint64_t> mCellStart;
    std::vector<std::uint32_t> mCellTriangles;
    std::vector<std::uint8_t> mCellStarts;
    /// The cells of triangle f: mTriangleCells[mTriangleCellStart[f] .. [f + 1]), ascending,
    /// its box starting in them along mTriangleStarts.
    std::vector<std::uint64_t> mTriangleCellStart;
    std::vector<std::uint32_t> mTriangleCells;
    std::vector<std::uint8_t> mTriangleStarts;
};

/// @brief The state of separatePatches(): the triangles around every point, the candidate
/// grid, and where every point started.
class Separation
{
public:
    Separation(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
               const SeparationSettings& settings)
        : mMesh(mesh), mMovable(movable), mSettings(settings), mOrigin(mesh.points)
        , mPatchOf(mesh.triangles.size())
        , mGrid(mesh, settings.cellSize, settings.maxMove, settings.threaded)
    {
        for (std::uint32_t p = 0; p < mesh.patches.size(); ++p) {
            const InterfacePatch& patch = mesh.patches[p];
            std::fill_n(mPatchOf.begin() + patch.firstTriangle, patch.triangleCount, p);
        }
        const std::size_t pointCount = mesh.points.size();
        mStart.assign(pointCount + 1, 0);
        mAround.resize(3 * mesh.triangles.size());
        for (const openvdb::Vec3I& t : mesh.triangles) {
            for (int i = 0; i < 3; ++i) ++mStart[t[i] + 1];
        }
        for (std::size_t v = 0; v < pointCount; ++v) mStart[v + 1] += mStart[v];
        std::vector<std::uint32_t> fill(mStart.begin(), mStart.end() - 1);
        for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
            for (int i = 0; i < 3; ++i) mAround[fill[mesh.triangles[f][i]]++] = f;
        }
    }

    /// The rounds; returns the meeting pairs found in the last one.
    std::size_t run()
    {
        const std::size_t pointCount = mMesh.points.size();
        std::vector<char> active(mMesh.triangles.size(), 1), listed(pointCount, 0);
        std::vector<int> push(pointCount, 0);
        std::vector<std::uint32_t> corners;
        std::size_t crossing = 0;
        for (int round = 0; round < mSettings.rounds; ++round) {
            const auto pairs = mGrid.meetingPairs(mMesh, active, mSettings.threaded);
            crossing = pairs.size();
            if (crossing == 0) break;
            corners.clear();
            for (const auto& [f, g] : pairs) {
                for (const std::uint32_t h : {f, g}) {
                    const int away = awayFromSharedLabel(h, h == f ? g : f);
                    for (int i = 0; i < 3; ++i) {
                        const std::uint32_t v = mMesh.triangles[h][i];
                        if (!mMovable[v]) continue;
                        if (!listed[v]) corners.push_back(v);
                        listed[v] = 1;
                        push[v] += away;
                    }
                }
            }
            std::fill(active.begin(), active.end(), 0);
            std::sort(corners.begin(), corners.end());
            bool moved = false;
            for (const std::uint32_t v : corners) {
                listed[v] = 0;
                const int direction = push[v];
                push[v] = 0;
                if (!moveCorner(v, direction)) continue;
                for (std::uint32_t i = mStart[v]; i < mStart[v + 1]; ++i) active[mAround[i]] = 1;
                moved = true;
            }
            if (!moved) break;
        }
        return crossing;
    }

private:
    /// +1 or -1: which way along the normal of triangle @a h is away from the label its patch
    /// shares with that of @a other (the normal points from a into b); 0 for triangles of one
    /// patch, or of patches sharing no label.
    int awayFromSharedLabel(std::uint32_t h, std::uint32_t other) const
    {
        const InterfacePatch &p = mMesh.patches[mPatchOf[h]], &q = mMesh.patches[mPatchOf[other]];
        if (mPatchOf[h] == mPatchOf[other]) return 0;
        if (p.a == q.a || p.a == q.b) return 1;
        if (p.b == q.a || p.b == q.b) return -1;
        return 0;
    }

    Vec3d faceNormal(std::uint32_t f) const
    {
        const openvdb::Vec3I& t = mMesh.triangles[f];
        const PointArray& points = mMesh.points;
        return (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]);
    }

    /// Pairs that meet among the triangles around @a v and those near them (TriangleCrossing.h's
    /// test, pairs within one patch too): a move may not add any.
    std::size_t meetingsAround(std::uint32_t v) const
    {
        std::size_t count = 0;
        const std::uint32_t *first = mAround.data() + mStart[v],
                            *last = mAround.data() + mStart[v + 1];
        for (const std::uint32_t* i = first; i != last; ++i) {
            const std::uint32_t f = *i;
            mGrid.forEachNeighbour(f, [&](std::uint32_t g) {
                // A pair of two triangles around v is counted from the smaller one.
                if (g < f && std::find(first, last, g) != last) return;
                count += trianglesMeet(mMesh.points, mMesh.triangles[f], mMesh.triangles[g]);
            });
        }
        return count;
    }

    /// @brief Moves @a v to @a next if that leaves at most @a limit meeting pairs around it,
    /// keeps it within maxMove of its start and turns no triangle around it over.
    /// @details A triangle that faced against the vertex normal @a normal (a fold, or no
    /// area) may turn to face with it: that is how a folded fan opens.
    bool moveTo(std::uint32_t v, const Vec3d& next, const Vec3d& normal, std::size_t limit)
    {
        if ((next - mOrigin[v]).length() > mSettings.maxMove) return false;
        mBefore.clear();
        for (std::uint32_t i = mStart[v]; i < mStart[v + 1]; ++i) {
            mBefore.push_back(faceNormal(mAround[i]));
        }
        const Vec3d old = mMesh.points[v];
        mMesh.points[v] = next;
        bool turned = false;
        for (std::uint32_t i = mStart[v]; i < mStart[v + 1] && !turned; ++i) {
            const Vec3d& before = mBefore[i - mStart[v]];
            const Vec3d after = faceNormal(mAround[i]);
            turned = !(after.dot(before) > 0.0)
                && !(before.dot(normal) <= 0.0 && after.dot(normal) > 0.0);
        }
        if (turned || meetingsAround(v) > limit) {
            mMesh.points[v] = old;
            return false;
        }
        return true;
    }

    /// @brief Moves corner @a v of meeting pairs, pushed @a direction times away from shared
    /// labels, to the first of these that leaves fewer meeting pairs around it: one step
    /// along its normal that way, the mean of its neighbours (kept within maxMove of its
    /// start), half way there. Else the step that way if it adds no meeting pair (a wedge
    /// opens over several rounds); else a step along or against the normal that removes one.
    bool moveCorner(std::uint32_t v, int direction)
    {
        Vec3d normal(0.0);
        for (std::uint32_t i = mStart[v]; i < mStart[v + 1]; ++i) {
            normal += faceNormal(mAround[i]);
        }
        const double length = normal.length();
        const Vec3d here = mMesh.points[v];
        const Vec3d step = length > 0.0 ? normal * (mSettings.step / length) : Vec3d(0.0);
        const bool pushed = direction != 0 && length > 0.0;
        const Vec3d push = direction > 0 ? here + step : here - step;
        const std::size_t meetings = meetingsAround(v);
        if (meetings > 0) {
            const Vec3d mean = towardsNeighbours(v);
            if ((pushed && moveTo(v, push, normal, meetings - 1))
                || moveTo(v, mean, normal, meetings - 1)
                || moveTo(v, (here + mean) * 0.5, normal, meetings - 1)) {
                return true;
            }
        }
        if (pushed && moveTo(v, push, normal, meetings)) return true;
        if (meetings == 0 || !(length > 0.0)) return false;
        return (direction <= 0 && moveTo(v, here + step, normal, meetings - 1))
            || (direction >= 0 && moveTo(v, here - step, normal, meetings - 1));
    }

    /// The mean of the other corners of the triangles around @a v, pulled back to within
    /// maxMove of where @a v started.
    Vec3d towardsNeighbours(std::uint32_t v) const
    {
        Vec3d sum(0.0);
        double weight = 0.0;
        for (std::uint32_t i = mStart[v]; i < mStart[v + 1]; ++i) {
            const openvdb::Vec3I& t = mMesh.triangles[mAround[i]];
            for (int k = 0; k < 3; ++k) {
                if (t[k] == v) continue;
                sum += mMesh.points[t[k]];
                weight += 1.0;
            }
        }
        if (weight == 0.0) return mMesh.points[v];
        const Vec3d offset = sum / weight - mOrigin[v];
        const double distance = offset.length();
        if (distance <= mSettings.maxMove) return mOrigin[v] + offset;
        return mOrigin[v] + offset * (mSettings.maxMove / distance);
    }

    InterfaceMesh& mMesh;
    const std::vector<std::uint8_t>& mMovable;
    const SeparationSettings& mSettings;
    const PointArray mOrigin;
    std::vector<std::uint32_t> mPatchOf;
    const CandidateGrid mGrid;
    /// Triangles around every point: mAround[mStart[v] .. mStart[v + 1]).
    std::vector<std::uint32_t> mStart, mAround;
    std::vector<Vec3d> mBefore;
};

} // namespace


std::size_t
separatePatches(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                const SeparationSettings& settings)
{
    return Separation(mesh, movable, settings).run();
}

} // namespace vdbi
