// SPDX-License-Identifier: Apache-2.0

#include <vdbi/IsotropicRemeshing.h>

#include <vdbi/EdgeCollapse.h>
#include <vdbi/EdgeDiamond.h>
#include <vdbi/FoldGuard.h>
#include <vdbi/ReferenceCoverage.h>
#include <vdbi/SharpFanSmoothing.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace vdbi {

namespace {

using Point = TriMesh::Point;
using VertexHandle = TriMesh::VertexHandle;
using HalfedgeHandle = TriMesh::HalfedgeHandle;
using EdgeHandle = TriMesh::EdgeHandle;
using FaceHandle = TriMesh::FaceHandle;

/// The rounds on one patch; holds the state of a round (valences, old positions) and the
/// reference points every face covers (ReferenceCoverage).
class IsotropicRemesher
{
public:
    IsotropicRemesher(RemeshingPatch& patch, const RemeshSettings& settings);

    void moveOffChords();
    void splitLongEdges();
    /// Collapses edges shorter than 4/5 of @a target (not the target of the settings in the
    /// first round's coarsening passes).
    /// @param neighboursOnly  test the new fan for crossings with the faces across its edges
    ///                        only (the passes towards the halved targets, from the
    ///                        staircase, have millions)
    void collapseShortEdges(double target, bool neighboursOnly);
    void equalizeValences();
    void removeCaps();
    void flipSharpTriangles();
    void tangentialRelaxation();
    void projectToReference();
    /// The reference points every face covers, for the passes after the rounds.
    ReferenceCoverage& coverage() { return mCoverage; }

private:
    bool isCollapseAllowed(HalfedgeHandle h, double target, bool toMidpoint, Point& position);
    bool isFlipAllowed(EdgeHandle e);
    void collapseEdge(HalfedgeHandle h, const Point& position);
    void flipEdge(EdgeHandle e);
    VertexHandle splitEdge(EdgeHandle e);

    TrianglePoints triangle(FaceHandle f) const { return trianglePoints(mMesh, f); }
    /// @brief Is every reference point covered by @a faces within the deviation bound of one
    /// of @a triangles, or no farther from them than from its own face as it was (at
    /// @a before, the current positions if null)? See ReferenceCoverage::keepsCovered().
    bool keepsCovered(const std::vector<FaceHandle>& faces,
                      const std::vector<TrianglePoints>& triangles,
                      const std::vector<Point>* before = nullptr,
                      std::size_t checkCount = std::size_t(-1)) const
    {
        return mCoverage.keepsCovered(faces, triangles, mSettings.deviation2, before, checkCount);
    }

    bool isLocked(VertexHandle v) const { return mPatch.isLocked(v); }
    bool isFree(VertexHandle v) const { return mPatch.isFree(v); }
    const Point& refNormal(VertexHandle v) const { return mPatch.refNormal(v); }
    bool agrees(const Point& a, const Point& b, const Point& c, VertexHandle va,
                VertexHandle vb, VertexHandle vc) const
    {
        return mPatch.agrees(a, b, c, va, vb, vc);
    }
    bool agrees(FaceHandle f) const { return mPatch.agrees(f); }

    int targetValence(VertexHandle v) const { return mMesh.is_boundary(v) ? 4 : 6; }
    int minValence(VertexHandle v) const { return mMesh.is_boundary(v) ? 2 : 3; }
    int valence(VertexHandle v) const
    {
        return mValence.empty() ? vertexValence(mMesh, v) : mValence[v.idx()];
    }
    void countValences()
    {
        mValence.assign(mMesh.n_vertices(), 0);
        for (const VertexHandle v : mMesh.vertices()) {
            if (!mMesh.status(v).deleted()) mValence[v.idx()] = vertexValence(mMesh, v);
        }
    }
    /// Smallest cosine between the reference normal at @a v and at its neighbours.
    double flatness(VertexHandle v) const
    {
        double f = 1.0;
        for (const VertexHandle w : mMesh.vv_range(v)) f = std::min(f, refNormal(v) | refNormal(w));
        return f;
    }

