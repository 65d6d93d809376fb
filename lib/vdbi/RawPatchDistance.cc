// SPDX-License-Identifier: Apache-2.0

#include <vdbi/RawPatchDistance.h>

#include <vdbi/CandidateGrid.h>
#include <vdbi/RadixSort.h>
#include <vdbi/ReferenceSurface.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vdbi {

using Vec3d = openvdb::Vec3d;

Vec3d
voxelFaceCentre(const Vec3d& a, const Vec3d& b, const Vec3d& c)
{
    // Raw corners are key multiples of the voxel size: equal components are exactly equal.
    auto alongAxis = [](const Vec3d& p, const Vec3d& q) {
        return int(p[0] == q[0]) + int(p[1] == q[1]) + int(p[2] == q[2]) == 2;
    };
    const Vec3d corner[3] = {a, b, c};
    int axisSides = 0, onlyAxisSide = -1; // side i runs from corner i to corner i + 1
    for (int i = 0; i < 3; ++i) {
        if (alongAxis(corner[i], corner[(i + 1) % 3])) {
            ++axisSides;
            onlyAxisSide = i;
        }
    }
    if (axisSides == 1) return corner[(onlyAxisSide + 2) % 3];
    if (axisSides == 2) {
        for (int i = 0; i < 3; ++i) {
            const Vec3d &p = corner[i], &q = corner[(i + 1) % 3], &r = corner[(i + 2) % 3];
            // The diagonal p-q, between two legs of equal length that meet at r.
            const double leg0 = (p - r).lengthSqr(), leg1 = (q - r).lengthSqr();
            if (!alongAxis(p, q) && std::abs(leg0 - leg1) <= 1e-9 * std::max(leg0, leg1)) {
                return 0.5 * (p + q);
            }
        }
    }
    return (a + b + c) / 3.0;
}


bool
ownsFaceCentre(const Vec3d (&corner)[3], const Vec3d& centre)
{
    for (int i = 0; i < 3; ++i) {
        const Vec3d &p = corner[i], &q = corner[(i + 1) % 3];
        if (0.5 * (p + q) == centre) return p < q;
    }
    return true;
}


namespace {

bool
isInBox(const Vec3d& q, const Vec3d& low, const Vec3d& high)
{
    return q[0] >= low[0] && q[1] >= low[1] && q[2] >= low[2] && q[0] <= high[0]
        && q[1] <= high[1] && q[2] <= high[2];
}

/// Is the closest point of triangle @a t to @a q within @a limit of it (no quick rejection
/// first: the callers have made theirs)?
bool
isClosestWithin(const Vec3d& q, const RawPatchDistance::Corners& t, double limit)
{
    Vec3d bary;
    return (closestPointOnTriangle(q, t.c[0], t.c[1], t.c[2], bary) - q).lengthSqr()
        <= limit * limit;
}

} // namespace


RawPatchDistance::RawPatchDistance(const InterfaceMesh& raw, const Vec3d& voxel, double radius)
    : mRaw(raw), mVoxel(voxel), mInverse(1.0 / voxel[0], 1.0 / voxel[1], 1.0 / voxel[2])
    , mRadius(radius), mCells(raw.patches.size())
{
}


Vec3d
RawPatchDistance::scaled(const Vec3d& p) const
{
    return Vec3d(p[0] * mInverse[0], p[1] * mInverse[1], p[2] * mInverse[2]);
}


Vec3d
RawPatchDistance::world(const Vec3d& q) const
{
    return Vec3d(q[0] * mVoxel[0], q[1] * mVoxel[1], q[2] * mVoxel[2]);
}


const RawPatchDistance::Cells&
RawPatchDistance::cellsOf(std::uint32_t patch)
{
    Cells& cells = mCells[patch];
    if (cells.built) return cells;
    const InterfacePatch& rp = mRaw.patches[patch];
    cells.entries.reserve(rp.triangleCount);
    for (std::size_t t = rp.firstTriangle; t < rp.firstTriangle + rp.triangleCount; ++t) {
        const openvdb::Vec3I& tri = mRaw.triangles[t];
        const Vec3d a = scaled(mRaw.points[tri[0]]), b = scaled(mRaw.points[tri[1]]),
                    c = scaled(mRaw.points[tri[2]]);
        const Vec3d centre = (a + b + c) / 3.0;
        cells.reach = std::max({cells.reach, (a - centre).length(), (b - centre).length(),
                                (c - centre).length()});
        cells.centreReach =
            std::max(cells.centreReach, (voxelFaceCentre(a, b, c) - centre).length());
        const openvdb::Vec3i cell(int(std::floor(centre[0])), int(std::floor(centre[1])),
                                  int(std::floor(centre[2])));
        cells.entries.emplace_back(cellKey(cell), std::uint32_t(t));
    }
    // Made by triangle: sorted by (key, triangle).
    sortByPackedKey<3, CELL_KEY_BITS>(cells.entries, [](const auto& e) { return e.first; });
    cells.built = true;
    return cells;
}


