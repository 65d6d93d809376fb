// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/CriticalElements.h
/// @brief Finds the non-manifold (critical) edges and vertices of every label's voxel set.
/// @details Bischoff & Kobbelt 2006; ALGORITHM.md §2. Index space: voxel c is the cube
/// [c, c+1]; grid point v is the min corner of voxel v; edge (v, axis) runs from v to
/// v + e_axis; face (v, axis) is the face at v with normal axis, between voxels v - e_axis
/// and v.

#ifndef VDBI_CRITICAL_ELEMENTS_HAS_BEEN_INCLUDED
#define VDBI_CRITICAL_ELEMENTS_HAS_BEEN_INCLUDED

#include <vdbi/Types.h>

#include <openvdb/openvdb.h>

#include <vector>

namespace vdbi {

/// A critical face (only with constraints): between voxels origin - e_axis and origin.
struct CriticalFace
{
    openvdb::Coord origin;
    int axis = 0;
    Label label = 0; ///< dominant label
};

/// A critical edge from grid point origin along axis.
struct CriticalEdge
{
    openvdb::Coord origin;
    int axis = 0;
    Label label = 0; ///< dominant label
};

/// A critical grid point; its 2x2x2 block is the voxels [point - 1, point].
struct CriticalVertex
{
    openvdb::Coord point;
    Label label = 0;         ///< dominant label
    bool isSingular = false; ///< one of the antipodal configurations (§2 rule 2) for some label
};

/// All critical elements of a label grid, each list sorted by coordinate (then axis).
struct CriticalElements
{
    std::vector<CriticalFace> faces;
    std::vector<CriticalEdge> edges;
    std::vector<CriticalVertex> vertices;

    std::size_t singularVertexCount() const;
    bool empty() const { return faces.empty() && edges.empty() && vertices.empty(); }
};

/// @brief Every edge and grid point at which some label's voxel set is not a 2-manifold.
/// @details An edge is critical for label L when two diagonally opposite voxels of its four
/// are L and the other two are not. A grid point is critical for L when it ends such an edge,
/// or when its 2x2x2 block holds exactly two antipodal voxels of L (or exactly six, with two
/// antipodal others). The dominant label is the one of highest priority among those for which
/// the element is critical. With constraints, faces, edges and points at which both labels of
/// a constraint occur are critical with the separator as dominant label (ALGORITHM.md §6).
/// Runs as a TBB pass over the leaf nodes (and the background next to them); the cost grows
/// with the number of leaves, not with the bounding box. Tiles are taken as their voxels.
/// @param grid     the labels; its background value is the label of everything not stored
/// @param options  priority, constraints, threading, interrupter
/// @throw vdbi::Interrupted if the interrupter asks to stop
CriticalElements findCriticalElements(const openvdb::Int32Grid& grid,
                                      const RepairOptions& options = RepairOptions());

} // namespace vdbi

#endif // VDBI_CRITICAL_ELEMENTS_HAS_BEEN_INCLUDED
