// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/EdgeCollapse.h
/// @brief The halfedge collapse of a TriMesh, its link-condition test and the compaction
/// afterwards, compiled here.
/// @details The same decisions and the same connectivity edits as OpenMesh's
/// TriConnectivity::is_collapse_ok() and PolyConnectivity::collapse(), made through the
/// kernel's header-inline accessors. Why not call those: Debian builds libOpenMeshCore with
/// assertions on, and every status or handle access inside it builds and compares a type-name
/// std::string or calls out of line; the two calls and valence() took about a quarter of the
/// remeshing's instructions, garbage collection another tenth on voxel art.
/// TestEdgeCollapse compares both, edit by edit, on random meshes.

#ifndef VDBI_EDGE_COLLAPSE_HAS_BEEN_INCLUDED
#define VDBI_EDGE_COLLAPSE_HAS_BEEN_INCLUDED

#include <vdbi/PatchMeshes.h>

#include <array>

namespace vdbi {

namespace edge_collapse_detail {

/// Calls @a f(h) for every halfedge leaving @a v, clockwise from its stored one (the order of
/// OpenMesh's vertex circulators); stops early when @a f returns true.
template<typename F>
inline void
forEachOutgoing(const TriMesh& mesh, TriMesh::VertexHandle v, F&& f)
{
    const TriMesh::HalfedgeHandle start = mesh.halfedge_handle(v);
    if (!start.is_valid()) return;
    TriMesh::HalfedgeHandle h = start;
    do {
        if (f(h)) return;
        h = mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(h));
    } while (h != start);
}

/// A boundary halfedge leaving @a v becomes its stored one, if there is any (the first
/// clockwise), as OpenMesh keeps it: is_boundary(v) looks at the stored one only.
inline void
adjustOutgoingHalfedge(TriMesh& mesh, TriMesh::VertexHandle v)
{
    forEachOutgoing(mesh, v, [&](TriMesh::HalfedgeHandle h) {
        if (!mesh.is_boundary(h)) return false;
        mesh.set_halfedge_handle(v, h);
        return true;
    });
}

/// Removes the face of the two-halfedge loop at @a h0 (left by a collapse): its halfedge
/// @a h0 and the opposite one go, the other edge takes their place.
inline void
collapseLoop(TriMesh& mesh, TriMesh::HalfedgeHandle h0)
{
    const TriMesh::HalfedgeHandle h1 = mesh.next_halfedge_handle(h0);
    const TriMesh::HalfedgeHandle o0 = mesh.opposite_halfedge_handle(h0);
    const TriMesh::HalfedgeHandle o1 = mesh.opposite_halfedge_handle(h1);
    const TriMesh::VertexHandle v0 = mesh.to_vertex_handle(h0), v1 = mesh.to_vertex_handle(h1);
    const TriMesh::FaceHandle fh = mesh.face_handle(h0), fo = mesh.face_handle(o0);

    mesh.set_next_halfedge_handle(h1, mesh.next_halfedge_handle(o0));
    mesh.set_next_halfedge_handle(mesh.prev_halfedge_handle(o0), h1);
    mesh.set_face_handle(h1, fo);
    mesh.set_halfedge_handle(v0, h1);
    adjustOutgoingHalfedge(mesh, v0);
    mesh.set_halfedge_handle(v1, o1);
    adjustOutgoingHalfedge(mesh, v1);
    if (fo.is_valid() && mesh.halfedge_handle(fo) == o0) mesh.set_halfedge_handle(fo, h1);

    if (fh.is_valid()) {
        mesh.set_halfedge_handle(fh, TriMesh::InvalidHalfedgeHandle);
        mesh.status(fh).set_deleted(true);
    }
    mesh.status(mesh.edge_handle(h0)).set_deleted(true);
    if (mesh.has_halfedge_status()) {
        mesh.status(h0).set_deleted(true);
        mesh.status(o0).set_deleted(true);
    }
}

} // namespace edge_collapse_detail

/// Number of edges at @a v (OpenMesh's valence(), inline).
inline int
vertexValence(const TriMesh& mesh, TriMesh::VertexHandle v)
{
    int count = 0;
    edge_collapse_detail::forEachOutgoing(mesh, v, [&](TriMesh::HalfedgeHandle) {
        ++count;
        return false;
    });
    return count;
}