    RemeshingPatch& mPatch;
    TriMesh& mMesh;
    const RemeshSettings& mSettings;
    std::vector<Point> mPrevious;   ///< positions before relaxation
    /// Valence of every vertex, kept up to date during the collapse and flip passes.
    std::vector<int> mValence;
    /// The reference points every face covers: the deviation bound is kept against them.
    ReferenceCoverage mCoverage;
    std::vector<FaceHandle> mChanged;        ///< scratch: faces an operation changed
    std::vector<FaceHandle> mFaces;          ///< scratch: faces around an operation
    std::vector<TrianglePoints> mTriangles;   ///< scratch: the triangles replacing them
    std::vector<FaceHandle> mRemovedFaces;    ///< scratch: faces a collapse removes
    std::vector<FaceHandle> mUnchangedFaces;  ///< scratch: faces a collapse keeps
    std::vector<TrianglePoints> mUnchangedTriangles;   ///< scratch: their triangles
    FoldGuard mFolds;
    /// The collapses towards the halved targets test for folds against the faces across the
    /// fan's edges only (FoldGuard::foldsMore()).
    bool mNeighboursOnly = false;
};

IsotropicRemesher::IsotropicRemesher(RemeshingPatch& patch, const RemeshSettings& settings)
    : mPatch(patch), mMesh(patch.mesh()), mSettings(settings), mCoverage(patch),
      mFolds(patch.mesh())
{
}

VertexHandle
IsotropicRemesher::splitEdge(EdgeHandle e)
{
    // The midpoint changes no geometry: points go to the nearest of the four faces.
    mChanged.clear();
    for (int k = 0; k < 2; ++k) {
        const FaceHandle f = mMesh.face_handle(mMesh.halfedge_handle(e, k));
        if (f.is_valid()) mChanged.push_back(f);
    }
    const VertexHandle m = mPatch.splitEdge(e);
    mFaces.assign(mMesh.vf_begin(m), mMesh.vf_end(m));
    mCoverage.recover(mChanged, mFaces);
    return m;
}

void
IsotropicRemesher::flipEdge(EdgeHandle e)
{
    mMesh.flip(e);
    mFaces.clear();
    for (int k = 0; k < 2; ++k) mFaces.push_back(mMesh.face_handle(mMesh.halfedge_handle(e, k)));
    mCoverage.recover(mFaces, mFaces);
}

void
IsotropicRemesher::collapseEdge(HalfedgeHandle h, const Point& position)
{
    const VertexHandle gone = mMesh.from_vertex_handle(h), kept = mMesh.to_vertex_handle(h);
    mChanged.assign(mMesh.vf_begin(gone), mMesh.vf_end(gone));
    if (position != mMesh.point(kept)) {
        mChanged.insert(mChanged.end(), mMesh.vf_begin(kept), mMesh.vf_end(kept));
    }
    vdbi::collapseEdge(mMesh, h);
    mMesh.set_point(kept, position);
    mFaces.assign(mMesh.vf_begin(kept), mMesh.vf_end(kept));
    mCoverage.recover(mChanged, mFaces);
}

void
IsotropicRemesher::moveOffChords()
{
    // A free vertex of a triangle without area (the centre of a split voxel face, on the
    // chord between two curve samples) goes to the mean of its neighbours, where all its
    // triangles have area and face the way of its reference normal. The faces are looked at
    // once each; a move makes no triangle without area, so a vertex is checked again only
    // where such a triangle was found.
    std::vector<VertexHandle> candidates;
    for (const FaceHandle f : mMesh.faces()) {
        const TrianglePoints t = triangle(f);
        if (!hasNoArea(t.a, t.b, t.c)) continue;
        for (const VertexHandle v : mMesh.fv_range(f)) if (isFree(v)) candidates.push_back(v);
    }
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    for (const VertexHandle v : candidates) {
        bool flat = false;
        for (const FaceHandle f : mMesh.vf_range(v)) {
            const TrianglePoints t = triangle(f);
            flat = flat || hasNoArea(t.a, t.b, t.c);
        }
        if (!flat) continue;
        const Point p = mMesh.point(v), mean = mPatch.neighbourMean(v);
        auto fine = [&](const Point& q) {
            for (const HalfedgeHandle h : mMesh.voh_range(v)) {
                if (!mMesh.face_handle(h).is_valid()) continue;
                const Point& b = mMesh.point(mMesh.to_vertex_handle(h));
                const Point& c =
                    mMesh.point(mMesh.to_vertex_handle(mMesh.next_halfedge_handle(h)));
                // A triangle turned over already may stay so (the rounds unfold it); one
                // without area must come to face the right way.
                const bool turned =
                    !hasNoArea(p, b, c) && (((b - p) % (c - p)) | refNormal(v)) < 0.0;
                if (hasNoArea(q, b, c)
                    || (!turned && (((b - q) % (c - q)) | refNormal(v)) <= 0.0)) {
                    return false;
                }
            }
            return true;
        };
        // Part of the way where the whole way turns a triangle of a crumpled fan over.
        for (const double step : {1.0, 0.5, 0.25, 0.125}) {
            const Point q = p + (mean - p) * step;
            if (fine(q)) {
                mMesh.set_point(v, q);
                break;
            }
        }
    }
}

void
IsotropicRemesher::splitLongEdges()
{
    // Boundary edges are the curve samples' segments: never split. Nor are edges whose
    // midpoint would stay off the reference for good.
    bool changed = true;
    for (int pass = 0; changed && pass < 10; ++pass) {
        changed = false;
        const std::size_t count = mMesh.n_edges();
        for (std::size_t i = 0; i < count; ++i) {
            const EdgeHandle e{int(i)};
            if (mMesh.status(e).deleted() || mMesh.is_boundary(e)) continue;
            const HalfedgeHandle h = mMesh.halfedge_handle(e, 0);
            const Point d = mMesh.point(mMesh.to_vertex_handle(h))
                - mMesh.point(mMesh.from_vertex_handle(h));
            if (d.sqrnorm() <= mSettings.high2
                || mPatch.wouldStrandMidpoint(e, mSettings.deviation2, mSettings.creaseCos)) {
                continue;
            }
            splitEdge(e);
            changed = true;
        }
    }
}

bool
IsotropicRemesher::isCollapseAllowed(HalfedgeHandle h, double target, bool toMidpoint,
                                     Point& position)
{
    const VertexHandle v0 = mMesh.from_vertex_handle(h), v1 = mMesh.to_vertex_handle(h);
    if (!isFree(v0)) return false;   // boundary (sample) vertices never go
    const Point &p0 = mMesh.point(v0), &p1 = mMesh.point(v1);
    const bool moves = toMidpoint && isFree(v1);
    position = moves ? (p0 + p1) * 0.5 : p1;
    // An edge under half the target is out of the range the result is judged by (0.5 to
    // 1.5 x target): it may go even where that makes edges up to 1.5 x target, which the
    // next round splits (a needle next to long edges otherwise stays).
    const double high2 = (p1 - p0).sqrnorm() < 0.25 * target * target
        ? 2.25 * target * target : 16.0 / 9.0 * target * target;
    const VertexHandle vl = mMesh.to_vertex_handle(mMesh.next_halfedge_handle(h));
    const VertexHandle vr = mMesh.to_vertex_handle(
        mMesh.next_halfedge_handle(mMesh.opposite_halfedge_handle(h)));
    // No edge longer than the split limit, no inner edge between two locked vertices that
    // another patch may make too. A vertex with three locked neighbours only stays: it is
    // the centre of a fan filling a boundary loop of three, without it two patches on the
    // same loop would become the same triangle.
    bool lockedRing = valence(v0) == 3;
    for (const VertexHandle w : mMesh.vv_range(v0)) {
        lockedRing = lockedRing && isLocked(w);
        if (w == v1 || w == vl || w == vr) continue;
        if (isLocked(v1) && isLocked(w) && !mPatch.mayJoinLocked(v1, w)) return false;
        if ((mMesh.point(w) - position).sqrnorm() > high2) return false;
    }
    if (lockedRing) return false;
    if (moves) {
        for (const VertexHandle w : mMesh.vv_range(v1)) {
            if (w != v0 && (mMesh.point(w) - position).sqrnorm() > high2) return false;
        }
    }
    if (!isCollapseOk(mMesh, h)) return false;   // link condition: stays a 2-manifold
    // Keep every vertex at valence >= 3 inside (2 on the boundary): no degenerate fans, and a
    // closed component stops at a tetrahedron.
    if (valence(vl) - 1 < minValence(vl)) return false;
    if (valence(vr) - 1 < minValence(vr)) return false;
    if (valence(v1) + valence(v0) - 4 < minValence(v1)) return false;

    // No triangle may turn over or collapse, and the reference points the changed faces
    // cover must stay close to the new surface. Turning is judged against the triangle's own
    // old normal, not the reference normals: those vary over the smoothed staircase by more
    // than a triangle of two voxels does, and refused most collapses of short edges.
    mFaces.clear();
    mTriangles.clear();
    mRemovedFaces.clear();
    mUnchangedFaces.clear();
    mUnchangedTriangles.clear();
    for (const VertexHandle centre : {v0, v1}) {
        for (const FaceHandle f : mMesh.vf_range(centre)) {
            auto it = mMesh.cfv_iter(f);
            VertexHandle c[3] = {*it, *++it, *++it};
            int ends = 0;
            for (int k = 0; k < 3; ++k) ends += (c[k] == v0 || c[k] == v1);
            if (centre == v1 && ends == 2) continue;   // met already around v0
            if (ends == 2) {   // removed with the edge
                mRemovedFaces.push_back(f);
                continue;
            }
            Point p[3];
            for (int k = 0; k < 3; ++k) {
                p[k] = (c[k] == v0 || c[k] == v1) ? position : mMesh.point(c[k]);
            }
            if (centre == v1 && !moves) {   // stays as it is
                mUnchangedFaces.push_back(f);
                mUnchangedTriangles.push_back({p[0], p[1], p[2]});
                continue;
            }
            if (hasNoArea(p[0], p[1], p[2])) return false;
            mFaces.push_back(f);
            mTriangles.push_back({p[0], p[1], p[2]});
            if (!agrees(f)) continue;   // was folded already: may unfold
            const Point before = (mMesh.point(c[1]) - mMesh.point(c[0]))
                % (mMesh.point(c[2]) - mMesh.point(c[0]));
            if ((before | ((p[1] - p[0]) % (p[2] - p[0]))) <= 0.0) return false;
        }
    }
    // Face k becomes triangle k, which keepsCovered() tries first for its points; the removed
    // faces and the unchanged triangles come after.
    const std::size_t changedCount = mFaces.size();
    mFaces.insert(mFaces.end(), mRemovedFaces.begin(), mRemovedFaces.end());
    mTriangles.insert(mTriangles.end(), mUnchangedTriangles.begin(), mUnchangedTriangles.end());
    if (!keepsCovered(mFaces, mTriangles)) return false;

    // Last, as the dearest: v1's new fan (the changed faces and those that stay) folds
    // through no more triangles than the faces it replaces did.
    mFolds.clear();
    for (std::size_t k = 0; k < changedCount; ++k) {
        int id[3], i = 0;
        for (const VertexHandle c : mMesh.fv_range(mFaces[k])) id[i++] = (c == v0 ? v1 : c).idx();
        const TrianglePoints& t = mTriangles[k];
        mFolds.addNew(CornerTriangle(t.a, t.b, t.c, id[0], id[1], id[2]));
        mFolds.addAcross(mFaces[k], v0, v1);
    }
    for (const FaceHandle f : mUnchangedFaces) {
        mFolds.addNew(mFolds.cornerTriangle(f));
        mFolds.addAcross(f, v0, v1);
    }
    mFaces.insert(mFaces.end(), mUnchangedFaces.begin(), mUnchangedFaces.end());
    return !mFolds.foldsMore({v0, v1}, mFaces, v1.idx(), mNeighboursOnly);
}

void
IsotropicRemesher::collapseShortEdges(double target, bool neighboursOnly)
{
    mNeighboursOnly = neighboursOnly;
    const double low2 = 0.64 * target * target;
    countValences();
    std::size_t collapses = 0;
    const std::size_t count = mMesh.n_edges();
    for (std::size_t i = 0; i < count; ++i) {
        const EdgeHandle e{int(i)};
        if (mMesh.status(e).deleted()) continue;
        const HalfedgeHandle h = mMesh.halfedge_handle(e, 0);
        const VertexHandle a = mMesh.from_vertex_handle(h), b = mMesh.to_vertex_handle(h);
        if ((mMesh.point(a) - mMesh.point(b)).sqrnorm() >= low2) continue;
        if (!isFree(a) && !isFree(b)) continue;
        // On flat ground both go to the midpoint (the paper's rule), removing the vertex of
        // lower valence; on a crease or corner the sharper vertex stays where it is.
        HalfedgeHandle first = h, second = mMesh.opposite_halfedge_handle(h);
        const double fa = flatness(a), fb = flatness(b);
        const bool flat = fa > mSettings.flatCos && fb > mSettings.flatCos;
        if (flat ? valence(b) < valence(a) : fb > fa) std::swap(first, second);
        for (const HalfedgeHandle g : {first, second}) {
            Point position;
            if (!isCollapseAllowed(g, target, flat, position)) continue;
            const VertexHandle gone = mMesh.from_vertex_handle(g), kept = mMesh.to_vertex_handle(g);
            const VertexHandle vl = mMesh.to_vertex_handle(mMesh.next_halfedge_handle(g));
            const VertexHandle vr = mMesh.to_vertex_handle(
                mMesh.next_halfedge_handle(mMesh.opposite_halfedge_handle(g)));
            mValence[kept.idx()] += mValence[gone.idx()] - 4;   // an inner edge: two faces go
            --mValence[vl.idx()];
            --mValence[vr.idx()];
            collapseEdge(g, position);
            ++collapses;
            break;
        }
    }
    mValence.clear();
    mNeighboursOnly = false;
    // The first pass deletes most of the staircase: compact, so that no later loop steps
    // over the deleted elements (properties move along; nothing keeps handles across).
    if (collapses > 0) collectGarbage(mMesh);
}

bool
IsotropicRemesher::isFlipAllowed(EdgeHandle e)
{
    if (mMesh.is_boundary(e) || !mMesh.is_flip_ok(e)) return false;
    const HalfedgeHandle h0 = mMesh.halfedge_handle(e, 0), h1 = mMesh.halfedge_handle(e, 1);
    const VertexHandle v0 = mMesh.from_vertex_handle(h0), v1 = mMesh.to_vertex_handle(h0);
    const VertexHandle c = mMesh.to_vertex_handle(mMesh.next_halfedge_handle(h0));
    const VertexHandle d = mMesh.to_vertex_handle(mMesh.next_halfedge_handle(h1));
    if (isLocked(c) && isLocked(d) && !mPatch.mayJoinLocked(c, d)) return false;
    if (valence(v0) - 1 < minValence(v0) || valence(v1) - 1 < minValence(v1)) return false;
    // Faces (v0, v1, c), (v1, v0, d) become (v0, d, c), (d, v1, c): neither may fold over.
    const Point &p0 = mMesh.point(v0), &p1 = mMesh.point(v1), &pc = mMesh.point(c),
                &pd = mMesh.point(d);
    if (hasNoArea(p0, pd, pc) || hasNoArea(pd, p1, pc)) return false;
    const int before = int(agrees(p0, p1, pc, v0, v1, c)) + int(agrees(p1, p0, pd, v1, v0, d));
    const int after = int(agrees(p0, pd, pc, v0, d, c)) + int(agrees(pd, p1, pc, d, v1, c));
    if (after < before || (before == 2 && after < 2)) return false;
    // Across a ridge the other diagonal cuts it off (the covered points tell), across a valley
    // it bridges it: keep the new diagonal close to the old faces. Its midpoint close to the
    // old one needs no search.
    mFaces.assign({mMesh.face_handle(h0), mMesh.face_handle(h1)});
    mTriangles.assign({TrianglePoints{p0, pd, pc}, TrianglePoints{pd, p1, pc}});
    if (!keepsCovered(mFaces, mTriangles)) return false;
    const Point oldMid = (p0 + p1) * 0.5, newMid = (pc + pd) * 0.5;
    if ((oldMid - newMid).sqrnorm() > mSettings.deviation2
        && std::min(squaredDistanceToTriangle(newMid, p0, p1, pc),
                    squaredDistanceToTriangle(newMid, p1, p0, pd))
            > mSettings.deviation2) {
        return false;
    }
    // Last, as the dearest: the new pair folds through no more triangles than the old one.
    mFolds.clear();
    mFolds.addNew(CornerTriangle(p0, pd, pc, v0.idx(), d.idx(), c.idx()));
    mFolds.addNew(CornerTriangle(pd, p1, pc, d.idx(), v1.idx(), c.idx()));
    // The diamond's sides (v1, c), (c, v0), (v0, d), (d, v1) and the new triangle of each.
    const HalfedgeHandle sides[4] = {
        mMesh.next_halfedge_handle(h0), mMesh.prev_halfedge_handle(h0),
        mMesh.next_halfedge_handle(h1), mMesh.prev_halfedge_handle(h1)};
    const int newOf[4] = {1, 0, 0, 1};
    for (int k = 0; k < 4; ++k) {
        const FaceHandle o = mMesh.opposite_face_handle(sides[k]);
        if (o.is_valid()) mFolds.addNeighbour(o, newOf[k]);
    }
    return !mFolds.foldsMore({v0, v1, c, d}, mFaces, -1, false);
}

void
IsotropicRemesher::equalizeValences()
{
    countValences();
    const std::size_t count = mMesh.n_edges();
    for (std::size_t i = 0; i < count; ++i) {
        const EdgeHandle e{int(i)};
        if (mMesh.status(e).deleted() || mMesh.is_boundary(e)) continue;
        const HalfedgeHandle h0 = mMesh.halfedge_handle(e, 0), h1 = mMesh.halfedge_handle(e, 1);
        const VertexHandle v[4] = {
            mMesh.from_vertex_handle(h0), mMesh.to_vertex_handle(h0),
            mMesh.to_vertex_handle(mMesh.next_halfedge_handle(h0)),
            mMesh.to_vertex_handle(mMesh.next_halfedge_handle(h1))};
        int before = 0, after = 0;
        for (int k = 0; k < 4; ++k) {
            const int val = mValence[v[k].idx()], target = targetValence(v[k]);
            const int change = k < 2 ? -1 : 1;
            before += (val - target) * (val - target);
            after += (val + change - target) * (val + change - target);
        }
        if (after < before && isFlipAllowed(e)) {
            flipEdge(e);
            --mValence[v[0].idx()];
            --mValence[v[1].idx()];
            ++mValence[v[2].idx()];
            ++mValence[v[3].idx()];
        }
    }
    mValence.clear();
}

void
IsotropicRemesher::removeCaps()
{
    // Flip an edge whose two opposite angles sum to more than 180 degrees (not Delaunay)
    // when that raises the smaller of the two triangles' smallest angles: a cap (one angle
    // near 180) becomes two better triangles. Valence stays the main criterion: only edges
    // the flip helps geometrically are touched.
    // Opposite angles C and D sum to more than 180 degrees iff sin(C + D) < 0; with
    // u, v the edges seen from a corner: sin ~ |u x v|, cos ~ u . v (same positive scale).
    auto sumExceedsPi = [](const Point& p0, const Point& p1, const Point& pc, const Point& pd) {
        const Point uc = p0 - pc, vc = p1 - pc, ud = p0 - pd, vd = p1 - pd;
        const double sinC = (uc % vc).norm(), cosC = uc | vc;
        const double sinD = (ud % vd).norm(), cosD = ud | vd;
        return sinC * cosD + cosC * sinD < 0.0;
    };
    const std::size_t count = mMesh.n_edges();
    for (std::size_t i = 0; i < count; ++i) {
        const EdgeHandle e{int(i)};
        if (mMesh.status(e).deleted() || mMesh.is_boundary(e)) continue;
        const EdgeDiamond q(mMesh, e);
        if (!sumExceedsPi(q.p0, q.p1, q.pc, q.pd)) continue;
        if (q.smallestCosFlipped() < q.smallestCos() && isFlipAllowed(e)) flipEdge(e);
    }
}

void
IsotropicRemesher::flipSharpTriangles()
{
    // After the last round: flip an edge of a triangle with an angle under 25 degrees when
    // that raises the smaller of the two triangles' smallest angles, Delaunay or not (the
    // rounds flip for valence first; here nothing is left to undo the shape gained).
    const double sharpCos = std::cos(SHARP_TRIANGLE_DEGREES * M_PI / 180.0);
    for (int pass = 0; pass < 3; ++pass) {
        const std::size_t count = mMesh.n_edges();
        bool changed = false;
        for (std::size_t i = 0; i < count; ++i) {
            const EdgeHandle e{int(i)};
            if (mMesh.status(e).deleted() || mMesh.is_boundary(e)) continue;
            const EdgeDiamond q(mMesh, e);
            const double before = q.smallestCos();
            if (before <= sharpCos) continue;
            if (q.smallestCosFlipped() < before && isFlipAllowed(e)) {
                flipEdge(e);
                changed = true;
            }
        }
        if (!changed) break;
    }
}

void
IsotropicRemesher::tangentialRelaxation()
{
    mPrevious.assign(mMesh.n_vertices(), Point(0, 0, 0));
    std::vector<Point> moved(mMesh.n_vertices());
    for (const VertexHandle v : mMesh.vertices()) {
        const Point& p = mMesh.point(v);
        mPrevious[v.idx()] = p;
        moved[v.idx()] = p;
        if (!isFree(v)) continue;
        // Area-weighted centroid of the 1-ring's triangles, moved in the tangent plane only.
        // A vertex on a folded triangle (attaching the curve samples leaves some where the
        // smoothed curve bulges out of a chord between samples) goes to the mean of its
        // neighbours instead: inside its ring, which the weighted centroid need not be.
        bool folded = false;
        for (const FaceHandle f : mMesh.vf_range(v)) folded = folded || !agrees(f);
        Point centre;
        if (folded) {
            centre = mPatch.neighbourMean(v);
        } else {
            Point sum(0, 0, 0);
            double area = 0.0;
            for (const FaceHandle f : mMesh.vf_range(v)) {
                auto it = mMesh.cfv_iter(f);
                const Point &a = mMesh.point(*it), &b = mMesh.point(*++it),
                            &c = mMesh.point(*++it);
                const double w = ((b - a) % (c - a)).norm();
                sum += (a + b + c) * (w / 3.0);
                area += w;
            }
            if (!(area > 0.0)) continue;
            centre = sum / area;
        }
        Point d = centre - p;
        const Point& n = refNormal(v);
        d -= n * (d | n);
        moved[v.idx()] = p + d;
    }
    for (const VertexHandle v : mMesh.vertices()) mMesh.set_point(v, moved[v.idx()]);
}

void
IsotropicRemesher::projectToReference()
{
    const std::size_t count = mMesh.n_vertices();
    std::vector<Point> normals(count), relaxed(count);
    // What each vertex has of its round's moves: 2 relaxed and projected, 1 relaxed only,
    // 0 neither.
    std::vector<char> kept(count, 0);
    for (const VertexHandle v : mMesh.vertices()) {
        normals[v.idx()] = refNormal(v);
        relaxed[v.idx()] = mMesh.point(v);
        if (!isFree(v)) continue;
        kept[v.idx()] = 1;
        std::uint32_t& start = mPatch.refTriangle(v);
        ReferenceSurface::Hit hit =
            mPatch.reference().closestPointNear(toVec(mMesh.point(v)), start);
        // A move that turns the normal away from the vertex's anchor crosses a crease and
        // would cut it off (vertices drift away from corners and tips): halve it, else stay.
        const Point& anchor = mPatch.anchor(v);
        if ((toPoint(hit.normal) | anchor) < mSettings.creaseCos) {
            const Point half = (mMesh.point(v) + mPrevious[v.idx()]) * 0.5;
            hit = mPatch.reference().closestPointNear(toVec(half), start);
            if ((toPoint(hit.normal) | anchor) < mSettings.creaseCos) {
                mMesh.set_point(v, mPrevious[v.idx()]);
                kept[v.idx()] = 0;
                continue;
            }
        }
        kept[v.idx()] = 2;
        start = hit.triangle;
        mMesh.set_point(v, toPoint(hit.point));
        mPatch.refNormal(v) = toPoint(hit.normal);
    }
    // A triangle folded now that agreed before the round, or after relaxation (relaxation
    // unfolds what attaching the samples folded), must not stay folded: step the vertex back,
    // from projected to relaxed to where it was, until no move folds a triangle or leaves a
    // covered reference point behind (a serial sweep in vertex order: the same result every
    // time).
    auto agreedAt = [&](FaceHandle f, const std::vector<Point>& at) {
        auto it = mMesh.cfv_iter(f);
        const VertexHandle a = *it, b = *++it, c = *++it;
        const Point n = (at[b.idx()] - at[a.idx()]) % (at[c.idx()] - at[a.idx()]);
        return (n | normals[a.idx()]) > 0.0 && (n | normals[b.idx()]) > 0.0
            && (n | normals[c.idx()]) > 0.0;
    };
    // A face whose points all lie within the bound of the face itself passes at every
    // corner: the answer (1 close, 2 not, 0 not measured) is remembered until a corner steps
    // back, so a face is measured about once a round, not once per corner.
    std::vector<char> closeToItself(mMesh.n_faces(), 0);
    std::vector<VertexHandle> check, next;
    for (const VertexHandle v : mMesh.vertices()) if (kept[v.idx()]) check.push_back(v);
    for (int round = 0; round < 40 && !check.empty(); ++round) {
        next.clear();
        for (const VertexHandle v : check) {
            if (!kept[v.idx()]) continue;
            bool keep = true;
            mFaces.clear();
            mTriangles.clear();
            std::size_t unsure = 0;   // faces not close to themselves, moved to the front
            for (const FaceHandle f : mMesh.vf_range(v)) {
                mFaces.push_back(f);
                mTriangles.push_back(triangle(f));
                if (!agrees(f) && (agreedAt(f, mPrevious) || agreedAt(f, relaxed))) {
                    keep = false;
                    break;
                }
                char& close = closeToItself[f.idx()];
                if (!close) {
                    close = mCoverage.allWithin(f, mTriangles.back(), mSettings.deviation2)
                        ? 1 : 2;
                }
                if (close == 1) continue;
                std::swap(mFaces[unsure], mFaces.back());
                std::swap(mTriangles[unsure], mTriangles.back());
                ++unsure;
            }
            if (keep && (unsure == 0 || keepsCovered(mFaces, mTriangles, &mPrevious, unsure))
                && !mFolds.movedIntoFold(v, mPrevious)) {
                continue;
            }
            --kept[v.idx()];
            mMesh.set_point(v, kept[v.idx()] ? relaxed[v.idx()] : mPrevious[v.idx()]);
            mPatch.refNormal(v) = normals[v.idx()];
            for (const FaceHandle f : mMesh.vf_range(v)) closeToItself[f.idx()] = 0;
            // It and its neighbours' faces changed: look at them again.
            if (kept[v.idx()]) next.push_back(v);
            for (const VertexHandle w : mMesh.vv_range(v)) if (kept[w.idx()]) next.push_back(w);
        }
        std::sort(next.begin(), next.end());
        next.erase(std::unique(next.begin(), next.end()), next.end());
        check.swap(next);
    }
    // Points of a face that moved go to the nearest of it and the faces around its corners.
    for (const FaceHandle f : mMesh.faces()) {
        if (mMesh.status(f).deleted() || !mCoverage.coversAny(f)) continue;
        bool moved = false;
        for (const VertexHandle v : mMesh.fv_range(f)) moved = moved || kept[v.idx()];
        if (!moved) continue;
        mCoverage.clearReleased();
        mCoverage.releaseOutside(f);
        if (!mCoverage.hasReleased()) continue;
        mFaces.assign(1, f);
        for (const VertexHandle v : mMesh.fv_range(f)) appendFacesAround(mMesh, v, mFaces);
        mCoverage.coverByNearest(mFaces);
    }
}

} // namespace