void
RawPatchDistance::buildCells(const std::vector<std::uint32_t>& patches)
{
    for (const std::uint32_t patch : patches) cellsOf(patch);
}


RawPatchDistance::Hit
RawPatchDistance::nearest(const Vec3d& p, std::uint32_t patch)
{
    const Cells& cells = cellsOf(patch);
    const Vec3d q = scaled(p);
    // A triangle within the radius has its centroid within radius + reach.
    const double margin = mRadius + cells.reach;
    double best2 = mRadius * mRadius;
    Vec3d best = q, bary;
    forEachEntryInCells(cells.entries, cellOf(q - Vec3d(margin), 1.0),
                        cellOf(q + Vec3d(margin), 1.0), [&](std::uint32_t t) {
        const openvdb::Vec3I& tri = mRaw.triangles[t];
        const Vec3d nearest = closestPointOnTriangle(q, scaled(mRaw.points[tri[0]]),
                                                     scaled(mRaw.points[tri[1]]),
                                                     scaled(mRaw.points[tri[2]]), bary);
        const double d2 = (nearest - q).lengthSqr();
        if (d2 < best2) {
            best2 = d2;
            best = nearest;
        }
    });
    Hit hit;
    hit.point = Vec3d(best[0] * mVoxel[0], best[1] * mVoxel[1], best[2] * mVoxel[2]);
    if (best == q) hit.point = p;
    hit.distance = std::sqrt(best2);
    return hit;
}


RawPatchDistance::Corners
RawPatchDistance::corners(const PointArray& points, const openvdb::Vec3I& t) const
{
    return {{scaled(points[t[0]]), scaled(points[t[1]]), scaled(points[t[2]])}};
}


bool
RawPatchDistance::isWithin(const Vec3d& q, const Corners& t, double limit)
{
    // Farther than the limit from the triangle's bounding box along an axis: farther from
    // the triangle. Most points the guards ask about are (their boxes are axis-aligned, the
    // surface is not), and this costs a fraction of the closest point.
    for (int k = 0; k < 3; ++k) {
        if (q[k] + limit < std::min({t.c[0][k], t.c[1][k], t.c[2][k]})
            || q[k] - limit > std::max({t.c[0][k], t.c[1][k], t.c[2][k]})) {
            return false;
        }
    }
    return isClosestWithin(q, t, limit);
}


namespace {

/// @brief A triangle (voxel units) of RawPatchDistance::keepsCovered(), with what rejects
/// most points without a closest point: its box and, if it has area, the slab of points
/// within the limit of its plane.
struct GuardTriangle
{
    explicit GuardTriangle(const RawPatchDistance::Corners& corners) : t(corners)
    {
        for (int k = 0; k < 3; ++k) {
            low[k] = std::min({t.c[0][k], t.c[1][k], t.c[2][k]});
            high[k] = std::max({t.c[0][k], t.c[1][k], t.c[2][k]});
        }
        const Vec3d u = t.c[1] - t.c[0], v = t.c[2] - t.c[0], n = u.cross(v);
        // A plane known to 1e-12 radians: the slab test stays on the safe side of rounding.
        hasPlane = n.lengthSqr() > 1e-8 * u.lengthSqr() * v.lengthSqr();
        normal = hasPlane ? n / n.length() : Vec3d(0.0);
    }

    /// RawPatchDistance::isWithin(), the same answer to every point: isNear() holds its box
    /// test and adds the slab's.
    bool isWithin(const Vec3d& q, double limit) const
    {
        return isNear(q, limit) && isClosestWithin(q, t, limit);
    }

    /// False only if @a q is farther than @a limit from the triangle.
    bool isNear(const Vec3d& q, double limit) const
    {
        for (int k = 0; k < 3; ++k) {
            if (q[k] + limit < low[k] || q[k] - limit > high[k]) return false;
        }
        // Off the slab by more than rounding can explain: off the triangle by more too.
        return !hasPlane || std::abs(normal.dot(q - t.c[0])) <= limit + 1e-7;
    }

