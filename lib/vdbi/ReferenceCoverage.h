// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/ReferenceCoverage.h
/// @brief Which face of a patch being remeshed each fixed reference point is nearest to: what
/// lets every remeshing operation keep the surface close to the reference (ALGORITHM.md §5).

#ifndef VDBI_REFERENCE_COVERAGE_HAS_BEEN_INCLUDED
#define VDBI_REFERENCE_COVERAGE_HAS_BEEN_INCLUDED

#include <vdbi/PatchBoundary.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace vdbi {

/// A triangle by its corner positions.
struct TrianglePoints
{
    TriMesh::Point a, b, c;
};

/// The corner positions of face @a f of @a mesh.
inline TrianglePoints
trianglePoints(const TriMesh& mesh, TriMesh::FaceHandle f)
{
    auto it = mesh.cfv_iter(f);
    const TriMesh::VertexHandle a = *it, b = *++it, c = *++it;
    return {mesh.point(a), mesh.point(b), mesh.point(c)};
}

/// Appends to @a faces those around @a v of @a mesh that it does not list yet.
inline void
appendFacesAround(const TriMesh& mesh, TriMesh::VertexHandle v,
                  std::vector<TriMesh::FaceHandle>& faces)
{
    for (const TriMesh::FaceHandle g : mesh.vf_range(v)) {
        if (std::find(faces.begin(), faces.end(), g) == faces.end()) faces.push_back(g);
    }
}

/// Squared distance from @a p to triangle (a, b, c). Flattened: the library's own copy of
/// closestPointOnTriangle() is exported, so a call to it went through the PLT (the bound
/// checks measure hundreds of millions of distances).
[[gnu::flatten]] inline double
squaredDistanceToTriangle(const TriMesh::Point& p, const TriMesh::Point& a,
                          const TriMesh::Point& b, const TriMesh::Point& c)
{
    openvdb::Vec3d bary;
    return (closestPointOnTriangle(toVec(p), toVec(a), toVec(b), toVec(c), bary) - toVec(p))
        .lengthSqr();
}

/// @brief The reference vertices of a patch off its curves, each covered by (listed at) the
/// face of the patch mesh nearest to it.
/// @details Operations keep the surface within a bound of these fixed points, not of the
/// surface of the step before: a bound against the last step lets tips and thin parts erode
/// a little every round. The lists live in a face property ("f:covered": the first point + 1,
/// 0 for none) and a next-point array (the next + 1 per point), so an operation touches only
/// the points of the faces it changes.
class ReferenceCoverage
{
public:
    using Point = TriMesh::Point;
    using FaceHandle = TriMesh::FaceHandle;

    /// Mesh vertex i was made at reference vertex i: a face at it covers it (at distance 0).
    explicit ReferenceCoverage(RemeshingPatch& patch);
    ~ReferenceCoverage();
    ReferenceCoverage(const ReferenceCoverage&) = delete;
    ReferenceCoverage& operator=(const ReferenceCoverage&) = delete;

    /// @brief After an operation changed @a changed (some perhaps deleted): a point whose
    /// nearest point on its face is no longer inside it goes to the nearest of @a around
    /// (the first of equals).
    void recover(const std::vector<FaceHandle>& changed, const std::vector<FaceHandle>& around)
    {
        mReleased.clear();
        for (const FaceHandle f : changed) releaseOutside(f);
        coverByNearest(around);
    }
    /// Moves the points of @a f whose nearest point on it is not inside it to released().
    void releaseOutside(FaceHandle f);
    /// The points the last releaseOutside() calls (since clearReleased()) let go.
    bool hasReleased() const { return !mReleased.empty(); }
    void clearReleased() { mReleased.clear(); }
    /// Every released point covered by the nearest of @a faces (the first of equals).
    void coverByNearest(const std::vector<FaceHandle>& faces);

    /// Does @a f cover any point?
    bool coversAny(FaceHandle f) const { return mMesh.property(mFirst, f) != 0; }
    /// Is every point @a f covers within sqrt(@a limit2) of triangle @a t?
    bool allWithin(FaceHandle f, const TrianglePoints& t, double limit2) const;
    /// @brief Is every point covered by @a faces within sqrt(@a limit2) of one of
    /// @a triangles (the surface replacing them), or no farther from them than from its own
    /// face as it was (at @a before, the current positions if null)?
    /// Only the points of the first @a checkCount faces are looked at (all by default).
    bool keepsCovered(const std::vector<FaceHandle>& faces,
                      const std::vector<TrianglePoints>& triangles, double limit2,
                      const std::vector<Point>* before = nullptr,
                      std::size_t checkCount = std::size_t(-1)) const;

private:
    TriMesh& mMesh;
    const std::vector<openvdb::Vec3d>& mPoints;
    OpenMesh::FPropHandleT<int> mFirst;
    std::vector<int> mNext;
    std::vector<int> mReleased;             ///< points to cover again
    std::vector<TrianglePoints> mTriangles;   ///< scratch: the faces coverByNearest() looks at
    std::vector<Point> mUnitNormals;        ///< scratch: their unit normals
};

} // namespace vdbi

#endif // VDBI_REFERENCE_COVERAGE_HAS_BEEN_INCLUDED