/// Does collapsing @a h (its from-vertex into its to-vertex) keep the mesh a 2-manifold?
/// The link condition: the ends' only common neighbours are the corners opposite the edge;
/// besides, neither triangle at the edge may have its other two edges on the boundary, and an
/// inner edge may not join two boundary vertices.
inline bool
isCollapseOk(const TriMesh& mesh, TriMesh::HalfedgeHandle h)
{
    using VertexHandle = TriMesh::VertexHandle;
    using HalfedgeHandle = TriMesh::HalfedgeHandle;
    if (mesh.status(mesh.edge_handle(h)).deleted()) return false;
    const HalfedgeHandle o = mesh.opposite_halfedge_handle(h);
    const VertexHandle v0 = mesh.to_vertex_handle(o), v1 = mesh.to_vertex_handle(h);
    if (mesh.status(v0).deleted() || mesh.status(v1).deleted()) return false;

    // The corner opposite the edge on each side (none on a boundary side).
    VertexHandle corner[2];
    const HalfedgeHandle sides[2] = {h, o};
    for (int k = 0; k < 2; ++k) {
        if (mesh.is_boundary(sides[k])) continue;
        const HalfedgeHandle h1 = mesh.next_halfedge_handle(sides[k]);
        const HalfedgeHandle h2 = mesh.next_halfedge_handle(h1);
        corner[k] = mesh.to_vertex_handle(h1);
        if (mesh.is_boundary(mesh.opposite_halfedge_handle(h1))
            && mesh.is_boundary(mesh.opposite_halfedge_handle(h2))) {
            return false;
        }
    }
    if (corner[0] == corner[1]) return false;

    bool sharesOther = false;
    edge_collapse_detail::forEachOutgoing(mesh, v0, [&](HalfedgeHandle a) {
        const VertexHandle w = mesh.to_vertex_handle(a);
        if (w == corner[0] || w == corner[1]) return false;
        edge_collapse_detail::forEachOutgoing(mesh, v1, [&](HalfedgeHandle b) {
            sharesOther = mesh.to_vertex_handle(b) == w;
            return sharesOther;
        });
        return sharesOther;
    });
    if (sharesOther) return false;

    return !(mesh.is_boundary(v0) && mesh.is_boundary(v1) && !mesh.is_boundary(h)
             && !mesh.is_boundary(o));
}

/// Collapses @a h: its from-vertex is deleted and its edges end at the to-vertex; the
/// triangles at the edge go (marked deleted, as OpenMesh does, until garbage collection).
/// @pre isCollapseOk(mesh, h)
inline void
collapseEdge(TriMesh& mesh, TriMesh::HalfedgeHandle h)
{
    using HalfedgeHandle = TriMesh::HalfedgeHandle;
    const HalfedgeHandle hn = mesh.next_halfedge_handle(h), hp = mesh.prev_halfedge_handle(h);
    const HalfedgeHandle o = mesh.opposite_halfedge_handle(h);
    const HalfedgeHandle on = mesh.next_halfedge_handle(o), op = mesh.prev_halfedge_handle(o);
    const TriMesh::FaceHandle fh = mesh.face_handle(h), fo = mesh.face_handle(o);
    const TriMesh::VertexHandle kept = mesh.to_vertex_handle(h), gone = mesh.to_vertex_handle(o);

    // Every halfedge into the vertex that goes now ends at the one kept.
    edge_collapse_detail::forEachOutgoing(mesh, gone, [&](HalfedgeHandle out) {
        mesh.set_vertex_handle(mesh.opposite_halfedge_handle(out), kept);
        return false;
    });
    mesh.set_next_halfedge_handle(hp, hn);
    mesh.set_next_halfedge_handle(op, on);
    if (fh.is_valid()) mesh.set_halfedge_handle(fh, hn);
    if (fo.is_valid()) mesh.set_halfedge_handle(fo, on);
    if (mesh.halfedge_handle(kept) == o) mesh.set_halfedge_handle(kept, hn);
    edge_collapse_detail::adjustOutgoingHalfedge(mesh, kept);
    mesh.set_isolated(gone);

    mesh.status(mesh.edge_handle(h)).set_deleted(true);
    mesh.status(gone).set_deleted(true);
    if (mesh.has_halfedge_status()) {
        mesh.status(h).set_deleted(true);
        mesh.status(o).set_deleted(true);
    }
    // The triangles at the edge are two-halfedge loops now.
    if (mesh.next_halfedge_handle(mesh.next_halfedge_handle(hn)) == hn) {
        edge_collapse_detail::collapseLoop(mesh, mesh.next_halfedge_handle(hn));
    }
    if (mesh.next_halfedge_handle(mesh.next_halfedge_handle(on)) == on) {
        edge_collapse_detail::collapseLoop(mesh, on);
    }
}

/// @brief Removes the deleted elements (OpenMesh's garbage_collection()), instantiated here
/// from OpenMesh's header template: with no handles to update it is a container type of its
/// own, so the library's copy with assertions is not the one called.
inline void
collectGarbage(TriMesh& mesh)
{
    std::array<TriMesh::VertexHandle*, 0> vertices;
    std::array<TriMesh::HalfedgeHandle*, 0> halfedges;
    std::array<TriMesh::FaceHandle*, 0> faces;
    mesh.garbage_collection(vertices, halfedges, faces);
}

} // namespace vdbi

#endif // VDBI_EDGE_COLLAPSE_HAS_BEEN_INCLUDED
