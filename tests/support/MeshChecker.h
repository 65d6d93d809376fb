// SPDX-License-Identifier: Apache-2.0
/// @file support/MeshChecker.h
/// @brief Independent checks of an interface mesh (ALGORITHM.md §4): every patch a consistently
/// oriented 2-manifold with boundary, patch boundaries shared, every label's patches a closed
/// oriented surface; its Euler characteristic and enclosed volume. Plus an independent plain
/// face extraction (2 triangles per coarse interface face) and the Euler characteristic of a
/// voxel set, to compare against.
/// @details Vertices are identified by their exact keys (InterfaceMesh::pointKeys) when present,
/// else by point index. Nothing here uses the library's extraction code.

#pragma once

#include <vdbi/InterfaceMesh.h>
#include <vdbi/Types.h>

#include <openvdb/openvdb.h>

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace vdbi_test {

/// Findings of one patch (a, b).
struct PatchReport
{
    vdbi::Label a = 0, b = 0;
    std::size_t triangles = 0;
    std::size_t degenerateTriangles = 0;    ///< two equal vertices
    std::size_t duplicateTriangles = 0;     ///< the same vertex set as an earlier triangle
    std::size_t duplicateDirectedEdges = 0; ///< a directed edge used twice: orientation flips
    std::size_t nonManifoldEdges = 0;       ///< undirected edges in more than 2 triangles
    std::size_t boundaryEdges = 0;          ///< undirected edges in exactly 1 triangle
    std::size_t unmatchedBoundaryEdges = 0; ///< boundary edges that bound no other patch
    /// Vertices whose triangles form a closed fan plus more fans (never allowed).
    std::size_t closedFanPlusMore = 0;
    /// Vertices whose triangles form several open fans (the boundary touches itself there;
    /// allowed, counted).
    std::size_t severalOpenFans = 0;
    /// Twice the area of the axis-aligned triangles in key units (exact; keys only): a fine
    /// face (2 x 2 keys) counts 8, a coarse face 2 keyScale^2, however it is triangulated.
    std::int64_t twiceAreaKeys = 0;
    std::size_t skewTriangles = 0;          ///< triangles in no coordinate plane (keys only)

    bool ok() const
    {
        return degenerateTriangles == 0 && duplicateTriangles == 0 && duplicateDirectedEdges == 0
            && nonManifoldEdges == 0 && unmatchedBoundaryEdges == 0 && closedFanPlusMore == 0;
    }
};

/// Findings of the union of the patches of one label, oriented outward.
struct LabelReport
{
    vdbi::Label label = 0;
    std::size_t triangles = 0, vertices = 0, edges = 0;
    std::size_t openEdges = 0;          ///< undirected edges not in exactly 2 triangles
    std::size_t orientationErrors = 0;  ///< edges in 2 triangles that do not run opposite ways
    std::size_t badFanVertices = 0;     ///< vertices whose triangles are not one closed fan
    std::int64_t euler = 0;             ///< V - E + F
    /// Signed enclosed volume (divergence theorem) in coarse index units; positive for a
    /// bounded label, minus the volume of all the rest for the background.
    double volume = 0;
    /// 6 x the volume in key units (exact when keys are present).
    __int128 sixVolumeKeys = 0;

    bool closed() const { return openEdges == 0 && orientationErrors == 0 && badFanVertices == 0; }
};

/// Everything the mesh checker found.
struct MeshReport
{
    std::size_t points = 0, triangles = 0, patches = 0;
    bool usedKeys = false;
    int keyScale = 0;
    /// Structural problems: bad indices, unsorted or overlapping patches, key count mismatch.
    std::size_t structureErrors = 0;
    std::size_t duplicatePoints = 0;        ///< distinct point indices with equal keys
    std::size_t unusedPoints = 0;
    std::size_t duplicateTrianglesGlobal = 0; ///< a triangle's vertex set in two patches
    /// Vertices lying strictly inside an edge of the mesh (exact test on keys; 0 without keys).
    std::size_t tJunctions = 0;
    std::vector<PatchReport> patchReports;
    std::map<vdbi::Label, LabelReport> labels;
    std::vector<std::string> messages;      ///< the first few problems, readable

    /// Every check passed (several open fans at a vertex are allowed).
    bool ok() const;
    std::string summary() const;
    /// Sum over patches of a PatchReport counter.
    std::size_t sum(std::size_t PatchReport::*counter) const;
};

/// @brief Runs every check on @a mesh.
/// @param useKeys  identify vertices by pointKeys when present (else by index)
MeshReport checkMesh(const vdbi::InterfaceMesh& mesh, bool useKeys = true);

/// @brief True when 6 x the volume in key units equals @a fineVoxels fine voxels of a grid
/// s = keyScale / 2 times finer (a fine voxel is 2 key units wide).
bool volumeEqualsFineVoxels(const LabelReport& label, std::int64_t fineVoxels);

/// @brief Plain face extraction, independent of the library: every coarse face between two
/// different labels a < b becomes two triangles of patch (a, b), normal from a into b.
/// Keys are 2 x the grid point (keyScale 2); points are index coordinates.
vdbi::InterfaceMesh plainInterfaceMesh(const openvdb::Int32Grid& grid);

/// Coarse interface faces per label pair (a < b).
std::map<std::pair<vdbi::Label, vdbi::Label>, std::size_t>
interfaceFacesPerPair(const openvdb::Int32Grid& grid);

/// @brief "" when @a mesh is exactly the plain face extraction of @a grid (each coarse
/// interface face covered by two triangles of the right patch and orientation, and nothing
/// else), else the first difference. Needs keys.
std::string compareWithPlainFaces(const vdbi::InterfaceMesh& mesh,
                                  const openvdb::Int32Grid& grid);

/// @brief Euler characteristic V - E + F - C of the union of the closed voxels of @a label
/// (the cubical complex), counted cell by cell.
std::int64_t voxelSetEuler(const openvdb::Int32Grid& grid, vdbi::Label label);

/// @brief "" when two meshes are identical (points, triangles, patches, keys), byte for byte.
std::string compareMeshes(const vdbi::InterfaceMesh& a, const vdbi::InterfaceMesh& b);

} // namespace vdbi_test
