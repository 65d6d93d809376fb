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


GuardedMoves::State::State(InterfaceMesh& mesh, const SeparationSettings& settings,
                           const PointArray* start)
    : ownOrigin(start ? PointArray() : mesh.points)
    , origin(start ? *start : ownOrigin)
    , patchOf(trianglePatches(mesh))
    , grid(mesh, settings.cellSize, settings.maxMove, settings.threaded)
{
    trianglesAroundPoints(mesh, this->start, around);
    if (settings.source) {
        startDistance.assign(mesh.points.size(), std::numeric_limits<double>::quiet_NaN());
    }
}


GuardedMoves::GuardedMoves(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                           const SeparationSettings& settings, const PointArray* start)
    : mMesh(mesh), mMovable(movable), mSettings(settings)
    , mState(std::make_shared<State>(mesh, settings, start))
    , mOrigin(mState->origin), mPatchOf(mState->patchOf), mGrid(mState->grid)
    , mStart(mState->start), mAround(mState->around), mStartDistance(mState->startDistance)
{
}


GuardedMoves::GuardedMoves(const GuardedMoves& other)
    : mMesh(other.mMesh), mMovable(other.mMovable), mSettings(other.mSettings)
    , mState(other.mState)
    , mOrigin(mState->origin), mPatchOf(mState->patchOf), mGrid(mState->grid)
    , mStart(mState->start), mAround(mState->around), mStartDistance(mState->startDistance)
{
}


GuardedMoves::IndependentBlocks
GuardedMoves::independentBlocks(const std::vector<std::uint32_t>& points) const
{
    using openvdb::Vec3i;
    // The first cell of every point's fan, and the widest fan.
    std::vector<std::pair<std::uint32_t, Vec3i>> firstCells;
    Vec3i widest(0);
    for (const std::uint32_t v : points) {
        if (!mMovable[v] || mStart[v] == mStart[v + 1]) continue;
        Vec3i low(std::numeric_limits<int>::max()), high(std::numeric_limits<int>::min());
        for (std::uint32_t i = mStart[v]; i < mStart[v + 1]; ++i) {
            Vec3i lo, hi;
            mGrid.cellRange(mAround[i], lo, hi);
            low = openvdb::math::minComponent(low, lo);
            high = openvdb::math::maxComponent(high, hi);
        }
        widest = openvdb::math::maxComponent(widest, high - low);
        firstCells.emplace_back(v, low);
    }
    // Beyond a fan's cells, the guards look for triangles within the source limit of points
    // within it of the fan: twice the limit farther, in world units.
    int reach = 1;
    if (mSettings.source) {
        const Vec3d voxel = mSettings.source->world(Vec3d(1.0));
        const double world = 2.0 * mSettings.sourceLimit * std::max({voxel[0], voxel[1], voxel[2]});
        reach += int(std::ceil(world / mGrid.cellWidth()));
    }
    // A block of a colour starts over a block's width past the end of another's last fan.
    const Vec3i width = widest + Vec3i(reach + 1);
    struct Entry
    {
        int colour;
        Vec3i block;
        std::uint32_t point;
    };
    std::vector<Entry> entries;
    entries.reserve(firstCells.size());
    for (const auto& [v, low] : firstCells) {
        Vec3i b;
        for (int k = 0; k < 3; ++k) {
            b[k] = low[k] >= 0 ? low[k] / width[k] : -((-low[k] - 1) / width[k]) - 1;
        }
        entries.push_back({(b[0] & 1) | (b[1] & 1) << 1 | (b[2] & 1) << 2, b, v});
    }
    // By colour, block, point.
    std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
        if (x.colour != y.colour) return x.colour < y.colour;
        if (x.block != y.block) return x.block < y.block;
        return x.point < y.point;
    });
    IndependentBlocks blocks;
    blocks.colourStart.assign(1, 0);
    for (std::size_t i = 0; i < entries.size(); ++i) {
        if (i == 0 || entries[i].block != entries[i - 1].block) {
            while (int(blocks.colourStart.size()) <= entries[i].colour) {
                blocks.colourStart.push_back(blocks.blockStart.size());
            }
            blocks.blockStart.push_back(i);
        }
        blocks.points.push_back(entries[i].point);
    }
    blocks.blockStart.push_back(entries.size());
    while (blocks.colourStart.size() <= 8) {
        blocks.colourStart.push_back(blocks.blockStart.size() - 1);
    }
    return blocks;
}


void
GuardedMoves::buildSourceCells(const std::vector<std::uint32_t>& points)
{
    if (!mSettings.source) return;
    std::vector<std::uint32_t> triangles, patches;
    for (const std::uint32_t v : points) {
        triangles.insert(triangles.end(), mAround.begin() + mStart[v],
                         mAround.begin() + mStart[v + 1]);
    }
    patchesOf(triangles.data(), triangles.data() + triangles.size(), mPatchOf, patches);
    mSettings.source->buildCells(patches);
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
