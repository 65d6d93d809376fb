// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/PatchMeshes.h
/// @brief One OpenMesh triangle mesh per interface patch, for remeshing and library users.
/// @details The only public header that includes OpenMesh.

#ifndef VDBI_PATCH_MESHES_HAS_BEEN_INCLUDED
#define VDBI_PATCH_MESHES_HAS_BEEN_INCLUDED

#include <vdbi/InterfaceMesh.h>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <vector>

namespace vdbi {

/// Double-precision points, as the world-space points of InterfaceMesh.
struct PatchMeshTraits : public OpenMesh::DefaultTraits
{
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<PatchMeshTraits>;

/// A world-space point of InterfaceMesh as a TriMesh point, and back.
inline TriMesh::Point toPoint(const openvdb::Vec3d& p) { return TriMesh::Point(p[0], p[1], p[2]); }
inline openvdb::Vec3d toVec(const TriMesh::Point& p) { return openvdb::Vec3d(p[0], p[1], p[2]); }

/// One patch between labels a < b, normals from a into b.
struct PatchMesh
{
    Label a = 0, b = 0;
    TriMesh mesh;
    /// Index in InterfaceMesh::points of every vertex of @c mesh (by vertex handle index).
    std::vector<std::uint32_t> pointIndex;
};

/// @brief Converts every patch into an OpenMesh halfedge mesh.
/// @details A patch is a 2-manifold with boundary (the boundary may touch itself at a vertex),
/// so every triangle must be accepted by the halfedge structure; a refused one (a complex
/// edge or vertex) is a broken guarantee. Patches convert in parallel.
/// @throw vdbi::TopologyError if a triangle cannot be added (names the patch)
std::vector<PatchMesh> toPatchMeshes(const InterfaceMesh& mesh, bool threaded = true);

} // namespace vdbi

#endif // VDBI_PATCH_MESHES_HAS_BEEN_INCLUDED
