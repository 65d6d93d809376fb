// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/EdgeDiamond.h
/// @brief The shape of the two triangles at an inner edge of a TriMesh, as they are and
/// after a flip of the edge: what the remesher's shape flips compare.

#ifndef VDBI_EDGE_DIAMOND_HAS_BEEN_INCLUDED
#define VDBI_EDGE_DIAMOND_HAS_BEEN_INCLUDED

#include <vdbi/PatchMeshes.h>

#include <algorithm>

namespace vdbi {

/// Cosine of the smallest angle of triangle (a, b, c).
inline double
smallestAngleCos(const TriMesh::Point& a, const TriMesh::Point& b, const TriMesh::Point& c)
{
    const TriMesh::Point ab = (b - a).normalized(), bc = (c - b).normalized(),
                         ca = (a - c).normalized();
    return std::max({-(ab | ca), -(bc | ab), -(ca | bc)});
}

/// The two triangles at an inner edge: the edge p0 -> p1 (halfedge 0), pc the corner
/// opposite it on halfedge 0's side, pd on the other.
struct EdgeDiamond
{
    TriMesh::Point p0, p1, pc, pd;

    EdgeDiamond(const TriMesh& mesh, TriMesh::EdgeHandle e)
    {
        const TriMesh::HalfedgeHandle h0 = mesh.halfedge_handle(e, 0),
                                      h1 = mesh.halfedge_handle(e, 1);
        p0 = mesh.point(mesh.from_vertex_handle(h0));
        p1 = mesh.point(mesh.to_vertex_handle(h0));
        pc = mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(h0)));
        pd = mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(h1)));
    }
    /// Cosine of the smallest angle of the two triangles, as they are and after a flip.
    double smallestCos() const
    {
        return std::max(smallestAngleCos(p0, p1, pc), smallestAngleCos(p1, p0, pd));
    }
    double smallestCosFlipped() const
    {
        return std::max(smallestAngleCos(p0, pd, pc), smallestAngleCos(pd, p1, pc));
    }
};

} // namespace vdbi

#endif // VDBI_EDGE_DIAMOND_HAS_BEEN_INCLUDED
