// SPDX-License-Identifier: Apache-2.0

#include <vdbi/MeetingEdgeFlips.h>

#include <vdbi/CandidateGrid.h>
#include <vdbi/TriangleCrossing.h>

#include <algorithm>
#include <initializer_list>

namespace vdbi {

namespace {

using Vec3d = openvdb::Vec3d;
using Vec3I = openvdb::Vec3I;

Vec3d
normalOf(const PointArray& points, const Vec3I& t)
{
    return (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]);
}

bool
hasCorner(const Vec3I& t, std::uint32_t v)
{
    return t[0] == v || t[1] == v || t[2] == v;
}

/// Has triangle @a t no area to speak of (hasNoArea())?
bool
triangleHasNoArea(const PointArray& points, const Vec3I& t)
{
    return hasNoArea(toPoint(points[t[0]]), toPoint(points[t[1]]), toPoint(points[t[2]]));
}

/// The flip of one edge: triangles f = (a, b, c) and g = (b, a, d) become (a, d, c) and
/// (d, b, c).
struct Flip
{
    std::uint32_t f = 0, g = 0;
    Vec3I newF, newG;
    int gain = 0;   ///< meeting pairs freed
};

class EdgeFlipper
{
public:
    EdgeFlipper(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable, double cellSize,
                bool threaded, RawPatchDistance* source, double sourceLimit)
        : mMesh(mesh), mMovable(movable), mSource(source), mSourceLimit(sourceLimit)
        , mGrid(mesh, cellSize, 0.0, threaded)
        , mPatchOf(trianglePatches(mesh)), mChanged(mesh.points.size(), 0)
    {
        trianglesAroundPoints(mesh, mFirst, mAround);
    }

    std::size_t run(const std::vector<std::uint32_t>& suspects, TrianglePairs* left)
    {
        std::vector<std::uint32_t> meeting;
        for (const std::uint32_t v : suspects) {
            for (std::uint32_t k = mFirst[v]; k < mFirst[v + 1]; ++k) {
                addMeeting(mAround[k], meeting);
            }
        }
        std::size_t flips = 0;
        for (int pass = 0; pass < PASSES && !meeting.empty(); ++pass) {
            std::sort(meeting.begin(), meeting.end());
            meeting.erase(std::unique(meeting.begin(), meeting.end()), meeting.end());
            const std::size_t flipsBefore = flips;
            for (const std::uint32_t h : meeting) {
                const Vec3I t = mMesh.triangles[h];
                if (mChanged[t[0]] || mChanged[t[1]] || mChanged[t[2]]) continue;
                Flip best;
                for (int i = 0; i < 3; ++i) {
                    Flip flip;
                    if (makeFlip(h, i, flip) && flip.gain > best.gain) best = flip;
                }
                if (best.gain <= 0) continue;
                for (const std::uint32_t f : {best.f, best.g}) {
                    for (int k = 0; k < 3; ++k) mChanged[mMesh.triangles[f][k]] = 1;
                    mFlipped.push_back(f);
                }
                mMesh.triangles[best.f] = best.newF;
                mMesh.triangles[best.g] = best.newG;
                ++flips;
            }
            if (flips == flipsBefore) break;
            // The next pass: the triangles of this one and those flipped that still meet one.
            trianglesAroundPoints(mMesh, mFirst, mAround);
            std::fill(mChanged.begin(), mChanged.end(), 0);
            meeting.insert(meeting.end(), mFlipped.begin(), mFlipped.end());
            meeting.erase(std::remove_if(meeting.begin(), meeting.end(),
                                         [&](std::uint32_t h) { return !meetsAny(h); }),
                          meeting.end());
        }
        if (left) {
            // Every triangle still meeting one is in the list: those of the last pass that
            // still meet, and those of the pass before if the last flipped none.
            left->clear();
            for (const std::uint32_t h : meeting) {
                findPartners(h);
                for (const std::uint32_t x : mPartners) {
                    left->emplace_back(std::min(h, x), std::max(h, x));
                }
            }
            std::sort(left->begin(), left->end());
            left->erase(std::unique(left->begin(), left->end()), left->end());
        }
        return flips;
    }

private:
    /// The flip of edge (t[i], t[i + 1]) of triangle @a f, if it is allowed.
    bool makeFlip(std::uint32_t f, int i, Flip& flip)
    {
        const Vec3I& t = mMesh.triangles[f];
        const std::uint32_t a = t[i], b = t[(i + 1) % 3], c = t[(i + 2) % 3];
        const std::int64_t other = triangleAcross(mMesh, mFirst, mAround, mPatchOf, f, a, b);
        if (other < 0) return false;
        const std::uint32_t g = std::uint32_t(other);
        const Vec3I& u = mMesh.triangles[g];
        const std::uint32_t d = u[0] != a && u[0] != b ? u[0] : u[1] != a && u[1] != b ? u[1] : u[2];
        if (mChanged[d] || (!mMovable[c] && !mMovable[d])) return false;
        for (std::uint32_t k = mFirst[c]; k < mFirst[c + 1]; ++k) {
            if (hasCorner(mMesh.triangles[mAround[k]], d)) return false;   // an edge already
        }
        flip.f = f;
        flip.g = g;
        flip.newF = Vec3I(a, d, c);
        flip.newG = Vec3I(d, b, c);
        const PointArray& points = mMesh.points;
        if (triangleHasNoArea(points, flip.newF) || triangleHasNoArea(points, flip.newG)) {
            return false;
        }
        const Vec3d facing = normalOf(points, t) + normalOf(points, u);
        if (!(normalOf(points, flip.newF).dot(facing) > 0.0)
            || !(normalOf(points, flip.newG).dot(facing) > 0.0)) {
            return false;
        }

        findCandidates({a, b, c, d});
        int before = trianglesMeet(points, t, u), after = trianglesMeet(points, flip.newF, flip.newG);
        for (const std::uint32_t x : mCandidates) {
            if (x == f || x == g) continue;
            const Vec3I& w = mMesh.triangles[x];
            before += int(trianglesMeet(points, t, w)) + int(trianglesMeet(points, u, w));
            after += int(trianglesMeet(points, flip.newF, w)) + int(trianglesMeet(points, flip.newG, w));
        }
        flip.gain = before - after;
        return flip.gain <= 0 || keepsSourceCovered(flip);
    }

