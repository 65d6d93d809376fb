// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/ReferenceSurface.h
/// @brief The smooth surface a patch is remeshed onto: its extracted staircase smoothed
/// within a bound, with closest-point queries.

#ifndef VDBI_REFERENCE_SURFACE_HAS_BEEN_INCLUDED
#define VDBI_REFERENCE_SURFACE_HAS_BEEN_INCLUDED

#include <vdbi/FeatureCurves.h>
#include <vdbi/InterfaceMesh.h>

#include <openvdb/Types.h>

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace vdbi {

/// @brief Smooths a triangle surface in place, with a bound on how far any point moves.
/// @details Taubin smoothing with the uniform (umbrella) Laplacian: per iteration a shrinking
/// step and an inflating step, so the volume stays; after every step a point farther than
/// @a maxDisplacement from @a original is pulled back onto that bound. This removes the voxel
/// staircase (steps of one voxel) while thin structures keep their thickness: nothing moves
/// more than the bound (ALGORITHM.md §5). Fixed points (the patch boundary, already on the
/// smoothed feature curves) do not move.
/// @param points           [in,out] start and result positions
/// @param original         positions the bound refers to (the extracted surface)
/// @param triangles        the triangles; a free point must be interior (a closed 1-ring)
/// @param fixed            one flag per point: nonzero keeps the point where it is
/// @param iterations       number of Taubin iterations (two Laplacian steps each)
/// @param maxDisplacement  the bound in world units per axis: the semi-axes of an
///                         axis-aligned ellipsoid around the original point (a fraction of
///                         the voxel size, which may differ per axis)
void smoothSurfacePoints(std::vector<openvdb::Vec3d>& points,
                         const std::vector<openvdb::Vec3d>& original,
                         const std::vector<openvdb::Vec3I>& triangles,
                         const std::vector<std::uint8_t>& fixed, int iterations,
                         const openvdb::Vec3d& maxDisplacement);

/// @brief @a p moved back onto the axis-aligned ellipsoid with semi-axes @a bound around
/// @a origin if it lies outside, along the line to @a origin; else @a p.
openvdb::Vec3d clampDisplacement(const openvdb::Vec3d& p, const openvdb::Vec3d& origin,
                                 const openvdb::Vec3d& bound);

/// @brief A triangle surface with closest-point queries.
/// @details A KD-tree (nanoflann) over the vertices finds the nearest few vertices; the
/// closest point is then computed exactly on the triangles around them. That is the exact
/// closest point whenever it lies in a triangle touching one of those vertices, which holds
/// for the well-shaped, dense reference surfaces built from extracted patches.
class ReferenceSurface
{
public:
    struct Hit
    {
        openvdb::Vec3d point;       ///< closest point found
        openvdb::Vec3d normal;      ///< unit normal there, interpolated from the vertices
        std::uint32_t triangle = 0; ///< the triangle it lies in
        openvdb::Vec3d barycentric; ///< of the point in that triangle
    };

    /// @param points     vertex positions
    /// @param triangles  counter-clockwise triangles (the normal follows the orientation)
    ReferenceSurface(std::vector<openvdb::Vec3d> points,
                     std::vector<openvdb::Vec3I> triangles);
    ~ReferenceSurface();
    ReferenceSurface(ReferenceSurface&&) noexcept;
    ReferenceSurface& operator=(ReferenceSurface&&) noexcept;
    ReferenceSurface(const ReferenceSurface&) = delete;
    ReferenceSurface& operator=(const ReferenceSurface&) = delete;

    /// The closest point of the surface to @a query.
    /// @pre the surface has at least one triangle
    Hit closestPoint(const openvdb::Vec3d& query) const;
    /// @brief The closest point to @a query found by walking from triangle @a start: the
    /// triangles around its corners are searched, then around the best one, until the best
    /// stays; after a few steps without settling, the KD-tree search takes over.
    /// @details For a point that moved a little since its last query (remeshing rounds) this
    /// finds the same point as closestPoint() without a tree search.
    Hit closestPointNear(const openvdb::Vec3d& query, std::uint32_t start) const;
    /// A triangle at vertex @a v (for closestPointNear()).
    std::uint32_t triangleAt(std::uint32_t v) const;

    const std::vector<openvdb::Vec3d>& points() const;
    const std::vector<openvdb::Vec3I>& triangles() const;
    /// Unit area-weighted vertex normals.
    const std::vector<openvdb::Vec3d>& vertexNormals() const;

private:
    void finishHit(Hit& hit, const openvdb::Vec3d& barycentric) const;

    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

/// @brief The point of triangle (a, b, c) closest to @a p, with its barycentric coordinates
/// (inline: the remeshing's checks call it hundreds of millions of times).
inline openvdb::Vec3d
closestPointOnTriangle(const openvdb::Vec3d& p, const openvdb::Vec3d& a,
                       const openvdb::Vec3d& b, const openvdb::Vec3d& c,
                       openvdb::Vec3d& bary)
{
    // Voronoi regions of the vertices, then of the edges, else the inside.
    const openvdb::Vec3d ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0) { bary = openvdb::Vec3d(1, 0, 0); return a; }
    const openvdb::Vec3d bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0.0 && d4 <= d3) { bary = openvdb::Vec3d(0, 1, 0); return b; }
    const openvdb::Vec3d cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0.0 && d5 <= d6) { bary = openvdb::Vec3d(0, 0, 1); return c; }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        bary = openvdb::Vec3d(1.0 - v, v, 0.0);
        return a + ab * v;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        bary = openvdb::Vec3d(1.0 - w, 0.0, w);
        return a + ac * w;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        bary = openvdb::Vec3d(0.0, 1.0 - w, w);
        return b + (c - b) * w;
    }
    const double sum = va + vb + vc;
    if (!(sum > 0.0)) {   // degenerate triangle: the nearest of its corners
        const double da = (p - a).lengthSqr(), db = (p - b).lengthSqr(),
                     dc = (p - c).lengthSqr();
        if (da <= db && da <= dc) { bary = openvdb::Vec3d(1, 0, 0); return a; }
        if (db <= dc) { bary = openvdb::Vec3d(0, 1, 0); return b; }
        bary = openvdb::Vec3d(0, 0, 1);
        return c;
    }
    const double v = vb / sum, w = vc / sum;
    bary = openvdb::Vec3d(1.0 - v - w, v, w);
    return a + ab * v + ac * w;
}

