// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/PatchBoundary.h
/// @brief A patch made ready for remeshing: its extracted boundary replaced by the shared
/// feature curve samples, which are locked from then on (ALGORITHM.md §5).

#ifndef VDBI_PATCH_BOUNDARY_HAS_BEEN_INCLUDED
#define VDBI_PATCH_BOUNDARY_HAS_BEEN_INCLUDED

#include <vdbi/FeatureCurves.h>
#include <vdbi/InterfaceMesh.h>
#include <vdbi/PatchMeshes.h>
#include <vdbi/ReferenceSurface.h>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace vdbi {

/// One patch after remeshing. Triangle corners below the sample count are sample ids (shared
/// boundary vertices); the others are sampleCount + an index into innerPoints.
struct PatchResult
{
    std::vector<openvdb::Vec3d> innerPoints;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    /// Per inner point, its distance to the reference surface (world units): a point off it
    /// (one projection refused, a collapse or smoothing move made last) may lie far from the
    /// voxel faces. Empty unless exportMesh() measured them.
    std::vector<double> referenceDistances;
};

/// @brief A patch as an OpenMesh mesh on its reference surface, bounded by the feature curve
/// samples, with what every remeshing operation needs to know of a vertex.
/// @details Vertex properties: "v:sample" (the global sample id of a locked boundary vertex,
/// else -1), "v:refnormal" (the reference normal at the vertex), "v:anchor" (the reference
/// normal where the vertex was made: relaxation keeps a vertex where the normal stays close
/// to it, so no vertex drifts off a crease, corner or tip over many small moves) and
/// "v:reftri" (the reference triangle of the last projection, where the next one starts).
class RemeshingPatch
{
public:
    using Point = TriMesh::Point;
    using VertexHandle = TriMesh::VertexHandle;
    using EdgeHandle = TriMesh::EdgeHandle;
    using FaceHandle = TriMesh::FaceHandle;

    /// @param patch       the patch's entry in the mesh, for messages
    /// @param patchIndex  its index in the mesh (the owner of some inner edges, see
    ///                    mayJoinLocked())
    RemeshingPatch(const InterfacePatch& patch, std::uint32_t patchIndex,
                   const PatchReference& reference, const FeatureCurves& curves);

    /// @brief Builds the mesh on the reference surface and replaces every boundary curve by
    /// its samples: a strip of triangles zips the extracted boundary to the sample polyline
    /// (a fan around a new inner vertex when the curve has a single segment). Afterwards no
    /// inner edge joins two locked vertices (it could coincide with a curve segment or with
    /// an inner edge of another patch): such edges are split. Remeshing may make such an
    /// edge again where mayJoinLocked() allows it.
    /// @throw vdbi::TopologyError if the patch does not fit its feature curves (a bug)
    void attachCurveSamples();

    /// Is the boundary exactly the curve samples' segments, with every inner edge between two
    /// locked vertices one that mayJoinLocked() allows?
    bool hasExpectedBoundary() const;
    /// The live triangles, vertices numbered as PatchResult says; its referenceDistances only
    /// if @a measureReference (a query per point: millions on the frog's extracted patches).
    PatchResult exportMesh(bool measureReference = false) const;
    /// "remeshing patch (a, b)", for messages.
    std::string where() const;

    TriMesh& mesh() { return mMesh; }
    const TriMesh& mesh() const { return mMesh; }
    const ReferenceSurface& reference() const { return *mReference.surface; }
    /// Is reference vertex @a i on a feature curve? (Mesh vertex i is made at reference
    /// vertex i.)
    bool isCurvePoint(std::size_t i) const { return mReference.onCurve[i] != 0; }

