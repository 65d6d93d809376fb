// SPDX-License-Identifier: Apache-2.0

#include <vdbi/MeetingEdgeCollapses.h>

#include <vdbi/TriangleCrossing.h>

#include <algorithm>
#include <limits>

namespace vdbi {

namespace {

using Vec3d = openvdb::Vec3d;
using Vec3I = openvdb::Vec3I;

bool
hasCorner(const Vec3I& t, std::uint32_t v)
{
    return t[0] == v || t[1] == v || t[2] == v;
}

/// An axis-aligned box.
struct Box
{
    Vec3d low, high;

    void add(const Box& b)
    {
        low = openvdb::math::minComponent(low, b.low);
        high = openvdb::math::maxComponent(high, b.high);
    }
    bool overlaps(const Box& b) const
    {
        for (int k = 0; k < 3; ++k) {
            if (high[k] < b.low[k] || b.high[k] < low[k]) return false;
        }
        return true;
    }
};

/// The collapse of free point u into its neighbour v.
struct Collapse
{
    std::uint32_t u = 0, v = 0;
    Vec3d position;   ///< v's new place
    int gain = 0;     ///< meeting pairs freed
};

class EdgeCollapser
{
public:
    EdgeCollapser(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                  double cellSize, bool threaded)
        : mMesh(mesh), mMovable(movable), mGrid(mesh, cellSize, 0.0, threaded)
        , mPatchOf(trianglePatches(mesh)), mRemoved(mesh.triangles.size(), 0)
        , mChanged(mesh.points.size(), 0)
    {
        findAround();
    }

    std::size_t run(const TrianglePairs& pairs, TrianglePairs* left)
    {
        std::vector<std::uint32_t> meeting;
        for (const auto& [f, g] : pairs) meeting.insert(meeting.end(), {f, g});
        std::size_t collapses = 0;
        for (int pass = 0; pass < PASSES && !meeting.empty(); ++pass) {
            std::sort(meeting.begin(), meeting.end());
            meeting.erase(std::unique(meeting.begin(), meeting.end()), meeting.end());
            const std::size_t collapsesBefore = collapses;
            for (const std::uint32_t h : meeting) {
                if (mRemoved[h]) continue;
                const Vec3I t = mMesh.triangles[h];
                if (mChanged[t[0]] || mChanged[t[1]] || mChanged[t[2]]) continue;
                Collapse best;
                for (const std::uint32_t u : {t[0], t[1], t[2]}) {
                    if (!mMovable[u]) continue;
                    neighbours(u, mRing);
                    for (const std::uint32_t v : mRing) {
                        if (!prepareCollapse(u, v)) continue;
                        // A collapse frees at most the pairs it removes: one that cannot free
                        // more than the best so far is not counted to the end.
                        const int before = meetingPairs(mOld, std::numeric_limits<int>::max());
                        // v where it is; if it is free, half way or where u is too.
                        const Vec3d pu = mMesh.points[u], pv = mMesh.points[v];
                        const Vec3d places[3] = {pv, (pu + pv) * 0.5, pu};
                        for (int i = 0; i < (mMovable[v] ? 3 : 1) && before > best.gain; ++i) {
                            const int after = pairsAfter(v, places[i], before - best.gain);
                            if (after >= 0 && after < before - best.gain) {
                                best = {u, v, places[i], before - after};
                            }
                        }
                    }
                }
                if (best.gain <= 0) continue;
                apply(best);
                ++collapses;
            }
            if (collapses == collapsesBefore) break;
            // The next pass: the triangles of this one and those changed that still meet one.
            findAround();
            std::fill(mChanged.begin(), mChanged.end(), 0);
            meeting.insert(meeting.end(), mCollapsed.begin(), mCollapsed.end());
            meeting.erase(std::remove_if(meeting.begin(), meeting.end(),
                                         [&](std::uint32_t h) {
                                             if (mRemoved[h]) return true;
                                             findPartners(h);
                                             return mPartners.empty();
                                         }),
                          meeting.end());
        }
        TrianglePairs stillMeeting;
        if (left) {
            for (const std::uint32_t h : meeting) {
                if (mRemoved[h]) continue;
                findPartners(h);
                for (const std::uint32_t x : mPartners) {
                    stillMeeting.emplace_back(std::min(h, x), std::max(h, x));
                }
            }
        }
        if (collapses > 0) compact(stillMeeting);
        if (left) {
            std::sort(stillMeeting.begin(), stillMeeting.end());
            stillMeeting.erase(std::unique(stillMeeting.begin(), stillMeeting.end()),
                               stillMeeting.end());
            left->swap(stillMeeting);
        }
        return collapses;
    }

private:
    /// The triangles around every point, of those not removed.
    void findAround() { trianglesAroundPoints(mMesh, mFirst, mAround, &mRemoved); }

