// SPDX-License-Identifier: Apache-2.0

#include <vdbi/GuardedMoves.h>

#include <vdbi/TriangleCrossing.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vdbi {

void
patchesOf(const std::uint32_t* first, const std::uint32_t* last,
          const std::vector<std::uint32_t>& patchOf, std::vector<std::uint32_t>& patches)
{
    patches.clear();
    for (const std::uint32_t* i = first; i != last; ++i) patches.push_back(patchOf[*i]);
    std::sort(patches.begin(), patches.end());
    patches.erase(std::unique(patches.begin(), patches.end()), patches.end());
}


void
patchesAround(std::uint32_t v, const std::vector<std::uint32_t>& first,
              const std::vector<std::uint32_t>& around, const std::vector<std::uint32_t>& patchOf,
              std::vector<std::uint32_t>& patches)
{
    patchesOf(around.data() + first[v], around.data() + first[v + 1], patchOf, patches);
}


GuardedMoves::GuardedMoves(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                           const SeparationSettings& settings, const PointArray* start)
    : mMesh(mesh), mMovable(movable), mSettings(settings)
    , mOwnOrigin(start ? PointArray() : mesh.points)
    , mOrigin(start ? *start : mOwnOrigin)
    , mPatchOf(trianglePatches(mesh))
    , mGrid(mesh, settings.cellSize, settings.maxMove, settings.threaded)
{
    trianglesAroundPoints(mesh, mStart, mAround);
    if (settings.source) {
        mStartDistance.assign(mesh.points.size(), std::numeric_limits<double>::quiet_NaN());
    }
}


bool
GuardedMoves::moveTo(std::uint32_t v, const Vec3d& next, const Vec3d& normal, std::size_t limit)
{
    if (!withinReach(v, next)) return false;
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
    mMovedFrom.assign(1, {v, old});
    if (turned || (limit < mMeetingHere.size() && !freesAPair())
        || meetingsAround(v) > limit
        || !keepsSourceCovered(mAround.data() + mStart[v], mAround.data() + mStart[v + 1])) {
        mMesh.points[v] = old;
        return false;
    }
    return true;
}


std::size_t
GuardedMoves::meetingsAround(std::uint32_t v, Pairs* pairs) const
{
    return meetingsAmong(mAround.data() + mStart[v], mAround.data() + mStart[v + 1], pairs);
}


std::size_t
GuardedMoves::meetingsAmong(const std::uint32_t* first, const std::uint32_t* last,
                            Pairs* pairs) const
{
    if (pairs) pairs->clear();
    std::size_t count = 0;
    for (const std::uint32_t* i = first; i != last; ++i) {
        const std::uint32_t f = *i;
        mGrid.forEachNeighbour(f, [&](std::uint32_t g) {
            // A pair of two of the triangles is counted from the smaller one.
            if (g < f && std::find(first, last, g) != last) return;
            if (!trianglesMeet(mMesh.points, mMesh.triangles[f], mMesh.triangles[g])) return;
            ++count;
            if (pairs) pairs->emplace_back(f, g);
        });
    }
    return count;
}


bool
GuardedMoves::freesAPair() const
{
    for (const auto& [f, g] : mMeetingHere) {
        if (!trianglesMeet(mMesh.points, mMesh.triangles[f], mMesh.triangles[g])) return true;
    }
    return false;
}


bool
GuardedMoves::withinReach(std::uint32_t v, const Vec3d& p)
{
    const double moved = (p - mOrigin[v]).length();
    return moved <= mSettings.maxMove && keepsClose(v, p, moved);
}


bool
GuardedMoves::keepsClose(std::uint32_t v, const Vec3d& p, double moved)
{
    if (!mSettings.source) return true;
    collectPatchesAround(v);
    double& atStart = mStartDistance[v];
    if (std::isnan(atStart)) {
        atStart = mSettings.source->farthest(mOrigin[v], mPatchesHere).distance;
    }
    const double allowed = std::max(mSettings.sourceLimit, atStart);
    if (atStart + moved / mSettings.sourceUnit <= allowed) return true;
    return mSettings.source->farthest(p, mPatchesHere).distance <= allowed;
}


bool
GuardedMoves::keepsSourceCovered(const std::uint32_t* first, const std::uint32_t* last)
{
    RawPatchDistance* source = mSettings.source;
    if (!source) return true;
    patchesOf(first, last, mPatchOf, mPatchesMoved);
    const double limit = mSettings.sourceLimit;
    for (const std::uint32_t patch : mPatchesMoved) {
        mNow.clear();
        mThen.clear();
        for (const std::uint32_t* i = first; i != last; ++i) {
            if (mPatchOf[*i] != patch) continue;
            const openvdb::Vec3I& t = mMesh.triangles[*i];
            mNow.push_back(source->corners(mMesh.points, t));
            RawPatchDistance::Corners& then = mThen.emplace_back(mNow.back());
            for (int k = 0; k < 3; ++k) {
                for (const auto& [w, q] : mMovedFrom) {
                    if (w == t[k]) then.c[k] = source->scaled(q);
                }
            }
        }
        // Every triangle within the limit of q has its box (the grid's, widened by
        // maxMove) in the cells of q's box.
        auto coveredElsewhere = [&](const Vec3d& q) {
            bool covered = false;
            mGrid.forEachInBox(source->world(q - Vec3d(limit)),
                               source->world(q + Vec3d(limit)), [&](std::uint32_t g) {
                covered = covered
                    || (mPatchOf[g] == patch
                        && RawPatchDistance::isWithin(
                            q, source->corners(mMesh.points, mMesh.triangles[g]), limit));
            });
            return covered;
        };
        if (!source->keepsCovered(patch, mThen, mNow, limit, coveredElsewhere)) return false;
    }
    return true;
}


void
GuardedMoves::collectPatchesAround(std::uint32_t v)
{
    patchesAround(v, mStart, mAround, mPatchOf, mPatchesHere);
}


GuardedMoves::Vec3d
GuardedMoves::faceNormal(std::uint32_t f) const
{
    const openvdb::Vec3I& t = mMesh.triangles[f];
    const PointArray& points = mMesh.points;
    return (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]);
}


GuardedMoves::Vec3d
GuardedMoves::vertexNormal(std::uint32_t v) const
{
    Vec3d normal(0.0);
    for (std::uint32_t i = mStart[v]; i < mStart[v + 1]; ++i) {
        normal += faceNormal(mAround[i]);
    }
    return normal;
}



GuardedMoves::Vec3d
GuardedMoves::towardsNeighbours(std::uint32_t v) const
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


FanShape
GuardedMoves::fanShape(std::uint32_t v) const
{
    FanShape shape;
    for (std::uint32_t i = mStart[v]; i < mStart[v + 1]; ++i) {
        const openvdb::Vec3I& t = mMesh.triangles[mAround[i]];
        const PointArray& p = mMesh.points;
        shape.add(smallestAngleCosOf(p[t[0]], p[t[1]], p[t[2]]));
    }
    return shape;
}

} // namespace vdbi
