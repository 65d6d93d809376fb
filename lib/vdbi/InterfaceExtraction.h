// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/InterfaceExtraction.h
/// @brief Walks the faces between different labels of the repaired volume into patches.

#ifndef VDBI_INTERFACE_EXTRACTION_HAS_BEEN_INCLUDED
#define VDBI_INTERFACE_EXTRACTION_HAS_BEEN_INCLUDED

#include <vdbi/InterfaceMesh.h>
#include <vdbi/RefinedLabels.h>

namespace vdbi {

struct ExtractionOptions
{
    /// Only faces owned by voxels in this box (face (v, axis) is owned by voxel v); an empty
    /// box means all. Tiles of a grid extracted this way stitch by their vertex keys.
    openvdb::CoordBBox ownerBox;
    /// Fill InterfaceMesh::pointKeys: needed to stitch tiles, not to write or draw the mesh.
    bool pointKeys = false;
    bool threaded = true;
    openvdb::util::NullInterrupter* interrupter = nullptr;
};

/// @brief Interface extraction (Bischoff & Kobbelt 2006; ALGORITHM.md §4).
/// @details Every face whose two sides carry different labels a < b joins patch (a, b). A
/// coarse face next to a subdivided voxel is split into its s x s fine faces. A coarse edge
/// with a subdivided voxel around it is split into s pieces; a coarse face with a split edge
/// becomes a fan around its centre, other coarse faces two triangles. Vertices are welded by
/// exact integer keys. The output is assembled in a fixed order: byte-identical for any
/// number of threads.
/// @throw openvdb::ValueError if the subdivision is not in [1, 15]
/// @throw vdbi::Interrupted if the interrupter asks to stop
InterfaceMesh extractInterfacePatches(const RefinedLabels& labels,
                                      const ExtractionOptions& options = ExtractionOptions());

} // namespace vdbi

#endif // VDBI_INTERFACE_EXTRACTION_HAS_BEEN_INCLUDED
