// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/FaceCentreCoverage.h
/// @brief The voxel face centres of the raw patches that lie farther than a bound from the
/// remeshed patches: the other half of the closeness the output promises (ALGORITHM.md §5).

#ifndef VDBI_FACE_CENTRE_COVERAGE_HAS_BEEN_INCLUDED
#define VDBI_FACE_CENTRE_COVERAGE_HAS_BEEN_INCLUDED

#include <vdbi/InterfaceMesh.h>

#include <openvdb/Types.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vdbi {

/// A voxel face centre of a raw patch, in world space.
struct FaceCentre
{
    std::uint32_t patch = 0;
    openvdb::Vec3d point;
};

/// Per patch of a raw mesh, its voxel face centres (voxelFaceCentre(), each face once) in
/// voxel units, in the order of its triangles.
using RawFaceCentres = std::vector<std::vector<openvdb::Vec3d>>;

/// The voxel face centres of patch @a patch of @a raw, in voxel units (@a voxel: world
/// size of a voxel per axis), in the order of its triangles (see RawFaceCentres).
std::vector<openvdb::Vec3d> rawFaceCentresOf(const InterfaceMesh& raw, std::size_t patch,
                                             const openvdb::Vec3d& voxel);

/// @brief The voxel face centres (voxelFaceCentre(), each face once) of every patch of
/// @a raw that lie farther than @a limit from every triangle of the same patch of @a mesh,
/// distances measured in voxels along each axis; by patch, then in the order of the raw
/// triangles.
/// @details Remeshing keeps its surface near the smoothed staircase, not near the face
/// centres themselves: at long edge lengths a thin tip can end up a little over a voxel
/// away. Per patch the triangles of @a mesh are sorted into cells two limits wide by their
/// bounding boxes, so that the triangles within the limit of a centre lie in the 8 cells its
/// box overlaps; the patches, and the centres of a large patch in runs of 16384, are
/// searched in parallel (the result does not depend on the number of threads).
/// @param raw    the extracted patches
/// @param mesh   the same patches remeshed (same order)
/// @param voxel  world size of a voxel per axis
std::vector<FaceCentre> findFarFaceCentres(const InterfaceMesh& raw, const InterfaceMesh& mesh,
                                           const openvdb::Vec3d& voxel, double limit,
                                           bool threaded = true);

/// findFarFaceCentres() with the raw patches' centres found already (rawFaceCentresOf()
/// of every patch): what a caller that asks more than once finds only once.
std::vector<FaceCentre> findFarFaceCentres(const RawFaceCentres& centres,
                                           const InterfaceMesh& mesh,
                                           const openvdb::Vec3d& voxel, double limit,
                                           bool threaded = true);

} // namespace vdbi

#endif // VDBI_FACE_CENTRE_COVERAGE_HAS_BEEN_INCLUDED
