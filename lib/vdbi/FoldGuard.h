// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/FoldGuard.h
/// @brief The remesher's guard against folds: no edge collapse, edge flip or vertex move may
/// make the triangles it changes cross each other, or the faces around them, more often than
/// the triangles it replaces did.

#ifndef VDBI_FOLD_GUARD_HAS_BEEN_INCLUDED
#define VDBI_FOLD_GUARD_HAS_BEEN_INCLUDED

#include <vdbi/PatchMeshes.h>
#include <vdbi/TriangleCrossing.h>

#include <initializer_list>
#include <vector>

namespace vdbi {

/// @brief Holds one operation on a mesh (the triangles it makes and the faces across their
/// outer edges) and tells whether it folds more than the faces it replaces.
/// @details Counting crossings is dear: looksUnfolded() comes first, and only the triangles
/// it calls suspect (at a sharp turn, or all of a fan that winds more than once around its
/// centre) are counted. A turn is sharp over 120 degrees, or over 60 for a collapse or flip
/// after the first round off the patch boundary (folds at right-angled creases; FoldGuard.cc
/// says why not everywhere). Keeps its scratch between operations: one per remesher.
class FoldGuard
{
public:
    using Point = TriMesh::Point;
    using VertexHandle = TriMesh::VertexHandle;
    using FaceHandle = TriMesh::FaceHandle;

    explicit FoldGuard(const TriMesh& mesh) : mMesh(mesh) {}

    /// Starts an operation: no new triangles, no neighbours.
    void clear();
    /// A triangle the operation makes.
    void addNew(const CornerTriangle& t) { mNewTriangles.push_back(t); }
    /// The face across the edge of face @a f that avoids @a a and @a b, if any, as the
    /// neighbour of the last new triangle.
    void addAcross(FaceHandle f, VertexHandle a, VertexHandle b);
    /// Face @a f as the neighbour of new triangle @a k.
    void addNeighbour(FaceHandle f, int k);

    /// @brief Do the new triangles, replacing the faces @a replaced, fold through each other
    /// or the faces around more often than @a replaced did?
    /// @param near            the suspect new triangles are counted against the faces with a
    ///                        corner on or next to one of these (other than @a replaced) ...
    /// @param neighboursOnly  ... or against the neighbours only (the millions of collapses
    ///                        of the first round's passes towards halved targets, from
    ///                        the staircase)
    /// @param centre          the vertex every new triangle has (-1: none)
    bool foldsMore(std::initializer_list<VertexHandle> near,
                   const std::vector<FaceHandle>& replaced, int centre, bool neighboursOnly);

    /// @brief Does the fan of @a v cross more of the faces around it, at the current positions,
    /// than it did with every vertex at @a before?
    bool movedIntoFold(VertexHandle v, const std::vector<Point>& before);

    /// @brief How many crossings the fan of @a v has, among its triangles and with the faces
    /// that have a corner within two edges of @a v: every triangle is counted, not only those
    /// at a sharp turn.
    int fanCrossings(VertexHandle v);

    /// Face @a f at the current positions.
    CornerTriangle cornerTriangle(FaceHandle f) const;
    /// Face @a f with every vertex i at @a at[i].
    CornerTriangle cornerTriangle(FaceHandle f, const std::vector<Point>& at) const;

private:
    /// Has a new triangle a corner on the boundary of the mesh?
    bool touchesBoundary() const;
    /// The faces with a corner on or next to one of @a near, other than @a skip, into
    /// mAroundFaces, and as triangles at the current positions into mAroundTriangles.
    void collectAround(std::initializer_list<VertexHandle> near,
                       const std::vector<FaceHandle>& skip);
    template<typename Vertices>
    void collectAroundAll(const Vertices& near, const std::vector<FaceHandle>& skip);

    const TriMesh& mMesh;
    /// The triangles the operation makes and those it replaces, the neighbours of the new
    /// ones (and which new triangle each is the neighbour of), the faces around, the suspects.
    std::vector<CornerTriangle> mNewTriangles, mOldTriangles, mNeighbours, mAroundTriangles;
    std::vector<int> mNeighbourOf;
    std::vector<char> mSuspect;
    std::vector<FaceHandle> mFan, mAroundFaces;
    std::vector<VertexHandle> mRing;   ///< scratch of fanCrossings()
    std::vector<int> mFaceMark;   ///< mMark where a face was met already
    int mMark = 0;
};

} // namespace vdbi

#endif // VDBI_FOLD_GUARD_HAS_BEEN_INCLUDED