    /// Does @a flip keep the face centres and centroids of the source near it within the limit?
    bool keepsSourceCovered(const Flip& flip)
    {
        if (!mSource) return true;
        const PointArray& points = mMesh.points;
        const std::vector<RawPatchDistance::Corners> before = {
            mSource->corners(points, mMesh.triangles[flip.f]),
            mSource->corners(points, mMesh.triangles[flip.g])},
            now = {mSource->corners(points, flip.newF), mSource->corners(points, flip.newG)};
        const std::uint32_t patch = mPatchOf[flip.f];
        const double limit = mSourceLimit;
        auto coveredElsewhere = [&](const Vec3d& q) {
            const Vec3d low = mSource->world(q - Vec3d(limit)),
                        high = mSource->world(q + Vec3d(limit));
            mCandidates.assign(mFlipped.begin(), mFlipped.end());
            mGrid.forEachInBox(low, high, [&](std::uint32_t x) { mCandidates.push_back(x); });
            for (const std::uint32_t x : mCandidates) {
                if (x != flip.f && x != flip.g && mPatchOf[x] == patch
                    && RawPatchDistance::isWithin(q, mSource->corners(points, mMesh.triangles[x]),
                                                  limit)) {
                    return true;
                }
            }
            return false;
        };
        return mSource->keepsCovered(patch, before, now, limit, coveredElsewhere);
    }

    /// @brief Every triangle that can meet one with the corners @a corners into mCandidates:
    /// its box shares a cell with theirs, or a flip changed it (the grid has its old box).
    void findCandidates(std::initializer_list<std::uint32_t> corners)
    {
        const PointArray& points = mMesh.points;
        Vec3d low = points[*corners.begin()], high = low;
        for (const std::uint32_t v : corners) {
            low = openvdb::math::minComponent(low, points[v]);
            high = openvdb::math::maxComponent(high, points[v]);
        }
        mCandidates.assign(mFlipped.begin(), mFlipped.end());
        mGrid.forEachInBox(low, high, [&](std::uint32_t x) { mCandidates.push_back(x); });
        std::sort(mCandidates.begin(), mCandidates.end());
        mCandidates.erase(std::unique(mCandidates.begin(), mCandidates.end()), mCandidates.end());
    }

    /// The triangles @a h meets, into mPartners.
    void findPartners(std::uint32_t h)
    {
        const Vec3I& t = mMesh.triangles[h];
        findCandidates({t[0], t[1], t[2]});
        mPartners.clear();
        for (const std::uint32_t x : mCandidates) {
            if (x != h && trianglesMeet(mMesh.points, t, mMesh.triangles[x])) {
                mPartners.push_back(x);
            }
        }
    }

    /// Appends @a h and every triangle it meets to @a meeting if it meets any.
    void addMeeting(std::uint32_t h, std::vector<std::uint32_t>& meeting)
    {
        findPartners(h);
        if (mPartners.empty()) return;
        meeting.insert(meeting.end(), mPartners.begin(), mPartners.end());
        meeting.push_back(h);
    }

    /// Does triangle @a h meet any other?
    bool meetsAny(std::uint32_t h)
    {
        findPartners(h);
        return !mPartners.empty();
    }

    /// Passes over the meeting triangles: a flip lets the triangles around its corners wait
    /// for the next (frog at 2 voxels: 29, 7, 3, 1 flips).
    static constexpr int PASSES = 8;

    InterfaceMesh& mMesh;
    const std::vector<std::uint8_t>& mMovable;
    RawPatchDistance* const mSource;
    const double mSourceLimit;
    const CandidateGrid mGrid;
    std::vector<std::uint32_t> mPatchOf;
    /// Triangles around every point (as before any flip): mAround[mFirst[v] .. mFirst[v + 1]).
    std::vector<std::uint32_t> mFirst, mAround;
    /// Points at a corner of a flipped pair: their triangles are no longer mAround's.
    std::vector<char> mChanged;
    std::vector<std::uint32_t> mFlipped, mCandidates, mPartners;
};

} // namespace


std::size_t
flipMeetingEdges(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable, double cellSize,
                 bool threaded, const std::vector<std::uint32_t>& suspects,
                 TrianglePairs* left, RawPatchDistance* source, double sourceLimit)
{
    return EdgeFlipper(mesh, movable, cellSize, threaded, source, sourceLimit)
        .run(suspects, left);
}

} // namespace vdbi
