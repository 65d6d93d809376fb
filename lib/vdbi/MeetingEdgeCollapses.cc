// SPDX-License-Identifier: Apache-2.0

#include <vdbi/MeetingEdgeCollapses.h>

#include <vdbi/FanShape.h>
#include <vdbi/TriangleCrossing.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <unordered_map>

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
        : mMesh(mesh), mMovable(movable), mInverseCell(1.0 / cellSize)
        , mGrid(mesh, cellSize, 0.0, threaded)
        , mPatchOf(trianglePatches(mesh)), mRemoved(mesh.triangles.size(), 0)
        , mChanged(mesh.points.size(), 0)
    {
        findAround();
    }

    /// @param shortEdges  if given, collapseShort() with it after the meeting triangles
    std::size_t run(const TrianglePairs& pairs, TrianglePairs* left,
                    const ShortEdgeCollapseSettings* shortEdges)
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
        if (shortEdges) collapses += collapseShort(*shortEdges);
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
    /// @brief Passes over the edges shorter than settings.shortLength, shortest first, each
    /// collapsed the best way collapseShortEdge() allows; a pass after the first looks at the
    /// edges around the points the one before changed.
    std::size_t collapseShort(const ShortEdgeCollapseSettings& settings)
    {
        mShort = &settings;
        std::size_t collapses = 0;
        std::vector<std::uint32_t> changedPoints;
        for (int pass = 0; pass < PASSES; ++pass) {
            findAround();
            std::fill(mChanged.begin(), mChanged.end(), 0);
            findShortEdges(pass == 0, changedPoints, settings.shortLength);
            const std::size_t before = collapses;
            for (const auto& [length2, a, b] : mShortEdges) {
                if (!mChanged[a] && !mChanged[b] && collapseShortEdge(a, b, settings)) {
                    ++collapses;
                }
            }
            if (collapses == before) break;
            changedPoints.clear();
            for (std::uint32_t v = 0; v < mChanged.size(); ++v) {
                if (mChanged[v]) changedPoints.push_back(v);
            }
        }
        mShort = nullptr;
        return collapses;
    }

    /// @brief mShortEdges: the edges shorter than @a length with a free end, of all
    /// triangles or of those around @a points, shortest first.
    void findShortEdges(bool all, const std::vector<std::uint32_t>& points, double length)
    {
        mShortEdges.clear();
        auto addEdges = [&](std::uint32_t f) {
            const Vec3I& t = mMesh.triangles[f];
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = std::min(t[k], t[(k + 1) % 3]);
                const std::uint32_t b = std::max(t[k], t[(k + 1) % 3]);
                if (!mMovable[a] && !mMovable[b]) continue;
                const double length2 = (mMesh.points[a] - mMesh.points[b]).lengthSqr();
                if (length2 < length * length) mShortEdges.emplace_back(length2, a, b);
            }
        };
        if (all) {
            for (std::uint32_t f = 0; f < mMesh.triangles.size(); ++f) {
                if (!mRemoved[f]) addEdges(f);
            }
        } else {
            for (const std::uint32_t v : points) {
                for (std::uint32_t k = mFirst[v]; k < mFirst[v + 1]; ++k) addEdges(mAround[k]);
            }
        }
        std::sort(mShortEdges.begin(), mShortEdges.end());
        mShortEdges.erase(std::unique(mShortEdges.begin(), mShortEdges.end()), mShortEdges.end());
    }

    /// @brief Collapses edge (@a a, @a b) the best way allowed, if any; true if it did.
    /// @details Each free end u may go into the other, v, which stays, or, if free too, moves
    /// to the midpoint or to u. Allowed as prepareCollapse() allows (a new inner edge may join
    /// two fixed points where settings.mayJoinFixed does), and if no new edge is longer than
    /// settings.longLength, no triangle turns over, the triangles around u and v meet no
    /// other before and after, the fan has no more sharp triangles and no smaller smallest
    /// angle (unless that stays above SHARP_TRIANGLE_DEGREES), and keepsSourceClose(). Of
    /// the allowed, the best fan (FanShape) of the first WAYS_TRIED the cheap tests allow.
    bool collapseShortEdge(std::uint32_t a, std::uint32_t b,
                           const ShortEdgeCollapseSettings& settings)
    {
        static const double sharpCos = std::cos(SHARP_TRIANGLE_DEGREES * M_PI / 180.0);
        const double long2 = settings.longLength * settings.longLength;
        // The ways the cheap tests allow, then the dear ones on them, best fan first.
        mWays.clear();
        for (const auto& [u, v] : {std::make_pair(a, b), std::make_pair(b, a)}) {
            if (!mMovable[u]) continue;
            neighbours(u, mRing);
            if (!prepareCollapse(u, v) || meetingPairs(mOld, 1) > 0) continue;
            const FanShape old = shapeOf(mOld);
            const double allowedCos = std::max(old.smallestCos, sharpCos);
            neighbours(v, mRingOfV);
            const Vec3d pu = mMesh.points[u], pv = mMesh.points[v];
            const Vec3d places[3] = {pv, (pu + pv) * 0.5, pu};
            for (int i = 0; i < (mMovable[v] ? 3 : 1); ++i) {
                const Vec3d& p = places[i];
                bool tooLong = false;
                for (const auto* ring : {&mRing, &mRingOfV}) {
                    for (const std::uint32_t w : *ring) {
                        tooLong = tooLong
                            || (w != u && w != v && (mMesh.points[w] - p).lengthSqr() > long2);
                    }
                }
                if (tooLong) continue;
                mMesh.points[v] = p;
                const FanShape now = shapeOf(mNew);
                bool turned = false;
                for (std::size_t k = 0; k < mNew.size(); ++k) {
                    turned = turned || !(normalOf(mNew[k]).dot(mNewBefore[k]) > 0.0);
                }
                mMesh.points[v] = pv;
                if (turned || now.sharp > old.sharp || now.smallestCos > allowedCos) continue;
                mWays.push_back({now, {u, v, p, 0}});
            }
        }
        std::stable_sort(mWays.begin(), mWays.end(),
                         [](const Way& x, const Way& y) { return x.shape < y.shape; });
        for (std::size_t k = 0; k < mWays.size() && k < WAYS_TRIED; ++k) {
            const Collapse& c = mWays[k].collapse;
            neighbours(c.u, mRing);
            prepareCollapse(c.u, c.v);
            if (pairsAfter(c.v, c.position, 1) != 0) continue;
            if (settings.source && !keepsSourceClose(c.u, c.v, c.position, settings)) continue;
            apply(c);
            return true;
        }
        return false;
    }

    /// The shape of @a triangles together, as FanShape counts it.
    FanShape shapeOf(const std::vector<Vec3I>& triangles) const
    {
        FanShape shape;
        const PointArray& p = mMesh.points;
        for (const Vec3I& t : triangles) shape.add(smallestAngleCosOf(p[t[0]], p[t[1]], p[t[2]]));
        return shape;
    }

    Vec3d normalOf(const Vec3I& t) const
    {
        const PointArray& p = mMesh.points;
        return (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]);
    }

    /// @brief With v at @a p instead of u (mOld -> mNew): is @a p within settings.sourceLimit
    /// of the patch's source if v moves, and does RawPatchDistance::keepsCovered() hold for
    /// the patch's changed triangles?
    bool keepsSourceClose(std::uint32_t u, std::uint32_t v, const Vec3d& p,
                          const ShortEdgeCollapseSettings& settings)
    {
        RawPatchDistance& source = *settings.source;
        const double limit = settings.sourceLimit;
        const std::uint32_t patch = mPatchOf[mAround[mFirst[u]]];
        mPatches.assign(1, patch);
        const Vec3d pv = mMesh.points[v];
        if (p != pv && source.farthest(p, mPatches).distance > limit) return false;
        mThen.clear();
        mNow.clear();
        for (std::size_t k = 0; k < mOld.size(); ++k) {
            if (mOldPatch[k] == patch) mThen.push_back(source.corners(mMesh.points, mOld[k]));
        }
        mMesh.points[v] = p;
        for (std::size_t k = 0; k < mNew.size(); ++k) {
            if (mNewPatch[k] == patch) mNow.push_back(source.corners(mMesh.points, mNew[k]));
        }
        mMesh.points[v] = pv;
        auto coveredElsewhere = [&](const Vec3d& q) {
            bool covered = false;
            const Box box{source.world(q - Vec3d(limit)), source.world(q + Vec3d(limit))};
            forEachNear(box, [&](std::uint32_t g) {
                const Vec3I& t = mMesh.triangles[g];
                covered = covered
                    || (!mRemoved[g] && mPatchOf[g] == patch && !hasCorner(t, u)
                        && !hasCorner(t, v)
                        && RawPatchDistance::isWithin(q, source.corners(mMesh.points, t), limit));
            });
            return covered;
        };
        return source.keepsCovered(patch, mThen, mNow, limit, coveredElsewhere);
    }

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
                if (w == v || w == across[0] || w == across[1] || mMovable[w]) continue;
                if (!mShort || !mShort->mayJoinFixed(patch, v, w)) return false;
            }
        } else if (trianglesOfPatchAt(v, patch) + (mFirst[u + 1] - mFirst[u]) - 4 < 3) {
            return false;
        }

        // The triangles around u and v change: those with both go, the others take v for u.
        mOld.clear();
        mNew.clear();
        mOldPatch.clear();
        mNewPatch.clear();
        mNewBefore.clear();
        for (const std::uint32_t w : {u, v}) {
            for (std::uint32_t k = mFirst[w]; k < mFirst[w + 1]; ++k) {
                const Vec3I& t = mMesh.triangles[mAround[k]];
                if (w == v && hasCorner(t, u)) continue;   // met around u
                mOld.push_back(t);
                mOldPatch.push_back(mPatchOf[mAround[k]]);
                if (hasCorner(t, u) && hasCorner(t, v)) continue;
                Vec3I n = t;
                for (int i = 0; i < 3; ++i) if (n[i] == u) n[i] = v;
                mNew.push_back(n);
                mNewPatch.push_back(mPatchOf[mAround[k]]);
                mNewBefore.push_back(normalOf(t));
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
        const std::size_t changedBefore = mCollapsed.size();
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
        for (std::size_t i = changedBefore; i < mCollapsed.size(); ++i) {
            const std::uint32_t f = mCollapsed[i];
            forEachCellKey(boxOf(mMesh.triangles[f]),
                           [&](std::uint64_t key) { mChangedCells[key].push_back(f); });
        }
    }

    /// Calls @a body(key) for the key of every grid cell @a box overlaps.
    template<typename Body>
    void forEachCellKey(const Box& box, const Body& body) const
    {
        const openvdb::Vec3i lo = cellOf(box.low, mInverseCell);
        const openvdb::Vec3i hi = cellOf(box.high, mInverseCell);
        for (int x = lo[0]; x <= hi[0]; ++x) {
            for (int y = lo[1]; y <= hi[1]; ++y) {
                for (int z = lo[2]; z <= hi[2]; ++z) body(cellKey(openvdb::Vec3i(x, y, z)));
            }
        }
    }

    /// @brief Calls @a body(g) for every triangle g whose box, as the grid has it or as a
    /// collapse made it, shares a cell with @a box (some more than once; removed ones too).
    template<typename Body>
    void forEachNear(const Box& box, const Body& body) const
    {
        mGrid.forEachInBox(box.low, box.high, body);
        if (mChangedCells.empty()) return;
        forEachCellKey(box, [&](std::uint64_t key) {
            const auto cell = mChangedCells.find(key);
            if (cell == mChangedCells.end()) return;
            for (const std::uint32_t g : cell->second) body(g);
        });
    }

    /// @brief Every triangle not removed that can meet one within @a box into mCandidates:
    /// its box, as it is, shares a cell with it.
    void findCandidates(const Box& box)
    {
        mCandidates.clear();
        forEachNear(box, [&](std::uint32_t x) { mCandidates.push_back(x); });
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
    /// @brief Of the ways to collapse a short edge that the cheap tests allow, the dear tests
    /// (meeting pairs, closeness) look at the best this many.
    /// @details Where a coarse target meets fine features, many short edges fail the dear
    /// tests every way (menger and the frog at 4 voxels: 122 k and 40 k short edges).
    static constexpr std::size_t WAYS_TRIED = 2;

    InterfaceMesh& mMesh;
    const std::vector<std::uint8_t>& mMovable;
    const double mInverseCell;   ///< of the grid's cells
    const CandidateGrid mGrid;
    /// The settings of collapseShort() while it runs: prepareCollapse() may then join fixed
    /// points where they allow.
    const ShortEdgeCollapseSettings* mShort = nullptr;
    std::vector<std::uint32_t> mPatchOf;
    std::vector<char> mRemoved;   ///< per triangle
    /// Triangles around every point (as at the start of the pass, removed ones left out):
    /// mAround[mFirst[v] .. mFirst[v + 1]).
    std::vector<std::uint32_t> mFirst, mAround;
    /// Points at a corner of a collapse this pass: their triangles are no longer mAround's.
    std::vector<char> mChanged;
    /// Triangles a collapse changed (their boxes are no longer the grid's), also by the cells
    /// of their new boxes.
    std::vector<std::uint32_t> mCollapsed;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> mChangedCells;
    /// Scratch: the neighbours of the point being collapsed, the candidates, the partners.
    std::vector<std::uint32_t> mRing, mCandidates, mPartners;
    std::vector<Vec3I> mOld, mNew;
    std::vector<Box> mChangedBoxes;   ///< scratch of meetingPairs()
    /// Scratch of collapseShort(): the short edges (squared length, ends), the neighbours of
    /// v, the patches of mOld's and mNew's triangles and the normals of mNew's before, the
    /// corners and patch for keepsCovered().
    std::vector<std::tuple<double, std::uint32_t, std::uint32_t>> mShortEdges;
    /// A collapse the cheap tests of collapseShortEdge() allow, and the fan it leaves.
    struct Way
    {
        FanShape shape;
        Collapse collapse;
    };
    std::vector<Way> mWays;
    std::vector<std::uint32_t> mRingOfV, mOldPatch, mNewPatch, mPatches;
    std::vector<Vec3d> mNewBefore;
    std::vector<RawPatchDistance::Corners> mThen, mNow;
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
    return EdgeCollapser(mesh, movable, cellSize, threaded).run(pairs, left, nullptr);
}


std::size_t
collapseMeetingAndShortEdges(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                             const ShortEdgeCollapseSettings& settings,
                             const TrianglePairs& pairs)
{
    return EdgeCollapser(mesh, movable, settings.cellSize, settings.threaded)
        .run(pairs, nullptr, &settings);
}

} // namespace vdbi