    bool isLocked(VertexHandle v) const { return mMesh.property(mSample, v) >= 0; }
    /// @brief May an inner edge of this patch join locked vertices @a u and @a v?
    /// @details Only if this patch is their chordOwner() (ChordOwners.h): every patch asks
    /// the same question of the same data, so at most one patch makes the edge, and it is no
    /// curve segment (the segments at an inner sample are boundary edges of every patch on
    /// its curve). Never between two junctions (a single-segment curve elsewhere may join
    /// them). Without such edges a vertex next to a run of samples could not go, leaving
    /// short edges at the curves.
    bool mayJoinLocked(VertexHandle u, VertexHandle v) const;
    /// Not deleted, not locked, not on the boundary: a vertex remeshing may move or remove.
    bool isFree(VertexHandle v) const
    {
        return !mMesh.status(v).deleted() && !isLocked(v) && !mMesh.is_boundary(v);
    }
    const Point& refNormal(VertexHandle v) const { return mMesh.property(mRefNormal, v); }
    Point& refNormal(VertexHandle v) { return mMesh.property(mRefNormal, v); }
    const Point& anchor(VertexHandle v) const { return mMesh.property(mAnchor, v); }
    std::uint32_t& refTriangle(VertexHandle v) { return mMesh.property(mRefTriangle, v); }
    /// The mean of the neighbours of @a v (which has some).
    Point neighbourMean(VertexHandle v) const
    {
        Point sum(0, 0, 0);
        int count = 0;
        for (const VertexHandle w : mMesh.vv_range(v)) {
            sum += mMesh.point(w);
            ++count;
        }
        return sum / double(count);
    }

    /// @brief Does triangle (a, b, c) face the way the reference surface does at each of its
    /// corners? A triangle that folds over, or spans a thin part from one side to the
    /// other, does not.
    bool agrees(const Point& a, const Point& b, const Point& c, VertexHandle va,
                VertexHandle vb, VertexHandle vc) const
    {
        const Point n = (b - a) % (c - a);
        return (n | refNormal(va)) > 0.0 && (n | refNormal(vb)) > 0.0
            && (n | refNormal(vc)) > 0.0;
    }
    bool agrees(FaceHandle f) const
    {
        auto it = mMesh.cfv_iter(f);
        const VertexHandle a = *it, b = *++it, c = *++it;
        return agrees(mMesh.point(a), mMesh.point(b), mMesh.point(c), a, b, c);
    }

    /// A new free vertex at @a p with reference normal (and anchor) @a normal.
    VertexHandle addInnerVertex(const Point& p, const Point& normal);
    /// Splits @a e at its midpoint; the new vertex starts its projections where the first
    /// end's last one ended.
    VertexHandle splitEdge(EdgeHandle e);
    /// @brief Would the midpoint splitEdge() makes on @a e stay off the reference surface for
    /// good?
    /// @details An edge across a bend much tighter than the target has its midpoint far from
    /// the reference (farther than sqrt(@a deviation2)). Where the nearest reference point's
    /// normal turns from the midpoint's by more than the crease angle (@a creaseCos),
    /// projection refuses the move every round, and a relaxed position is stepped back: the
    /// vertex stays on the chord (frog at 4 voxels: 1.39 voxels from the raw faces; menger
    /// 1.63). Such an edge is better left long, as it is.
    bool wouldStrandMidpoint(EdgeHandle e, double deviation2, double creaseCos) const;

private:
    /// The reference normal splitEdge() gives the midpoint of @a a and @a b.
    Point midpointNormal(VertexHandle a, VertexHandle b) const;
    void buildMesh();
    void separateLockedVertices();
    void zipCurve(std::uint32_t curveIndex, bool forward);
    void relaxZippedPoints();

    const InterfacePatch& mPatch;
    const PatchReference& mReference;
    const FeatureCurves& mCurves;
    std::uint32_t mPatchIndex;

    TriMesh mMesh;
    OpenMesh::VPropHandleT<std::int64_t> mSample;
    OpenMesh::VPropHandleT<Point> mRefNormal;
    OpenMesh::VPropHandleT<Point> mAnchor;
    OpenMesh::VPropHandleT<std::uint32_t> mRefTriangle;
    /// The boundary the samples give, as sorted (from, to) sample id pairs.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> mExpectedBoundary;
    /// The extracted boundary points zipCurve() made inner vertices.
    std::vector<VertexHandle> mZippedPoints;
};

} // namespace vdbi

#endif // VDBI_PATCH_BOUNDARY_HAS_BEEN_INCLUDED
