// SPDX-License-Identifier: Apache-2.0
/// @file support/MeshIntersections.h
/// @brief Independent geometric checks of an interface mesh: triangles that intersect other
/// than at shared edges and vertices, and distances to a triangle set, both through a uniform
/// grid of candidate triangles.
/// @details Predicates are orientation determinants in double precision ("exact enough": a
/// remeshed surface has no exactly degenerate configurations by accident; voxel faces are
/// exact in double). Nothing here uses the library's remeshing code.

#pragma once

#include <vdbi/InterfaceMesh.h>
#include <vdbi/RawPatchDistance.h>

#include <openvdb/Types.h>

#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <unordered_map>
#include <vector>

namespace vdbi_test {

/// @brief The triangles [first, first + count) of a mesh, bucketed by a uniform grid of cubes
/// of side @a cellSize over their bounding boxes.
class TriangleGrid
{
public:
    TriangleGrid(const vdbi::PointArray& points,
                 const vdbi::TriangleArray& triangles, std::size_t first,
                 std::size_t count, double cellSize);

    /// Distance from @a q to the nearest triangle if it is at most @a radius, else a value
    /// larger than @a radius.
    double distanceWithin(const openvdb::Vec3d& q, double radius) const;

    /// Every unordered pair of triangles (indices into the triangle array) whose bounding
    /// boxes share a cell, each pair once.
    template<typename Visit>
    void forEachCandidatePair(Visit&& visit) const;

private:
    using CellKey = std::uint64_t;
    CellKey cellOf(const openvdb::Vec3i& c) const;
    openvdb::Vec3i cellCoord(const openvdb::Vec3d& p) const;

    const vdbi::PointArray& mPoints;
    const vdbi::TriangleArray& mTriangles;
    double mCellSize;
    std::unordered_map<CellKey, std::vector<std::uint32_t>> mCells;
    std::vector<openvdb::Vec3i> mLow, mHigh;   ///< cell range of every triangle (local index)
    std::size_t mFirst;
};

/// @brief Do triangles @a s and @a t (corner indices into @a points) intersect anywhere
/// other than in the corners and edges they share (by index)?
/// @details Disjoint triangles that merely touch count as intersecting; triangles sharing a
/// vertex intersect when they have a common point other than it (their cones at the vertex
/// overlap); triangles sharing an edge intersect when they lie in one plane on the same side
/// of it (a fold). Two triangles with the same three corners always intersect.
bool trianglesIntersect(const vdbi::PointArray& points, const openvdb::Vec3I& s,
                        const openvdb::Vec3I& t);

/// One intersecting pair found by findSelfIntersections().
struct Intersection
{
    std::uint32_t first = 0, second = 0;   ///< triangle indices, first < second
};

/// @brief Every pair of triangles of @a mesh, in the same patch or in different ones, that
/// intersect other than at shared edges and vertices.
/// @param cellSize  grid cell side; about the typical edge length is fastest
/// @param limit     stop after this many
std::vector<Intersection> findSelfIntersections(const vdbi::InterfaceMesh& mesh,
                                                double cellSize, std::size_t limit = 100);

/// Every intersecting pair of findSelfIntersections() (no limit), as a set.
std::set<std::pair<std::uint32_t, std::uint32_t>> intersectingPairs(
    const vdbi::InterfaceMesh& mesh, double cellSize = 1.0);

/// "" when there is no intersection, else a readable description of the first few.
std::string describeIntersections(const vdbi::InterfaceMesh& mesh,
                                  const std::vector<Intersection>& found);

/// Largest distances of a remeshed mesh to its raw extraction, in voxels.
struct Closeness
{
    /// Over every output vertex: distance to the raw patch of the same label pair (for a
    /// vertex on several patches, to the nearest of them).
    double vertexToRaw = 0.0;
    /// Over every voxel face centre (of the coarse faces, and of the fine faces near repaired
    /// places): distance to the output patch of the same label pair. The measure.
    double faceCentreToOutput = 0.0;
    /// The same over every raw triangle's centroid: stricter, since the centroids of the two
    /// halves of a face lie a quarter of a diagonal off its centre, towards its corners.
    double rawToOutput = 0.0;
};

/// The library's measure of a raw triangle's voxel face centre (tested on its own).
using vdbi::voxelFaceCentre;

/// @brief Measures Closeness patch by patch, with points scaled by 1 / @a voxelSize per axis
/// (anisotropic voxels count in voxels along each axis). Distances beyond @a radius voxels
/// are reported as a value above @a radius (not exactly).
/// @pre @a out has the patches of @a raw, in the same order
Closeness measureCloseness(const vdbi::InterfaceMesh& raw, const vdbi::InterfaceMesh& out,
                           const openvdb::Vec3d& voxelSize, double radius = 2.0);

// ---------------------------------------------------------------------------------------

template<typename Visit>
void
TriangleGrid::forEachCandidatePair(Visit&& visit) const
{
    // A pair is visited in the lowest cell (x, then y, then z) of its boxes' overlap.
    for (const auto& [key, list] : mCells) {
        (void)key;
        for (std::size_t i = 0; i < list.size(); ++i) {
            const openvdb::Vec3i &lo0 = mLow[list[i]], &hi0 = mHigh[list[i]];
            for (std::size_t j = i + 1; j < list.size(); ++j) {
                const openvdb::Vec3i &lo1 = mLow[list[j]], &hi1 = mHigh[list[j]];
                openvdb::Vec3i lo;
                bool overlap = true;
                for (int k = 0; k < 3; ++k) {
                    lo[k] = std::max(lo0[k], lo1[k]);
                    overlap = overlap && lo[k] <= std::min(hi0[k], hi1[k]);
                }
                if (!overlap || cellOf(lo) != key) continue;
                visit(std::uint32_t(mFirst + list[i]), std::uint32_t(mFirst + list[j]));
            }
        }
    }
}

} // namespace vdbi_test
