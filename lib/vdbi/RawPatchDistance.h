// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/RawPatchDistance.h
/// @brief How far points lie from the extracted (raw) patches, in voxels: what keeps the
/// moves after remeshing within the closeness the output promises (ALGORITHM.md §5).

#ifndef VDBI_RAW_PATCH_DISTANCE_HAS_BEEN_INCLUDED
#define VDBI_RAW_PATCH_DISTANCE_HAS_BEEN_INCLUDED

#include <vdbi/InterfaceMesh.h>

#include <openvdb/Types.h>

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace vdbi {

/// @brief The centre of the voxel face that raw triangle (a, b, c) is part of, in voxel units.
/// @details A face is two triangles whose legs lie along the lattice axes (its centre is the
/// midpoint of their shared diagonal), or, where a side is split, a fan from its centre, whose
/// triangles have one side along an axis (the centre is the corner opposite). Any other
/// triangle (the piece of a fan next to the midpoint of a side split in an even number):
/// its centroid. With sides split in 2 that piece looks like a fine face's half: the point
/// taken is then the centre of a quarter of the face.
openvdb::Vec3d voxelFaceCentre(const openvdb::Vec3d& a, const openvdb::Vec3d& b,
                               const openvdb::Vec3d& c);

/// @brief Is @a centre, the voxelFaceCentre() of the triangle with corners @a corner, this
/// triangle's to report? Both halves of a face give the midpoint of their shared diagonal,
/// exactly, and run along it in opposite directions: the half that runs from the smaller
/// corner reports it. (The centre of a fan, a corner of each of its triangles, is reported
/// by each: they are few.)
bool ownsFaceCentre(const openvdb::Vec3d (&corner)[3], const openvdb::Vec3d& centre);

/// @brief Distances from points to the raw patches, measured in voxels along each axis (as
/// the tests measure closeness), exactly up to a radius.
/// @details A patch's triangles are sorted into cells of one voxel by their centroids when a
/// distance to it is first asked: the moves after remeshing ask few distances, and building
/// a KD-tree with its normals (ReferenceSurface) for each patch they touch took separation on
/// the frog at 2 voxels from 1.7 to 4.1 s (2.1 s with the cells). One caller at a time, but
/// for callers that ask only about patches whose cells buildCells() built, and for calls of
/// buildCells() on different patches (each patch's cells are its own).
class RawPatchDistance
{
public:
    /// @param raw       the extracted patches (kept by reference)
    /// @param voxel     world size of a voxel per axis
    /// @param radius    in voxels: a distance beyond it is reported as @a radius
    RawPatchDistance(const InterfaceMesh& raw, const openvdb::Vec3d& voxel, double radius);

    /// The nearest point of a patch to a query.
    struct Hit
    {
        openvdb::Vec3d point;   ///< in world space; the query itself if none is in the radius
        double distance = 0.0;  ///< in voxels, at most the radius
    };

    /// Sorts the triangles of @a patches into their cells now, not when first asked.
    void buildCells(const std::vector<std::uint32_t>& patches);

    /// The point of patch @a patch of the raw mesh nearest to world point @a p.
    Hit nearest(const openvdb::Vec3d& p, std::uint32_t patch);
    /// nearest() on the patch of @a patches farthest from @a p (a hit at p for none).
    Hit farthest(const openvdb::Vec3d& p, const std::vector<std::uint32_t>& patches);

    /// A triangle by its corners in voxel units (scaled()).
    struct Corners
    {
        openvdb::Vec3d c[3];
    };
    /// Triangle @a t of @a points (world space) in voxel units.
    Corners corners(const PointArray& points, const openvdb::Vec3I& t) const;
    /// Is @a q within @a limit of triangle @a t (both in voxel units)?
    static bool isWithin(const openvdb::Vec3d& q, const Corners& t, double limit);

    /// @brief Does a change of some triangles of patch @a patch keep the patch's source
    /// close? A voxel face centre (voxelFaceCentre()) or triangle centroid of the source within
    /// @a limit voxels of one of @a before (the changed triangles as they were) must be within
    /// it of one of @a now (as they are), or @a coveredElsewhere(point) must find another
    /// triangle of the patch within it.
    /// @details The face centres are what the output promises to stay near; neither measure
    /// bounds the other (a centre can lie farther from the result than the centroids of its
    /// face's halves; guarding the centres alone let the frog at 4 voxels have a centre 1.010
    /// voxels from the result, its centroids up to 1.223).
    bool keepsCovered(std::uint32_t patch, const std::vector<Corners>& before,
                      const std::vector<Corners>& now, double limit,
                      const std::function<bool(const openvdb::Vec3d&)>& coveredElsewhere);

    /// World point @a p in voxel units along each axis.
    openvdb::Vec3d scaled(const openvdb::Vec3d& p) const;
    /// Point @a q in voxel units back in world space.
    openvdb::Vec3d world(const openvdb::Vec3d& q) const;

private:
    /// A patch's triangles by cell: ascending keys, and the triangle of each.
    struct Cells
    {
        bool built = false;
        std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
        double reach = 0.0;   ///< farthest corner from its triangle's centroid, in voxels
        double centreReach = 0.0;   ///< the same for voxelFaceCentre()
    };

    const Cells& cellsOf(std::uint32_t patch);
    /// @brief Calls @a visit(point) for the centroids of patch @a patch's triangles in the box
    /// [@a low, @a high], and for their voxel face centres there (a face's once for its two
    /// halves), until it returns false; returns false if it did.
    template<typename Visit>
    bool guardedPointsIn(std::uint32_t patch, const openvdb::Vec3d& low,
                         const openvdb::Vec3d& high, const Visit& visit);

    const InterfaceMesh& mRaw;
    const openvdb::Vec3d mVoxel, mInverse;
    const double mRadius;
    std::vector<Cells> mCells;
};

} // namespace vdbi

#endif // VDBI_RAW_PATCH_DISTANCE_HAS_BEEN_INCLUDED