    RawPatchDistance::Corners t;
    Vec3d low, high, normal;
    bool hasPlane;
};

/// @brief Does @a test hold for one of @a triangles? Tries the one it last held for first
/// (@a hint, updated to the one it holds for): the points come cell by cell, and neighbours
/// mostly lie near the same triangle.
template<typename Test>
bool
anyFromHint(const std::vector<GuardTriangle>& triangles, std::size_t& hint, const Test& test)
{
    const std::size_t n = triangles.size();
    for (std::size_t j = 0; j < n; ++j) {
        const std::size_t k = hint + j < n ? hint + j : hint + j - n;
        if (test(triangles[k])) {
            hint = k;
            return true;
        }
    }
    return false;
}

} // namespace


bool
RawPatchDistance::keepsCovered(std::uint32_t patch, const std::vector<Corners>& before,
                               const std::vector<Corners>& now, double limit,
                               const std::function<bool(const Vec3d&)>& coveredElsewhere)
{
    // A triangle in both lists keeps the points within the limit of it: only the points
    // near the others can be lost (a collapse into a point that stays keeps half its fan).
    auto isSame = [](const Corners& s, const Corners& t) {
        for (int i = 0; i < 3; ++i) {
            for (int k = 0; k < 3; ++k) if (s.c[i][k] != t.c[i][k]) return false;
        }
        return true;
    };
    std::vector<GuardTriangle> then;
    then.reserve(before.size());
    for (const Corners& t : before) {
        const bool kept = std::any_of(now.begin(), now.end(),
                                      [&](const Corners& n) { return isSame(t, n); });
        if (!kept) then.emplace_back(t);
    }
    if (then.empty()) return true;
    const std::vector<GuardTriangle> after(now.begin(), now.end());
    // Only points within the limit of a changed triangle as it was can have lost it; the
    // box of those holds them all, and most of its points are not near any.
    Vec3d low(std::numeric_limits<double>::max()), high(-low);
    for (const GuardTriangle& t : then) {
        low = openvdb::math::minComponent(low, t.low);
        high = openvdb::math::maxComponent(high, t.high);
    }
    std::size_t nearHint = 0, thenHint = 0, afterHint = 0;
    auto nearBefore = [&](const Vec3d& q) {
        return anyFromHint(then, nearHint,
                           [&](const GuardTriangle& t) { return t.isNear(q, limit); });
    };
    auto within = [&](const Vec3d& q, const std::vector<GuardTriangle>& triangles,
                      std::size_t& hint) {
        return anyFromHint(triangles, hint,
                           [&](const GuardTriangle& t) { return t.isWithin(q, limit); });
    };
    // Each point is judged as it is found: the first one lost ends the search.
    return guardedPointsIn(patch, low - Vec3d(limit), high + Vec3d(limit), [&](const Vec3d& q) {
        return !nearBefore(q) || within(q, after, afterHint) || !within(q, then, thenHint)
            || coveredElsewhere(q);
    });
}


template<typename Visit>
bool
RawPatchDistance::guardedPointsIn(std::uint32_t patch, const Vec3d& low, const Vec3d& high,
                                  const Visit& visit)
{
    const Cells& cells = cellsOf(patch);
    // Cells hold triangles by centroid: a face centre in the box has its triangle's centroid
    // within centreReach of it.
    const Vec3d cellLow = low - Vec3d(cells.centreReach),
                cellHigh = high + Vec3d(cells.centreReach);
    bool goOn = true;
    forEachEntryInCells(cells.entries, cellOf(cellLow, 1.0), cellOf(cellHigh, 1.0),
                        [&](std::uint32_t t) {
        if (!goOn) return;
        const openvdb::Vec3I& tri = mRaw.triangles[t];
        const Vec3d corner[3] = {scaled(mRaw.points[tri[0]]), scaled(mRaw.points[tri[1]]),
                                 scaled(mRaw.points[tri[2]])};
        const Vec3d centroid = (corner[0] + corner[1] + corner[2]) / 3.0;
        if (isInBox(centroid, low, high)) goOn = visit(centroid);
        // The face centre is within centreReach of the centroid.
        if (!goOn || !isInBox(centroid, cellLow, cellHigh)) return;
        const Vec3d centre = voxelFaceCentre(corner[0], corner[1], corner[2]);
        if (isInBox(centre, low, high) && ownsFaceCentre(corner, centre)) goOn = visit(centre);
    });
    return goOn;
}


RawPatchDistance::Hit
RawPatchDistance::farthest(const Vec3d& p, const std::vector<std::uint32_t>& patches)
{
    Hit result;
    result.point = p;
    for (const std::uint32_t patch : patches) {
        const Hit hit = nearest(p, patch);
        if (hit.distance > result.distance) result = hit;
    }
    return result;
}

} // namespace vdbi
