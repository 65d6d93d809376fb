// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/RefinedLabels.h
/// @brief The repaired label volume: the coarse grid, plus a sparse grid s times finer that
/// holds only the subvoxels whose label changed, plus a mask of the subdivided coarse voxels.

#ifndef VDBI_REFINED_LABELS_HAS_BEEN_INCLUDED
#define VDBI_REFINED_LABELS_HAS_BEEN_INCLUDED

#include <vdbi/Types.h>

#include <openvdb/openvdb.h>

namespace vdbi {

/// Floor of a / b for b > 0 (C++ division truncates toward zero).
inline std::int32_t
floorDiv(std::int32_t a, std::int32_t b)
{
    const std::int32_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}

/// The coarse voxel that holds fine voxel @a f.
inline openvdb::Coord
coarseOf(const openvdb::Coord& f, int s)
{
    return openvdb::Coord(floorDiv(f.x(), s), floorDiv(f.y(), s), floorDiv(f.z(), s));
}

/// @brief Labels after fattening (ALGORITHM.md §3).
/// @details Fine voxel f lies in coarse voxel floor(f / s). Its label is the value of @c fine
/// at f where that voxel is active (relabelled), else the label of its coarse voxel. Only
/// coarse voxels marked in @c subdivided hold active fine voxels; nothing is densely upsampled.
struct RefinedLabels
{
    openvdb::Int32Grid::ConstPtr coarse; ///< the input labels (tiles voxelized)
    openvdb::Int32Grid::Ptr fine;        ///< active voxels: relabelled subvoxels (fine index space)
    openvdb::MaskGrid::Ptr subdivided;   ///< active voxels: subdivided coarse voxels
    int subdivision = 1;                 ///< s: 5, or 7 with constraints

    /// Read access for one thread (holds value accessors: never share between threads).
    class Accessor
    {
    public:
        explicit Accessor(const RefinedLabels& r)
            : mCoarse(r.coarse->getConstAccessor())
            , mFine(r.fine->getConstAccessor())
            , mMask(r.subdivided->getConstAccessor())
            , mS(r.subdivision)
        {}
        Label coarseLabel(const openvdb::Coord& c) { return mCoarse.getValue(c); }
        bool isSubdivided(const openvdb::Coord& c) { return mMask.isValueOn(c); }
        Label fineLabel(const openvdb::Coord& f)
        {
            Label v;
            if (mFine.probeValue(f, v)) return v;
            return mCoarse.getValue(coarseOf(f, mS));
        }

    private:
        openvdb::Int32Grid::ConstAccessor mCoarse;
        openvdb::Int32Grid::ConstAccessor mFine;
        openvdb::MaskGrid::ConstAccessor mMask;
        int mS;
    };
};

} // namespace vdbi

#endif // VDBI_REFINED_LABELS_HAS_BEEN_INCLUDED