    /// The points sharing a triangle with @a u, ascending, into @a out.
    void neighbours(std::uint32_t u, std::vector<std::uint32_t>& out) const
    {
        out.clear();
        for (std::uint32_t k = mFirst[u]; k < mFirst[u + 1]; ++k) {
            const Vec3I& t = mMesh.triangles[mAround[k]];
            for (int i = 0; i < 3; ++i) if (t[i] != u) out.push_back(t[i]);
        }
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
    }

    /// The bounding box of triangle @a t.
    Box boxOf(const Vec3I& t) const
    {
        using openvdb::math::maxComponent;
        using openvdb::math::minComponent;
        const PointArray& points = mMesh.points;
        return {minComponent(points[t[0]], minComponent(points[t[1]], points[t[2]])),
                maxComponent(points[t[0]], maxComponent(points[t[1]], points[t[2]]))};
    }

    /// How many triangles of patch @a patch are around point @a v.
    int trianglesOfPatchAt(std::uint32_t v, std::uint32_t patch) const
    {
        int count = 0;
        for (std::uint32_t k = mFirst[v]; k < mFirst[v + 1]; ++k) {
            count += mPatchOf[mAround[k]] == patch;
        }
        return count;
    }

    /// @brief Is the collapse of free point @a u into its neighbour @a v allowed (mRing: the
    /// neighbours of u)? If so, the triangles it changes, as they are and as they become
    /// (v's index for u's), into mOld and mNew, and those they can meet into mCandidates.
    bool prepareCollapse(std::uint32_t u, std::uint32_t v)
    {
        if (mChanged[u] || mChanged[v]) return false;
        const std::uint32_t patch = mPatchOf[mAround[mFirst[u]]];
        std::uint32_t across[2];
        int sides = 0;
        for (std::uint32_t k = mFirst[u]; k < mFirst[u + 1]; ++k) {
            const std::uint32_t f = mAround[k];
            if (mPatchOf[f] != patch) return false;   // not an inner point after all
            const Vec3I& t = mMesh.triangles[f];
            if (!hasCorner(t, v)) continue;
            if (sides == 2) return false;
            across[sides++] = t[0] != u && t[0] != v ? t[0] : t[1] != u && t[1] != v ? t[1] : t[2];
        }
        if (sides != 2 || across[0] == across[1]) return false;
        for (const std::uint32_t x : across) {
            if (mChanged[x] || trianglesOfPatchAt(x, patch) < (mMovable[x] ? 4 : 2)) {
                return false;
            }
        }
        // Link condition: u and v have no common neighbour in the patch but those across.
        for (std::uint32_t k = mFirst[v]; k < mFirst[v + 1]; ++k) {
            const std::uint32_t g = mAround[k];
            if (mPatchOf[g] != patch) continue;
            const Vec3I& t = mMesh.triangles[g];
            for (int i = 0; i < 3; ++i) {
                const std::uint32_t w = t[i];
                if (w == u || w == v || w == across[0] || w == across[1]) continue;
                if (std::binary_search(mRing.begin(), mRing.end(), w)) return false;
            }
        }
        if (!mMovable[v]) {
            for (const std::uint32_t w : mRing) {
                if (w != v && w != across[0] && w != across[1] && !mMovable[w]) return false;
            }
        } else if (trianglesOfPatchAt(v, patch) + (mFirst[u + 1] - mFirst[u]) - 4 < 3) {
            return false;
        }

        // The triangles around u and v change: those with both go, the others take v for u.
        mOld.clear();
        mNew.clear();
        for (const std::uint32_t w : {u, v}) {
            for (std::uint32_t k = mFirst[w]; k < mFirst[w + 1]; ++k) {
                const Vec3I& t = mMesh.triangles[mAround[k]];
                if (w == v && hasCorner(t, u)) continue;   // met around u
                mOld.push_back(t);
                if (hasCorner(t, u) && hasCorner(t, v)) continue;
                Vec3I n = t;
                for (int i = 0; i < 3; ++i) if (n[i] == u) n[i] = v;
                mNew.push_back(n);
            }
        }
        // The triangles around u hold u and all its neighbours.
        Box around = boxOf(mOld.front());
        for (const Vec3I& t : mOld) around.add(boxOf(t));
        findCandidates(around);
        mCandidates.erase(std::remove_if(mCandidates.begin(), mCandidates.end(),
                                         [&](std::uint32_t x) {
                                             const Vec3I& w = mMesh.triangles[x];
                                             return hasCorner(w, u) || hasCorner(w, v);
                                         }),
                          mCandidates.end());
        return true;
    }