/// @brief One patch of an interface mesh in local numbering, with its reference surface.
struct PatchReference
{
    /// InterfaceMesh point index of every local vertex, ascending.
    std::vector<std::uint32_t> rawPoints;
    /// The patch's triangles in local vertex indices, in their extracted order.
    std::vector<openvdb::Vec3I> triangles;
    /// The smoothed surface: local vertices, the boundary ones on the smoothed curves.
    std::unique_ptr<ReferenceSurface> surface;
    /// Nonzero for every local vertex on a feature curve (kept in place by smoothing).
    std::vector<std::uint8_t> onCurve;
    /// Every feature curve on the patch boundary, ascending, with true when the boundary
    /// walked against the triangles' orientation (OpenMesh's boundary halfedges) runs from
    /// the curve's first point to its last.
    std::vector<std::pair<std::uint32_t, bool>> curveDirections;
};

/// @brief The reference surface of patch @a patch (ALGORITHM.md §5): its boundary points on
/// their smoothed feature curves (fixed), the other points smoothed with smoothSurfacePoints()
/// within @a maxDisplacement of the extracted staircase.
/// @pre smoothFeatureCurves() ran on @a curves
/// @throw vdbi::TopologyError if a boundary edge is no feature edge, or the boundary runs
/// both ways along a curve
PatchReference buildPatchReference(const InterfaceMesh& mesh, std::size_t patch,
                                   const FeatureCurves& curves, int iterations,
                                   const openvdb::Vec3d& maxDisplacement);

} // namespace vdbi

#endif // VDBI_REFERENCE_SURFACE_HAS_BEEN_INCLUDED
