// SPDX-License-Identifier: Apache-2.0

#include <vdbi/SharpFanSmoothing.h>

#include <vdbi/EdgeDiamond.h>
#include <vdbi/FoldGuard.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace vdbi {

namespace {

using Point = TriMesh::Point;
using VertexHandle = TriMesh::VertexHandle;
using HalfedgeHandle = TriMesh::HalfedgeHandle;
using FaceHandle = TriMesh::FaceHandle;

/// Passes over the vertices (the last ones move few).
constexpr int SHARP_FAN_PASSES = 5;

/// The passes on one patch, with their scratch.
class SharpFanSmoother
{
public:
    SharpFanSmoother(RemeshingPatch& patch, ReferenceCoverage& coverage,
                     const RemeshSettings& settings)
        : mPatch(patch), mMesh(patch.mesh()), mSettings(settings), mCoverage(coverage),
          mFolds(patch.mesh())
    {
    }

    /// One pass: toward the mean only, or (@a aside) also to the steps around it.
    void smooth(bool aside);

private:
    /// The shape of the fan of @a v.
    FanShape fanShape(VertexHandle v) const;
    /// Where sharp fan @a v (normal @a normal, shape @a old) may move: toward the mean of its
    /// neighbours, whole and half way; @a aside, the offsets among those and a pattern of
    /// steps around it that make its shape better before projection, the best first.
    const std::vector<Point>& moves(VertexHandle v, const Point& normal, const FanShape& old,
                                    bool aside);

    /// @brief Has @a v a neighbour where the boundary is tight: where it touches itself, or
    /// where one of its segments is shorter than half the target?
    /// @details There other patches come close (tiny features, curves side by side), and a
    /// patch cannot see them: steps aside there made two patches cross (frog at 4 voxels, 2
    /// pairs, at segments of 0.17 and 0.35 target) where separation could not free them.
    bool nextToTightBoundary(VertexHandle v) const
    {
        const double short2 = 0.25 * mSettings.target * mSettings.target;
        for (const VertexHandle w : mMesh.vv_range(v)) {
            if (!mPatch.isLocked(w)) continue;
            int segments = 0;
            for (const HalfedgeHandle h : mMesh.voh_range(w)) {
                if (!mMesh.is_boundary(mMesh.edge_handle(h))) continue;
                ++segments;
                const Point d = mMesh.point(mMesh.to_vertex_handle(h)) - mMesh.point(w);
                if (d.sqrnorm() < short2) return true;
            }
            if (segments != 2) return true;
        }
        return false;
    }
    /// @brief Is @a hit on an edge or a corner of a reference triangle whose ends are curve
    /// points (its barycentric weights are exactly 0 elsewhere)?
    /// @details A step aside past the patch's edge projects there: a free vertex on a curve
    /// touches the patches across it.
    bool isOnCurve(const ReferenceSurface::Hit& hit) const
    {
        const openvdb::Vec3I& t = mPatch.reference().triangles()[hit.triangle];
        bool onEdge = false, curveEnds = true;
        for (int k = 0; k < 3; ++k) {
            if (hit.barycentric[k] == 0.0) onEdge = true;
            else curveEnds = curveEnds && mPatch.isCurvePoint(std::size_t(t[k]));
        }
        return onEdge && curveEnds;
    }
    TrianglePoints triangle(FaceHandle f) const { return trianglePoints(mMesh, f); }