    /// @brief The meeting pairs of mNew, with v at @a position, counted up to @a limit; -1 if
    /// a triangle of mNew has no area there.
    int pairsAfter(std::uint32_t v, const Vec3d& position, int limit)
    {
        PointArray& points = mMesh.points;
        const Vec3d kept = points[v];
        points[v] = position;
        bool flat = false;
        for (const Vec3I& n : mNew) {
            flat = flat || hasNoArea(toPoint(points[n[0]]), toPoint(points[n[1]]),
                                     toPoint(points[n[2]]));
        }
        const int after = flat ? -1 : meetingPairs(mNew, limit);
        points[v] = kept;
        return after;
    }

    /// @brief The meeting pairs of @a changed with each other and with mCandidates, counted
    /// up to @a limit (more are not needed).
    int meetingPairs(const std::vector<Vec3I>& changed, int limit)
    {
        const PointArray& points = mMesh.points;
        // Triangles whose boxes do not overlap cannot meet: most candidates, as cells are as
        // wide as an edge.
        mChangedBoxes.resize(changed.size());
        for (std::size_t i = 0; i < changed.size(); ++i) mChangedBoxes[i] = boxOf(changed[i]);
        int count = 0;
        for (const std::uint32_t x : mCandidates) {
            const Vec3I& w = mMesh.triangles[x];
            const Box box = boxOf(w);
            for (std::size_t i = 0; i < changed.size(); ++i) {
                if (!mChangedBoxes[i].overlaps(box)) continue;
                count += trianglesMeet(points, changed[i], w);
                if (count >= limit) return count;
            }
        }
        for (std::size_t i = 0; i < changed.size(); ++i) {
            for (std::size_t j = i + 1; j < changed.size(); ++j) {
                if (!mChangedBoxes[i].overlaps(mChangedBoxes[j])) continue;
                count += trianglesMeet(points, changed[i], changed[j]);
                if (count >= limit) return count;
            }
        }
        return count;
    }

    void apply(const Collapse& c)
    {
        if (mMesh.points[c.v] != c.position) {
            // v's triangles have new boxes too.
            for (std::uint32_t k = mFirst[c.v]; k < mFirst[c.v + 1]; ++k) {
                const std::uint32_t f = mAround[k];
                const Vec3I& t = mMesh.triangles[f];
                for (int i = 0; i < 3; ++i) mChanged[t[i]] = 1;
                if (!hasCorner(t, c.u)) mCollapsed.push_back(f);
            }
            mMesh.points[c.v] = c.position;
        }
        for (std::uint32_t k = mFirst[c.u]; k < mFirst[c.u + 1]; ++k) {
            const std::uint32_t f = mAround[k];
            Vec3I& t = mMesh.triangles[f];
            for (int i = 0; i < 3; ++i) mChanged[t[i]] = 1;
            if (hasCorner(t, c.v)) {
                mRemoved[f] = 1;
                continue;
            }
            for (int i = 0; i < 3; ++i) if (t[i] == c.u) t[i] = c.v;
            mCollapsed.push_back(f);
        }
    }

