// SPDX-License-Identifier: Apache-2.0

#include <vdbi/RawPatchDistance.h>

#include <vdbi/CandidateGrid.h>
#include <vdbi/ReferenceSurface.h>

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>

namespace vdbi {

using Vec3d = openvdb::Vec3d;

RawPatchDistance::RawPatchDistance(const InterfaceMesh& raw, const Vec3d& voxel, double radius,
                                   bool threaded)
    : mRaw(raw), mVoxel(voxel), mInverse(1.0 / voxel[0], 1.0 / voxel[1], 1.0 / voxel[2])
    , mRadius(radius), mThreaded(threaded), mCells(raw.patches.size())
{
}


Vec3d
RawPatchDistance::scaled(const Vec3d& p) const
{
    return Vec3d(p[0] * mInverse[0], p[1] * mInverse[1], p[2] * mInverse[2]);
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
        const Vec3d centroid = (a + b + c) / 3.0;
        cells.reach = std::max({cells.reach, (a - centroid).length(),
                                (b - centroid).length(), (c - centroid).length()});
        const openvdb::Vec3i cell(int(std::floor(centroid[0])), int(std::floor(centroid[1])),
                                  int(std::floor(centroid[2])));
        cells.entries.emplace_back(cellKey(cell), std::uint32_t(t));
    }
    // Every entry differs (one per triangle): the order is the same on any number of threads.
    if (mThreaded) {
        tbb::parallel_sort(cells.entries.begin(), cells.entries.end());
    } else {
        std::sort(cells.entries.begin(), cells.entries.end());
    }
    cells.built = true;
    return cells;
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
    for (int x = int(std::floor(q[0] - margin)); x <= int(std::floor(q[0] + margin)); ++x) {
        for (int y = int(std::floor(q[1] - margin)); y <= int(std::floor(q[1] + margin)); ++y) {
            for (int z = int(std::floor(q[2] - margin)); z <= int(std::floor(q[2] + margin));
                 ++z) {
                const std::uint64_t key = cellKey(openvdb::Vec3i(x, y, z));
                auto it = std::lower_bound(cells.entries.begin(), cells.entries.end(),
                                           std::make_pair(key, std::uint32_t(0)));
                for (; it != cells.entries.end() && it->first == key; ++it) {
                    const openvdb::Vec3I& tri = mRaw.triangles[it->second];
                    const Vec3d nearest = closestPointOnTriangle(
                        q, scaled(mRaw.points[tri[0]]), scaled(mRaw.points[tri[1]]),
                        scaled(mRaw.points[tri[2]]), bary);
                    const double d2 = (nearest - q).lengthSqr();
                    if (d2 < best2) {
                        best2 = d2;
                        best = nearest;
                    }
                }
            }
        }
    }
    Hit hit;
    hit.point = Vec3d(best[0] * mVoxel[0], best[1] * mVoxel[1], best[2] * mVoxel[2]);
    if (best == q) hit.point = p;
    hit.distance = std::sqrt(best2);
    return hit;
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
