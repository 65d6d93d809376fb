// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/MeshWriter.h
/// @brief Writes interface meshes (.ply, .obj, .vtp) and per-label closed surfaces.

#ifndef VDBI_MESH_WRITER_HAS_BEEN_INCLUDED
#define VDBI_MESH_WRITER_HAS_BEEN_INCLUDED

#include <vdbi/InterfaceMesh.h>

#include <string>

namespace vdbi {

/// @brief Writes all patches to one file; the format comes from the extension of @a path.
/// @details .ply: binary little-endian, face properties label0, label1 (int). .obj: one group
/// per patch named patch_A_B. .vtp: VTK XML PolyData with the 2-component int cell array
/// BoundaryLabels (the vtkSurfaceNets3D convention). Written to a temporary file in the same
/// folder and renamed on success: a failed write never leaves a partial file.
/// @throw openvdb::IoError if the file cannot be written (the message names it)
/// @throw openvdb::ValueError for an unknown extension
void writeInterfaceMesh(const InterfaceMesh& mesh, const std::string& path);

/// @brief One closed, outward-oriented surface per label (the union of its patches, flipped
/// where the label is the b side) into folder @a dir as label_<L>.<ext>, ext "stl" or "ply".
/// The background label is skipped. The folder must exist.
/// @throw openvdb::IoError, openvdb::ValueError as writeInterfaceMesh()
void writePerLabelSurfaces(const InterfaceMesh& mesh, const std::string& dir,
                           const std::string& ext = "stl", Label background = 0);

} // namespace vdbi

#endif // VDBI_MESH_WRITER_HAS_BEEN_INCLUDED