    /// @brief Every triangle not removed that can meet one within @a box into mCandidates:
    /// its box shares a cell with it, or a collapse changed it (the grid has its old box).
    void findCandidates(const Box& box)
    {
        mCandidates.assign(mCollapsed.begin(), mCollapsed.end());
        mGrid.forEachInBox(box.low, box.high, [&](std::uint32_t x) { mCandidates.push_back(x); });
        std::sort(mCandidates.begin(), mCandidates.end());
        mCandidates.erase(std::unique(mCandidates.begin(), mCandidates.end()), mCandidates.end());
        mCandidates.erase(std::remove_if(mCandidates.begin(), mCandidates.end(),
                                         [&](std::uint32_t x) { return mRemoved[x] != 0; }),
                          mCandidates.end());
    }

    /// The triangles @a h meets, into mPartners.
    void findPartners(std::uint32_t h)
    {
        const Vec3I& t = mMesh.triangles[h];
        findCandidates(boxOf(t));
        mPartners.clear();
        for (const std::uint32_t x : mCandidates) {
            if (x != h && trianglesMeet(mMesh.points, t, mMesh.triangles[x])) {
                mPartners.push_back(x);
            }
        }
    }

    /// Drops the removed triangles (keeping each patch's in order) and the points no triangle
    /// uses; renumbers @a pairs.
    void compact(TrianglePairs& pairs)
    {
        std::vector<std::uint32_t> newTriangle(mMesh.triangles.size(), 0);
        TriangleArray triangles;
        triangles.reserve(mMesh.triangles.size());
        for (InterfacePatch& patch : mMesh.patches) {
            const std::size_t first = triangles.size();
            for (std::size_t f = patch.firstTriangle;
                 f < patch.firstTriangle + patch.triangleCount; ++f) {
                if (mRemoved[f]) continue;
                newTriangle[f] = std::uint32_t(triangles.size());
                triangles.push_back(mMesh.triangles[f]);
            }
            patch.firstTriangle = first;
            patch.triangleCount = triangles.size() - first;
        }
        std::vector<std::uint32_t> newPoint(mMesh.points.size(), 0);
        std::vector<char> used(mMesh.points.size(), 0);
        for (const Vec3I& t : triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
        std::uint32_t kept = 0;
        const bool keys = mMesh.pointKeys.size() == mMesh.points.size();
        for (std::size_t v = 0; v < mMesh.points.size(); ++v) {
            if (!used[v]) continue;
            newPoint[v] = kept;
            mMesh.points[kept] = mMesh.points[v];
            if (keys) mMesh.pointKeys[kept] = mMesh.pointKeys[v];
            ++kept;
        }
        mMesh.points.resize(kept);
        if (keys) mMesh.pointKeys.resize(kept);
        for (Vec3I& t : triangles) {
            for (int i = 0; i < 3; ++i) t[i] = newPoint[t[i]];
        }
        mMesh.triangles.swap(triangles);
        for (auto& [f, g] : pairs) {
            f = newTriangle[f];
            g = newTriangle[g];
            if (g < f) std::swap(f, g);
        }
    }

    /// Passes over the meeting triangles: a collapse lets the triangles around its corners
    /// wait for the next.
    static constexpr int PASSES = 8;

    InterfaceMesh& mMesh;
    const std::vector<std::uint8_t>& mMovable;
    const CandidateGrid mGrid;
    std::vector<std::uint32_t> mPatchOf;
    std::vector<char> mRemoved;   ///< per triangle
    /// Triangles around every point (as at the start of the pass, removed ones left out):
    /// mAround[mFirst[v] .. mFirst[v + 1]).
    std::vector<std::uint32_t> mFirst, mAround;
    /// Points at a corner of a collapse this pass: their triangles are no longer mAround's.
    std::vector<char> mChanged;
    /// Triangles a collapse changed (their boxes are no longer the grid's).
    std::vector<std::uint32_t> mCollapsed;
    /// Scratch: the neighbours of the point being collapsed, the candidates, the partners.
    std::vector<std::uint32_t> mRing, mCandidates, mPartners;
    std::vector<Vec3I> mOld, mNew;
    std::vector<Box> mChangedBoxes;   ///< scratch of meetingPairs()
};

} // namespace


std::size_t
collapseMeetingEdges(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                     double cellSize, bool threaded, const TrianglePairs& pairs,
                     TrianglePairs* left)
{
    if (pairs.empty()) {
        if (left) left->clear();
        return 0;
    }
    return EdgeCollapser(mesh, movable, cellSize, threaded).run(pairs, left);
}

} // namespace vdbi