    RemeshingPatch& mPatch;
    TriMesh& mMesh;
    const RemeshSettings& mSettings;
    ReferenceCoverage& mCoverage;
    FoldGuard mFolds;
    struct Move
    {
        FanShape shape; ///< of the fan with the vertex moved
        Point move;
    };
    std::vector<Move> mMoves;            ///< scratch of moves()
    std::vector<Point> mBestMoves;       ///< what moves() returns
    std::vector<FaceHandle> mFaces, mChanged;
    std::vector<TrianglePoints> mTriangles;
};

FanShape
SharpFanSmoother::fanShape(VertexHandle v) const
{
    FanShape shape;
    for (const FaceHandle f : mMesh.vf_range(v)) {
        const TrianglePoints t = triangle(f);
        shape.add(smallestAngleCos(t.a, t.b, t.c));
    }
    return shape;
}

const std::vector<TriMesh::Point>&
SharpFanSmoother::moves(VertexHandle v, const Point& normal, const FanShape& old,
                                 bool aside)
{
    const Point p = mMesh.point(v);
    Point toMean = mPatch.neighbourMean(v) - p;
    toMean -= normal * (toMean | normal);
    mBestMoves.assign({toMean, toMean * 0.5});
    if (!aside) return mBestMoves;
    // The mean alone left most sharp fans as they were: where it is refused, or gains
    // nothing, a step aside often does. So a small pattern around the vertex, in its tangent
    // plane (forEachStepAside()).
    double reach = 0.0;
    int neighbours = 0;
    for (const VertexHandle w : mMesh.vv_range(v)) {
        reach += (mMesh.point(w) - p).norm();
        ++neighbours;
    }
    reach /= double(neighbours);
    // Directions from the one toward the mean, or any in the tangent plane.
    Point e1 = toMean;
    if (!(e1.norm() > 1e-9 * reach)) {
        e1 = std::abs(normal[0]) < 0.9 ? Point(1, 0, 0) : Point(0, 1, 0);
        e1 -= normal * (e1 | normal);
    }
    e1.normalize();
    const Point e2 = normal % e1;
    mMoves.clear();
    for (const Point& m : mBestMoves) mMoves.push_back({FanShape(), m});
    forEachStepAside(e1, e2, reach,
                     [&](const Point& move) { mMoves.push_back({FanShape(), move}); });
    // Ranked by the fan's shape with the vertex moved (before projection, which moves it
    // little); ties keep the order above, the mean first.
    for (Move& m : mMoves) {
        mMesh.set_point(v, p + m.move);
        m.shape = fanShape(v);
    }
    mMesh.set_point(v, p);
    // Exact comparisons here (a sort needs a strict weak order), with the margin below.
    std::stable_sort(mMoves.begin(), mMoves.end(),
                     [](const Move& a, const Move& b) { return a.shape < b.shape; });
    mBestMoves.clear();
    for (const Move& m : mMoves) {
        if (mBestMoves.size() == STEPS_ASIDE_TRIED || !m.shape.isBetterThan(old)) break;
        mBestMoves.push_back(m.move);
    }
    return mBestMoves;
}

void
SharpFanSmoother::smooth(bool aside)
{
    // After the last round: a free vertex of a fan with a small angle moves (onto the
    // reference) when that makes the fan better and passes the guards of a projection: no
    // fold, no crease crossed, every covered point within the (tighter) bound. Tangential
    // relaxation aims at even areas; this aims at the angles the result is judged by.
    // - Toward the mean of its neighbours (whole or half way), when that raises the fan's
    //   smallest angle. These moves also open folds the rounds leave at right-angled creases,
    //   which separation relies on (menger at 4 voxels).
    // - Then (@a aside) to the best of a few places around it too (moves()), when
    //   that makes its FanShape better: fewer sharp triangles, else a larger smallest angle.
    //   Only the fan's triangles change, so no move adds a sharp triangle anywhere (raising
    //   the smallest angle alone made others sharp: monu1 at 2 voxels, 1st percentile
    //   23.7 -> 20.9 degrees). A crease is judged from where the vertex is, not from its
    //   anchor (where it was made): the rounds moved it since, and the coverage bound keeps
    //   it from cutting tips off; against the anchor, more moves failed than by any guard but
    //   coverage. Fans that cross anything within two edges are left to separation, and no
    //   move may make a fan cross more: tried in many places, moves find folds at creases
    //   that the rounds' test (at sharp turns only) lets through (menger at 4 voxels). Fans
    //   next to a tight part of the boundary stay as they are (nextToTightBoundary()).
    std::vector<Point> before(mMesh.n_vertices());
    for (const VertexHandle v : mMesh.vertices()) before[v.idx()] = mMesh.point(v);
    // The first pass looks at every vertex, the next ones only at those with a face that a
    // move changed or gave covered points: a vertex refused before is refused again if none.
    std::vector<VertexHandle> candidates(mMesh.vertices().begin(), mMesh.vertices().end()), next;
    for (int pass = 0; pass < SHARP_FAN_PASSES && !candidates.empty(); ++pass) {
        next.clear();
        for (const VertexHandle v : candidates) {
            if (mMesh.status(v).deleted() || !mPatch.isFree(v)) continue;
            const FanShape old = fanShape(v);
            if (!old.isSharp()) continue;
            if (aside && nextToTightBoundary(v)) continue;
            const Point p = mMesh.point(v), normal = mPatch.refNormal(v);
            // Whether the fan crosses anything where it is is asked only once a move has
            // passed every other guard: it is dear (the faces around the ring, every pair),
            // and most sharp fans find no such move (frog at 2 voxels: 22 k of 83 k do).
            bool freeAsItIs = false;
            const std::uint32_t startTriangle = mPatch.refTriangle(v);
            bool agreedBefore = true;
            for (const FaceHandle f : mMesh.vf_range(v)) {
                agreedBefore = agreedBefore && mPatch.agrees(f);
            }
            for (const Point& move : moves(v, normal, old, aside)) {
                std::uint32_t start = startTriangle;
                const ReferenceSurface::Hit hit =
                    mPatch.reference().closestPointNear(toVec(p + move), start);
                const Point& from = aside ? normal : mPatch.anchor(v);
                if ((toPoint(hit.normal) | from) < mSettings.creaseCos || isOnCurve(hit)) {
                    continue;
                }
                mMesh.set_point(v, toPoint(hit.point));
                mPatch.refNormal(v) = toPoint(hit.normal);
                const FanShape shape = fanShape(v);
                bool ok = aside ? shape.isBetterThan(old)
                                : shape.smallestCos < old.smallestCos - 1e-6;
                mFaces.clear();
                mTriangles.clear();
                for (const FaceHandle f : mMesh.vf_range(v)) {
                    if (!ok) break;
                    // Without area: the fan's smallest angle is no guard where it was sharp
                    // already (monu16 at 4 voxels: a triangle along a straight curve).
                    const TrianglePoints t = triangle(f);
                    if ((agreedBefore && !mPatch.agrees(f)) || hasNoArea(t.a, t.b, t.c)) {
                        ok = false;
                    }
                    mFaces.push_back(f);
                    mTriangles.push_back(t);
                }
                ok = ok && mCoverage.keepsCovered(mFaces, mTriangles,
                                                  mSettings.smoothingDeviation2, &before);
                if (ok && aside && !freeAsItIs) {
                    mMesh.set_point(v, p);
                    if (mFolds.fanCrossings(v) > 0) {   // left to separation, as it is
                        mPatch.refNormal(v) = normal;
                        break;
                    }
                    freeAsItIs = true;
                    mMesh.set_point(v, toPoint(hit.point));
                }
                ok = ok && (aside ? mFolds.fanCrossings(v) == 0
                                  : !mFolds.movedIntoFold(v, before));
                if (!ok) {
                    mMesh.set_point(v, p);
                    mPatch.refNormal(v) = normal;
                    continue;
                }
                mPatch.refTriangle(v) = hit.triangle;
                before[v.idx()] = mMesh.point(v);
                mChanged = mFaces;
                for (const VertexHandle w : mMesh.vv_range(v)) appendFacesAround(mMesh, w, mFaces);
                mCoverage.recover(mChanged, mFaces);
                for (const FaceHandle g : mFaces) {
                    for (const VertexHandle w : mMesh.fv_range(g)) next.push_back(w);
                }
                break;
            }
        }
        std::sort(next.begin(), next.end());
        next.erase(std::unique(next.begin(), next.end()), next.end());
        candidates.swap(next);
    }
}

} // namespace


void
smoothSharpFans(RemeshingPatch& patch, ReferenceCoverage& coverage,
                const RemeshSettings& settings)
{
    SharpFanSmoother smoother(patch, coverage, settings);
    smoother.smooth(false);
    smoother.smooth(true);
}

} // namespace vdbi
