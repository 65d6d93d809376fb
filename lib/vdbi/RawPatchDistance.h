// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/RawPatchDistance.h
/// @brief How far points lie from the extracted (raw) patches, in voxels: what keeps the
/// moves after remeshing within the closeness the output promises (ALGORITHM.md §5).

#ifndef VDBI_RAW_PATCH_DISTANCE_HAS_BEEN_INCLUDED
#define VDBI_RAW_PATCH_DISTANCE_HAS_BEEN_INCLUDED

#include <vdbi/InterfaceMesh.h>

#include <openvdb/Types.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace vdbi {

/// @brief Distances from points to the raw patches, measured in voxels along each axis (as
/// the tests measure closeness), exactly up to a radius.
/// @details A patch's triangles are sorted into cells of one voxel by their centroids when a
/// distance to it is first asked: the moves after remeshing ask few distances, and building
/// a KD-tree with its normals (ReferenceSurface) for each patch they touch took separation on
/// the frog at 2 voxels from 1.7 to 4.1 s (2.1 s with the cells). Not thread-safe: one caller
/// at a time.
class RawPatchDistance
{
public:
    /// @param raw       the extracted patches (kept by reference)
    /// @param voxel     world size of a voxel per axis
    /// @param radius    in voxels: a distance beyond it is reported as @a radius
    /// @param threaded  sort a patch's cells with TBB
    RawPatchDistance(const InterfaceMesh& raw, const openvdb::Vec3d& voxel, double radius,
                     bool threaded = true);

    /// The nearest point of a patch to a query.
    struct Hit
    {
        openvdb::Vec3d point;   ///< in world space; the query itself if none is in the radius
        double distance = 0.0;  ///< in voxels, at most the radius
    };

    /// The point of patch @a patch of the raw mesh nearest to world point @a p.
    Hit nearest(const openvdb::Vec3d& p, std::uint32_t patch);
    /// nearest() on the patch of @a patches farthest from @a p (a hit at p for none).
    Hit farthest(const openvdb::Vec3d& p, const std::vector<std::uint32_t>& patches);

private:
    /// A patch's triangles by cell: ascending keys, and the triangle of each.
    struct Cells
    {
        bool built = false;
        std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
        double reach = 0.0;   ///< farthest corner from its triangle's centroid, in voxels
    };

    const Cells& cellsOf(std::uint32_t patch);
    openvdb::Vec3d scaled(const openvdb::Vec3d& p) const;

    const InterfaceMesh& mRaw;
    const openvdb::Vec3d mVoxel, mInverse;
    const double mRadius;
    const bool mThreaded;
    std::vector<Cells> mCells;
};

} // namespace vdbi

#endif // VDBI_RAW_PATCH_DISTANCE_HAS_BEEN_INCLUDED
