// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/InterfaceMesh.h
/// @brief The flat result: points, triangles and the label pair of every triangle, grouped
/// into patches. Needs no mesh library (writers, the Houdini SOP).

#ifndef VDBI_INTERFACE_MESH_HAS_BEEN_INCLUDED
#define VDBI_INTERFACE_MESH_HAS_BEEN_INCLUDED

#include <vdbi/Types.h>

#include <openvdb/Types.h>

#include <array>
#include <cstdint>
#include <vector>

namespace vdbi {

/// Exact integer position of a vertex on the key grid, 2s points per coarse voxel: coarse
/// grid point v is 2s*v, fine grid point p is 2p, the centre of a coarse face is its corner
/// plus s along the two face axes. Equal keys are the same vertex, across patches and tiles.
using VertexKey = std::array<std::int64_t, 3>;

/// The triangles [firstTriangle, firstTriangle + triangleCount) between labels a < b.
struct InterfacePatch
{
    Label a = 0, b = 0;
    std::size_t firstTriangle = 0;
    std::size_t triangleCount = 0;
};

/// @brief Interface triangles between every pair of adjacent labels.
/// @details Every triangle of patch (a, b) is oriented with its normal pointing from label a
/// into label b (counter-clockwise seen from b). Patches are sorted by (a, b); their triangles
/// are contiguous. Points are shared between patches along common boundary curves.
struct InterfaceMesh
{
    std::vector<openvdb::Vec3d> points;           ///< world space
    std::vector<openvdb::Vec3I> triangles;        ///< indices into points
    std::vector<InterfacePatch> patches;          ///< sorted by (a, b)
    /// Exact key of every point; empty unless asked for (ExtractionOptions::pointKeys) and
    /// after remeshing moved points off the key grid.
    std::vector<VertexKey> pointKeys;
    int keyScale = 0;                             ///< key units per coarse voxel (2s)

    std::size_t triangleCount() const { return triangles.size(); }
    std::size_t pointCount() const { return points.size(); }
    /// The label pair (a, b) of every triangle, in triangle order.
    std::vector<std::array<Label, 2>> triangleLabels() const;
};

} // namespace vdbi

#endif // VDBI_INTERFACE_MESH_HAS_BEEN_INCLUDED