bool
remeshIsotropically(RemeshingPatch& patch, const RemeshSettings& settings,
                    InterruptFlag& interrupt, RemeshStepSeconds* seconds)
{
    RemeshStepSeconds steps;
    auto clock = std::chrono::steady_clock::now();
    // Adds the seconds since the last call to @a step.
    auto lap = [&clock](double& step) {
        const auto now = std::chrono::steady_clock::now();
        step += std::chrono::duration<double>(now - clock).count();
        clock = now;
    };
    IsotropicRemesher remesher(patch, settings);
    for (int it = 0; it < settings.iterations; ++it) {
        if (interrupt.poll()) return false;
        if (it == 0) remesher.moveOffChords();
        remesher.splitLongEdges();
        lap(steps.split);
        if (it == 0) {
            // From the staircase through halved targets: where the extraction refined the
            // voxels (to a fifth), collapsing straight to the target grows fans of a dozen
            // triangles and more, and the fold guard's cost grows with a fan's square. The
            // passes towards the halved targets test their fans against the faces across
            // the fans' edges only; the last, at the target, and the later rounds against
            // all faces around (fewer folds left for separation). Frog at 2 voxels, one
            // thread, with the pass at 1 voxel tested so: remeshing 35.2 -> 33.6 s (medians
            // of 3), the same quality and closeness, no crossing.
            std::vector<double> targets;
            for (double t = 0.5 * settings.target;
                 settings.finestCoarsening > 0.0 && t >= settings.finestCoarsening; t *= 0.5) {
                targets.insert(targets.begin(), t);
            }
            targets.push_back(settings.target);
            for (std::size_t k = 0; k < targets.size(); ++k) {
                remesher.collapseShortEdges(targets[k], k + 1 < targets.size());
            }
        } else {
            remesher.collapseShortEdges(settings.target, false);
        }
        lap(steps.collapse);
        remesher.equalizeValences();
        remesher.removeCaps();
        lap(steps.flip);
        remesher.tangentialRelaxation();
        lap(steps.relax);
        remesher.projectToReference();
        lap(steps.project);
    }
    if (settings.iterations > 0) {
        remesher.flipSharpTriangles();
        smoothSharpFans(patch, remesher.coverage(), settings);
        remesher.flipSharpTriangles();
        lap(steps.sharpFans);
    }
    if (seconds) *seconds += steps;
    return true;
}

} // namespace vdbi
