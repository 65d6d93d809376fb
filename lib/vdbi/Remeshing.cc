// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Remeshing.h>

#include <vdbi/Exceptions.h>
#include <vdbi/FeatureCurves.h>
#include <vdbi/Interruption.h>
#include <vdbi/PatchMeshes.h>
#include <vdbi/ReferenceSurface.h>

#include <openvdb/Exceptions.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <sstream>
#include <utility>

namespace vdbi {

namespace {

using Vec3d = openvdb::Vec3d;
using Point = TriMesh::Point;
using VertexHandle = TriMesh::VertexHandle;
using HalfedgeHandle = TriMesh::HalfedgeHandle;
using EdgeHandle = TriMesh::EdgeHandle;
using FaceHandle = TriMesh::FaceHandle;

inline Point toPoint(const Vec3d& p) { return Point(p[0], p[1], p[2]); }
inline Vec3d toVec(const Point& p) { return Vec3d(p[0], p[1], p[2]); }

/// Squared distance from @a p to triangle (a, b, c).
inline double
distance2(const Point& p, const Point& a, const Point& b, const Point& c)
{
    Vec3d bary;
    return (closestPointOnTriangle(toVec(p), toVec(a), toVec(b), toVec(c), bary) - toVec(p))
        .lengthSqr();
}

/// How far, in voxels, smoothing may move a curve point and a reference surface point: enough
/// to flatten the staircase, little enough that a one-voxel rod keeps most of its section.
constexpr double CURVE_BOUND = 0.45, SURFACE_BOUND = 0.45;
/// How far, in voxels, a collapse, flip or relaxation move may take the surface from a point
/// it had.
constexpr double DEVIATION = 0.4;

/// Numbers every stage needs, derived once from RemeshOptions.
struct Settings
{
    double target = 1.0;
    double low2 = 0.0;             ///< (4/5 target)^2: shorter edges are collapsed
    double high2 = 0.0;            ///< (4/3 target)^2: longer edges are split
    int iterations = 10;
    int curveSmoothing = 10;       ///< Taubin iterations along the feature curves
    int surfaceSmoothing = 10;     ///< Taubin iterations of the reference surfaces
    Vec3d curveBound;              ///< how far a curve point may move (world units per axis)
    Vec3d surfaceBound;            ///< how far a reference surface point may move
    /// (Largest distance)^2 between a point of the surface before a collapse, flip or
    /// relaxation move and the surface after it: keeps tips and thin parts from being eaten.
    double deviation2 = 0.0;
    /// A vertex whose reference normal differs from a neighbour's by more than this angle
    /// sits on a crease or corner: it is kept in place of a flat neighbour when collapsing.
    double flatCos = std::cos(20.0 * M_PI / 180.0);
    /// A relaxation move that turns the reference normal by more than this angle crosses a
    /// crease (it would cut the crease off): it is halved, else undone.
    double creaseCos = std::cos(30.0 * M_PI / 180.0);
};

/// One patch after remeshing. Triangle corners below the sample count are sample ids (shared
/// boundary vertices); the others are sampleCount + an index into innerPoints.
struct PatchResult
{
    std::vector<Vec3d> innerPoints;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// @brief Remeshes one patch: boundary replaced by the curve samples and locked, then rounds
/// of split, collapse, flip, relax and project (Botsch & Kobbelt 2004).
/// @details Holds only this patch's state, so patches run in parallel and each result
/// depends on its input alone. Every loop runs in a fixed order (edge or vertex index).
class PatchRemesher
{
public:
    PatchRemesher(const InterfaceMesh& raw, std::size_t patch, const FeatureCurves& curves,
                  const Settings& settings, InterruptFlag& interrupt);

    /// @throw vdbi::TopologyError if the patch does not fit its feature curves (a bug)
    PatchResult run();

private:
    // Set-up.
    void buildMesh();
    void buildReference();
    void separateLockedVertices();
    void attachCurveSamples();
    // The rounds.
    void splitLongEdges();
    void collapseShortEdges();
    void equalizeValences();
    void removeCaps();
    void tangentialRelaxation();
    void projectToReference();
    // Checks.
    bool isCollapseAllowed(HalfedgeHandle h, bool toMidpoint, Point& position);
    bool isFlipAllowed(EdgeHandle e);
    bool hasExpectedBoundary() const;
    PatchResult exportMesh() const;

    bool isLocked(VertexHandle v) const { return mMesh.property(mSample, v) >= 0; }
    bool isFree(VertexHandle v) const
    {
        return !mMesh.status(v).deleted() && !isLocked(v) && !mMesh.is_boundary(v);
    }
    const Point& refNormal(VertexHandle v) const { return mMesh.property(mRefNormal, v); }
    int targetValence(VertexHandle v) const { return mMesh.is_boundary(v) ? 4 : 6; }
    int minValence(VertexHandle v) const { return mMesh.is_boundary(v) ? 2 : 3; }
    int valence(VertexHandle v) const
    {
        return mValence.empty() ? int(mMesh.valence(v)) : mValence[v.idx()];
    }
    void countValences()
    {
        mValence.assign(mMesh.n_vertices(), 0);
        for (const VertexHandle v : mMesh.vertices()) {
            if (!mMesh.status(v).deleted()) mValence[v.idx()] = int(mMesh.valence(v));
        }
    }
    /// Smallest cosine between the reference normal at @a v and at its neighbours.
    double flatness(VertexHandle v) const
    {
        double f = 1.0;
        for (const VertexHandle w : mMesh.vv_range(v)) f = std::min(f, refNormal(v) | refNormal(w));
        return f;
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
    VertexHandle addInnerVertex(const Point& p, const Point& normal);
    VertexHandle splitEdge(EdgeHandle e);
    std::string where() const;

    const InterfaceMesh& mRaw;
    const InterfacePatch& mPatch;
    const FeatureCurves& mCurves;
    const Settings& mSettings;
    InterruptFlag& mInterrupt;

    TriMesh mMesh;
    OpenMesh::VPropHandleT<std::int64_t> mSample;     ///< "v:sample": global sample id or -1
    OpenMesh::VPropHandleT<Point> mRefNormal;         ///< "v:refnormal": reference normal
    /// "v:anchor": the reference normal where the vertex was made; relaxation keeps the
    /// vertex where the normal is within creaseCos of it, so no vertex drifts off a crease,
    /// corner or tip over many small moves.
    OpenMesh::VPropHandleT<Point> mAnchor;
    /// "v:reftri": the reference triangle of the last projection, where the next starts.
    OpenMesh::VPropHandleT<std::uint32_t> mRefTriangle;
    std::vector<std::uint32_t> mRawPoints;            ///< raw point of every initial vertex
    std::vector<openvdb::Vec3I> mTriangles;           ///< raw triangles, local indices
    /// Curves bounding this patch, with the direction the patch boundary runs along them.
    std::vector<std::pair<std::uint32_t, bool>> mCurveDirections;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> mExpectedBoundary;   ///< sample pairs
    std::unique_ptr<ReferenceSurface> mReference;
    std::vector<Point> mPrevious;                     ///< positions before relaxation
    /// Valence of every vertex, kept up to date during the collapse and flip passes.
    std::vector<int> mValence;
};


PatchRemesher::PatchRemesher(const InterfaceMesh& raw, std::size_t patch,
                             const FeatureCurves& curves, const Settings& settings,
                             InterruptFlag& interrupt)
    : mRaw(raw), mPatch(raw.patches[patch]), mCurves(curves), mSettings(settings),
      mInterrupt(interrupt)
{
}


std::string
PatchRemesher::where() const
{
    std::ostringstream os;
    os << "remeshing patch (" << mPatch.a << ", " << mPatch.b << ")";
    return os.str();
}


VertexHandle
PatchRemesher::addInnerVertex(const Point& p, const Point& normal)
{
    const VertexHandle v = mMesh.add_vertex(p);
    mMesh.property(mSample, v) = -1;
    mMesh.property(mRefNormal, v) = normal;
    mMesh.property(mAnchor, v) = normal;
    mMesh.property(mRefTriangle, v) = std::uint32_t(-1);
    return v;
}


VertexHandle
PatchRemesher::splitEdge(EdgeHandle e)
{
    const HalfedgeHandle h = mMesh.halfedge_handle(e, 0);
    const VertexHandle a = mMesh.from_vertex_handle(h), b = mMesh.to_vertex_handle(h);
    Point normal = refNormal(a) + refNormal(b);
    const double len = normal.norm();
    if (len > 0.0) normal /= len;
    const VertexHandle m = addInnerVertex((mMesh.point(a) + mMesh.point(b)) * 0.5, normal);
    mMesh.property(mRefTriangle, m) = mMesh.property(mRefTriangle, a);
    mMesh.split(e, m);
    return m;
}


void
PatchRemesher::buildMesh()
{
    const std::size_t begin = mPatch.firstTriangle, end = begin + mPatch.triangleCount;
    mRawPoints.clear();
    mRawPoints.reserve(3 * mPatch.triangleCount);
    for (std::size_t t = begin; t < end; ++t) {
        for (int i = 0; i < 3; ++i) mRawPoints.push_back(mRaw.triangles[t][i]);
    }
    std::sort(mRawPoints.begin(), mRawPoints.end());
    mRawPoints.erase(std::unique(mRawPoints.begin(), mRawPoints.end()), mRawPoints.end());
    auto local = [&](std::uint32_t p) {
        return std::uint32_t(std::lower_bound(mRawPoints.begin(), mRawPoints.end(), p)
                             - mRawPoints.begin());
    };
    mTriangles.resize(mPatch.triangleCount);
    for (std::size_t t = begin; t < end; ++t) {
        const openvdb::Vec3I& tri = mRaw.triangles[t];
        mTriangles[t - begin] = openvdb::Vec3I(local(tri[0]), local(tri[1]), local(tri[2]));
    }

    mMesh.request_vertex_status();
    mMesh.request_edge_status();
    mMesh.request_halfedge_status();
    mMesh.request_face_status();
    mMesh.add_property(mSample, "v:sample");
    mMesh.add_property(mRefNormal, "v:refnormal");
    mMesh.add_property(mAnchor, "v:anchor");
    mMesh.add_property(mRefTriangle, "v:reftri");
    mMesh.reserve(mRawPoints.size() * 2, mRawPoints.size() * 6, mTriangles.size() * 2);
    for (std::uint32_t p : mRawPoints) {
        const VertexHandle v = addInnerVertex(toPoint(mRaw.points[p]), Point(0, 0, 0));
        mMesh.property(mSample, v) = mCurves.junctionSample(p);
    }
    for (const openvdb::Vec3I& t : mTriangles) {
        const FaceHandle f = mMesh.add_face(VertexHandle(int(t[0])), VertexHandle(int(t[1])),
                                            VertexHandle(int(t[2])));
        if (!f.is_valid()) {
            throw TopologyError(where() + ": a triangle makes a complex edge or vertex");
        }
    }
}


void
PatchRemesher::buildReference()
{
    const std::size_t n = mRawPoints.size();
    std::vector<Vec3d> original(n), points(n);
    std::vector<std::uint8_t> fixed(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        original[i] = points[i] = mRaw.points[mRawPoints[i]];
        fixed[i] = mMesh.property(mSample, VertexHandle(int(i))) >= 0;
    }
    // Boundary points move onto their smoothed feature curve and stay there.
    for (const HalfedgeHandle h : mMesh.halfedges()) {
        if (!mMesh.is_boundary(h)) continue;
        const int u = mMesh.from_vertex_handle(h).idx(), v = mMesh.to_vertex_handle(h).idx();
        const FeatureEdge* edge = mCurves.findEdge(mRawPoints[u], mRawPoints[v]);
        if (!edge) throw TopologyError(where() + ": a boundary edge is no feature edge");
        const FeatureCurve& curve = mCurves.curves[edge->curve];
        const bool forward = curve.points[edge->segment] == mRawPoints[u];
        points[u] = curve.smoothed[edge->segment + (forward ? 0 : 1)];
        points[v] = curve.smoothed[edge->segment + (forward ? 1 : 0)];
        fixed[u] = fixed[v] = 1;
        mCurveDirections.emplace_back(edge->curve, forward);
    }
    std::sort(mCurveDirections.begin(), mCurveDirections.end());
    mCurveDirections.erase(std::unique(mCurveDirections.begin(), mCurveDirections.end()),
                           mCurveDirections.end());
    for (std::size_t i = 1; i < mCurveDirections.size(); ++i) {
        if (mCurveDirections[i].first == mCurveDirections[i - 1].first) {
            throw TopologyError(where() + ": the boundary runs both ways along a curve");
        }
    }

    smoothSurfacePoints(points, original, mTriangles, fixed, mSettings.surfaceSmoothing,
                        mSettings.surfaceBound);
    mReference.reset(new ReferenceSurface(points, mTriangles));
    const std::vector<Vec3d>& normals = mReference->vertexNormals();
    for (std::size_t i = 0; i < n; ++i) {
        const VertexHandle v{int(i)};
        mMesh.set_point(v, toPoint(points[i]));
        mMesh.property(mRefNormal, v) = toPoint(normals[i]);
        mMesh.property(mAnchor, v) = toPoint(normals[i]);
        mMesh.property(mRefTriangle, v) = mReference->triangleAt(std::uint32_t(i));
    }
}


void
PatchRemesher::separateLockedVertices()
{
    // An inner edge between two boundary vertices could coincide with a curve segment or an
    // inner edge of another patch; split it so every inner edge has an inner end.
    const std::size_t count = mMesh.n_edges();
    for (std::size_t i = 0; i < count; ++i) {
        const EdgeHandle e{int(i)};
        if (mMesh.status(e).deleted() || mMesh.is_boundary(e)) continue;
        const HalfedgeHandle h = mMesh.halfedge_handle(e, 0);
        if (isLocked(mMesh.from_vertex_handle(h)) && isLocked(mMesh.to_vertex_handle(h))) {
            splitEdge(e);
        }
    }
}


void
PatchRemesher::attachCurveSamples()
{
    auto local = [&](std::uint32_t p) {
        auto it = std::lower_bound(mRawPoints.begin(), mRawPoints.end(), p);
        if (it == mRawPoints.end() || *it != p) {
            throw TopologyError(where() + ": a curve point is not in the patch");
        }
        return VertexHandle(int(it - mRawPoints.begin()));
    };
    for (const auto& [curveIndex, forward] : mCurveDirections) {
        const FeatureCurve& curve = mCurves.curves[curveIndex];
        const std::size_t m = curve.points.size() - 1, n = curve.samples.size() - 1;
        const double length = curve.length();
        // Chain A: the extracted boundary, chain B: the samples, both in the direction of
        // the patch boundary, with their arc-length parameters.
        std::vector<VertexHandle> a(m + 1), b(n + 1);
        std::vector<double> ta(m + 1), tb(n + 1);
        for (std::size_t i = 0; i <= m; ++i) {
            const std::size_t k = forward ? i : m - i;
            a[i] = local(curve.points[k]);
            ta[i] = forward ? curve.arcLength[k] : length - curve.arcLength[k];
        }
        b[0] = a[0];
        b[n] = a[m];
        for (std::size_t j = 0; j <= n; ++j) {
            const std::size_t k = forward ? j : n - j;
            tb[j] = forward ? curve.sampleArcLength[k] : length - curve.sampleArcLength[k];
            if (j == 0 || j == n) continue;
            const std::uint32_t id = curve.samples[k];
            const Vec3d& p = mCurves.samplePoints[id];
            const VertexHandle v = addInnerVertex(toPoint(p),
                                                  toPoint(mReference->closestPoint(p).normal));
            mMesh.property(mSample, v) = id;
            b[j] = v;
        }
        for (std::size_t j = 0; j < n; ++j) {
            mExpectedBoundary.emplace_back(std::uint32_t(mMesh.property(mSample, b[j])),
                                           std::uint32_t(mMesh.property(mSample, b[j + 1])));
        }
        for (std::size_t i = 0; i < m; ++i) {
            const HalfedgeHandle h = mMesh.find_halfedge(a[i], a[i + 1]);
            if (!h.is_valid() || !mMesh.is_boundary(h)) {
                throw TopologyError(where() + ": a curve is not on the patch boundary");
            }
        }
        if (m == 1 && n == 1) continue;   // the extracted edge is the sample segment

        auto addFace = [&](VertexHandle x, VertexHandle y, VertexHandle z) {
            if (!mMesh.add_face(x, y, z).is_valid()) {
                throw TopologyError(where() + ": the curve samples could not be attached");
            }
        };
        if (n == 1) {
            // A fan around a new inner vertex closes the polygon a[0..m] with the segment.
            Point centre(0, 0, 0), normal(0, 0, 0);
            for (VertexHandle v : a) {
                centre += mMesh.point(v);
                normal += refNormal(v);
            }
            centre /= double(a.size());
            const double len = normal.norm();
            if (len > 0.0) normal /= len;
            const VertexHandle c = addInnerVertex(centre, normal);
            for (std::size_t i = 0; i < m; ++i) addFace(c, a[i], a[i + 1]);
            addFace(c, a[m], a[0]);
            continue;
        }
        // Zip the two chains by arc length: every triangle has one edge on one chain and its
        // third corner on the other. The faces sit on the outer side of the old boundary.
        addFace(a[0], a[1], b[1]);
        std::size_t i = 1, j = 1;
        while (!((i == m && j == n - 1) || (i == m - 1 && j == n) || (i == m && j == n))) {
            const bool advanceA = (j == n) || (i < m && ta[i + 1] <= tb[j + 1]);
            if (advanceA) {
                addFace(a[i], a[i + 1], b[j]);
                ++i;
            } else {
                addFace(a[i], b[j + 1], b[j]);
                ++j;
            }
        }
    }
    std::sort(mExpectedBoundary.begin(), mExpectedBoundary.end());
}


void
PatchRemesher::splitLongEdges()
{
    // Boundary edges are the curve samples' segments: never split.
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
            if (d.sqrnorm() <= mSettings.high2) continue;
            splitEdge(e);
            changed = true;
        }
    }
}


bool
PatchRemesher::isCollapseAllowed(HalfedgeHandle h, bool toMidpoint, Point& position)
{
    const VertexHandle v0 = mMesh.from_vertex_handle(h), v1 = mMesh.to_vertex_handle(h);
    if (!isFree(v0)) return false;   // boundary (sample) vertices never go
    const Point p0 = mMesh.point(v0), p1 = mMesh.point(v1);
    const bool moves = toMidpoint && isFree(v1);
    position = moves ? (p0 + p1) * 0.5 : p1;
    const VertexHandle vl = mMesh.to_vertex_handle(mMesh.next_halfedge_handle(h));
    const VertexHandle vr = mMesh.to_vertex_handle(
        mMesh.next_halfedge_handle(mMesh.opposite_halfedge_handle(h)));
    // No edge longer than the split limit, no inner edge between two locked vertices. A
    // vertex with only locked neighbours stays: it is the centre of a fan filling a small
    // boundary loop, without it two patches on the same loop would become the same
    // triangle.
    bool lockedRing = true;
    for (const VertexHandle w : mMesh.vv_range(v0)) {
        lockedRing = lockedRing && isLocked(w);
        if (w == v1 || w == vl || w == vr) continue;
        if (isLocked(v1) && isLocked(w)) return false;
        if ((mMesh.point(w) - position).sqrnorm() > mSettings.high2) return false;
    }
    if (lockedRing) return false;
    if (moves) {
        for (const VertexHandle w : mMesh.vv_range(v1)) {
            if (w != v0 && (mMesh.point(w) - position).sqrnorm() > mSettings.high2) return false;
        }
    }
    if (!mMesh.is_collapse_ok(h)) return false;   // link condition: stays a 2-manifold
    // Keep every vertex at valence >= 3 inside (2 on the boundary): no degenerate fans, and a
    // closed component stops at a tetrahedron.
    if (valence(vl) - 1 < minValence(vl)) return false;
    if (valence(vr) - 1 < minValence(vr)) return false;
    if (valence(v1) + valence(v0) - 4 < minValence(v1)) return false;

    // No triangle may fold over, and the points that go must stay close to the new surface.
    // The kept vertex lies on every new face: a point that close passes without a search.
    const double limit2 = mSettings.deviation2;
    double near0 = (p0 - position).sqrnorm(), near1 = moves ? (p1 - position).sqrnorm() : 0.0;
    for (const VertexHandle centre : {v0, v1}) {
        if (centre == v1 && !moves) break;
        for (const FaceHandle f : mMesh.vf_range(centre)) {
            auto it = mMesh.cfv_iter(f);
            VertexHandle c[3] = {*it, *++it, *++it};
            int ends = 0;
            for (int k = 0; k < 3; ++k) ends += (c[k] == v0 || c[k] == v1);
            if (ends == 2) continue;   // removed with the edge
            Point p[3];
            for (int k = 0; k < 3; ++k) {
                p[k] = (c[k] == v0 || c[k] == v1) ? position : mMesh.point(c[k]);
            }
            if (near0 > limit2) near0 = std::min(near0, distance2(p0, p[0], p[1], p[2]));
            if (near1 > limit2) near1 = std::min(near1, distance2(p1, p[0], p[1], p[2]));
            if (!agrees(f)) continue;   // was folded already
            for (int k = 0; k < 3; ++k) if (c[k] == v0) c[k] = v1;
            if (!agrees(p[0], p[1], p[2], c[0], c[1], c[2])) return false;
        }
    }
    return std::max(near0, near1) <= limit2;
}


void
PatchRemesher::collapseShortEdges()
{
    countValences();
    const std::size_t count = mMesh.n_edges();
    for (std::size_t i = 0; i < count; ++i) {
        const EdgeHandle e{int(i)};
        if (mMesh.status(e).deleted()) continue;
        const HalfedgeHandle h = mMesh.halfedge_handle(e, 0);
        const VertexHandle a = mMesh.from_vertex_handle(h), b = mMesh.to_vertex_handle(h);
        if ((mMesh.point(a) - mMesh.point(b)).sqrnorm() >= mSettings.low2) continue;
        if (!isFree(a) && !isFree(b)) continue;
        // On flat ground both go to the midpoint (the paper's rule), removing the vertex of
        // lower valence; on a crease or corner the sharper vertex stays where it is.
        HalfedgeHandle first = h, second = mMesh.opposite_halfedge_handle(h);
        const double fa = flatness(a), fb = flatness(b);
        const bool flat = fa > mSettings.flatCos && fb > mSettings.flatCos;
        if (flat ? valence(b) < valence(a) : fb > fa) std::swap(first, second);
        for (const HalfedgeHandle g : {first, second}) {
            Point position;
            if (!isCollapseAllowed(g, flat, position)) continue;
            const VertexHandle gone = mMesh.from_vertex_handle(g), kept = mMesh.to_vertex_handle(g);
            const VertexHandle vl = mMesh.to_vertex_handle(mMesh.next_halfedge_handle(g));
            const VertexHandle vr = mMesh.to_vertex_handle(
                mMesh.next_halfedge_handle(mMesh.opposite_halfedge_handle(g)));
            mValence[kept.idx()] += mValence[gone.idx()] - 4;   // an inner edge: two faces go
            --mValence[vl.idx()];
            --mValence[vr.idx()];
            mMesh.collapse(g);
            mMesh.set_point(kept, position);
            break;
        }
    }
    mValence.clear();
}


bool
PatchRemesher::isFlipAllowed(EdgeHandle e)
{
    if (mMesh.is_boundary(e) || !mMesh.is_flip_ok(e)) return false;
    const HalfedgeHandle h0 = mMesh.halfedge_handle(e, 0), h1 = mMesh.halfedge_handle(e, 1);
    const VertexHandle v0 = mMesh.from_vertex_handle(h0), v1 = mMesh.to_vertex_handle(h0);
    const VertexHandle c = mMesh.to_vertex_handle(mMesh.next_halfedge_handle(h0));
    const VertexHandle d = mMesh.to_vertex_handle(mMesh.next_halfedge_handle(h1));
    if (isLocked(c) && isLocked(d)) return false;
    if (valence(v0) - 1 < minValence(v0) || valence(v1) - 1 < minValence(v1)) return false;
    // Faces (v0, v1, c), (v1, v0, d) become (v0, d, c), (d, v1, c): neither may fold over.
    const Point &p0 = mMesh.point(v0), &p1 = mMesh.point(v1), &pc = mMesh.point(c),
                &pd = mMesh.point(d);
    const int before = int(agrees(p0, p1, pc, v0, v1, c)) + int(agrees(p1, p0, pd, v1, v0, d));
    const int after = int(agrees(p0, pd, pc, v0, d, c)) + int(agrees(pd, p1, pc, d, v1, c));
    if (after < before || (before == 2 && after < 2)) return false;
    // Across a ridge or valley the other diagonal cuts it off: keep the two surfaces close.
    // Each diagonal's midpoint is on its own faces, so close midpoints need no search.
    const Point oldMid = (p0 + p1) * 0.5, newMid = (pc + pd) * 0.5;
    if ((oldMid - newMid).sqrnorm() <= mSettings.deviation2) return true;
    const double oldToNew = std::min(distance2(oldMid, p0, pd, pc), distance2(oldMid, pd, p1, pc));
    const double newToOld = std::min(distance2(newMid, p0, p1, pc), distance2(newMid, p1, p0, pd));
    return std::max(oldToNew, newToOld) <= mSettings.deviation2;
}


void
PatchRemesher::equalizeValences()
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
            mMesh.flip(e);
            --mValence[v[0].idx()];
            --mValence[v[1].idx()];
            ++mValence[v[2].idx()];
            ++mValence[v[3].idx()];
        }
    }
    mValence.clear();
}


void
PatchRemesher::removeCaps()
{
    // Flip an edge whose two opposite angles sum to more than 180 degrees (not Delaunay)
    // when that raises the smaller of the two triangles' smallest angles: a cap (one angle
    // near 180) becomes two better triangles. Valence stays the main criterion: only edges
    // the flip helps geometrically are touched.
    auto largestCos = [](const Point& a, const Point& b, const Point& c) {
        const Point ab = (b - a).normalized(), bc = (c - b).normalized(),
                    ca = (a - c).normalized();
        return std::max({-(ab | ca), -(bc | ab), -(ca | bc)});   // of the smallest angle
    };
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
        const HalfedgeHandle h0 = mMesh.halfedge_handle(e, 0), h1 = mMesh.halfedge_handle(e, 1);
        const VertexHandle v0 = mMesh.from_vertex_handle(h0), v1 = mMesh.to_vertex_handle(h0);
        const VertexHandle c = mMesh.to_vertex_handle(mMesh.next_halfedge_handle(h0));
        const VertexHandle d = mMesh.to_vertex_handle(mMesh.next_halfedge_handle(h1));
        const Point &p0 = mMesh.point(v0), &p1 = mMesh.point(v1), &pc = mMesh.point(c),
                    &pd = mMesh.point(d);
        if (!sumExceedsPi(p0, p1, pc, pd)) continue;
        const double before = std::max(largestCos(p0, p1, pc), largestCos(p1, p0, pd));
        const double after = std::max(largestCos(p0, pd, pc), largestCos(pd, p1, pc));
        if (after < before && isFlipAllowed(e)) mMesh.flip(e);
    }
}


void
PatchRemesher::tangentialRelaxation()
{
    mPrevious.assign(mMesh.n_vertices(), Point(0, 0, 0));
    std::vector<Point> moved(mMesh.n_vertices());
    for (const VertexHandle v : mMesh.vertices()) {
        const Point& p = mMesh.point(v);
        mPrevious[v.idx()] = p;
        moved[v.idx()] = p;
        if (!isFree(v)) continue;
        // Area-weighted centroid of the 1-ring's triangles, moved in the tangent plane only.
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
        Point d = sum / area - p;
        const Point& n = refNormal(v);
        d -= n * (d | n);
        moved[v.idx()] = p + d;
    }
    for (const VertexHandle v : mMesh.vertices()) mMesh.set_point(v, moved[v.idx()]);
}


void
PatchRemesher::projectToReference()
{
    const std::size_t count = mMesh.n_vertices();
    std::vector<Point> normals(count);
    std::vector<char> moved(count, 0);
    for (const VertexHandle v : mMesh.vertices()) {
        normals[v.idx()] = refNormal(v);
        if (!isFree(v)) continue;
        std::uint32_t& start = mMesh.property(mRefTriangle, v);
        ReferenceSurface::Hit hit = mReference->closestPointNear(toVec(mMesh.point(v)), start);
        // A move that turns the normal away from the vertex's anchor crosses a crease and
        // would cut it off (vertices drift away from corners and tips): halve it, else stay.
        const Point& anchor = mMesh.property(mAnchor, v);
        if ((toPoint(hit.normal) | anchor) < mSettings.creaseCos) {
            const Point half = (mMesh.point(v) + mPrevious[v.idx()]) * 0.5;
            hit = mReference->closestPointNear(toVec(half), start);
            if ((toPoint(hit.normal) | anchor) < mSettings.creaseCos) {
                mMesh.set_point(v, mPrevious[v.idx()]);
                continue;
            }
        }
        moved[v.idx()] = 1;
        start = hit.triangle;
        mMesh.set_point(v, toPoint(hit.point));
        mMesh.property(mRefNormal, v) = toPoint(hit.normal);
    }
    // Undo the moves that fold a triangle over or uncover the place the vertex left, until
    // no move does (a serial sweep in vertex order: the same result every time).
    auto agreedBefore = [&](FaceHandle f) {
        auto it = mMesh.cfv_iter(f);
        const VertexHandle a = *it, b = *++it, c = *++it;
        const Point n = (mPrevious[b.idx()] - mPrevious[a.idx()])
            % (mPrevious[c.idx()] - mPrevious[a.idx()]);
        return (n | normals[a.idx()]) > 0.0 && (n | normals[b.idx()]) > 0.0
            && (n | normals[c.idx()]) > 0.0;
    };
    std::vector<VertexHandle> check, next;
    for (const VertexHandle v : mMesh.vertices()) if (moved[v.idx()]) check.push_back(v);
    for (int round = 0; round < 20 && !check.empty(); ++round) {
        next.clear();
        for (const VertexHandle v : check) {
            if (!moved[v.idx()]) continue;
            bool keep = true;
            // The vertex is on its new faces: a short move cannot uncover its old place.
            double nearest2 = (mMesh.point(v) - mPrevious[v.idx()]).sqrnorm();
            for (const FaceHandle f : mMesh.vf_range(v)) {
                auto it = mMesh.cfv_iter(f);
                const Point &a = mMesh.point(*it), &b = mMesh.point(*++it),
                            &c = mMesh.point(*++it);
                if (nearest2 > mSettings.deviation2) {
                    nearest2 = std::min(nearest2, distance2(mPrevious[v.idx()], a, b, c));
                }
                if (!agrees(f) && agreedBefore(f)) keep = false;
            }
            if (keep && nearest2 <= mSettings.deviation2) continue;
            moved[v.idx()] = 0;
            mMesh.set_point(v, mPrevious[v.idx()]);
            mMesh.property(mRefNormal, v) = normals[v.idx()];
            // Its neighbours' faces changed: look at them again.
            for (const VertexHandle w : mMesh.vv_range(v)) if (moved[w.idx()]) next.push_back(w);
        }
        std::sort(next.begin(), next.end());
        next.erase(std::unique(next.begin(), next.end()), next.end());
        check.swap(next);
    }
}


bool
PatchRemesher::hasExpectedBoundary() const
{
    std::vector<std::pair<std::uint32_t, std::uint32_t>> boundary;
    for (const HalfedgeHandle h : mMesh.halfedges()) {
        if (mMesh.status(h).deleted() || !mMesh.is_boundary(h)) continue;
        const std::int64_t u = mMesh.property(mSample, mMesh.from_vertex_handle(h));
        const std::int64_t v = mMesh.property(mSample, mMesh.to_vertex_handle(h));
        if (u < 0 || v < 0) return false;
        boundary.emplace_back(std::uint32_t(u), std::uint32_t(v));
    }
    std::sort(boundary.begin(), boundary.end());
    if (boundary != mExpectedBoundary) return false;
    for (const EdgeHandle e : mMesh.edges()) {
        if (mMesh.status(e).deleted() || mMesh.is_boundary(e)) continue;
        const HalfedgeHandle h = mMesh.halfedge_handle(e, 0);
        if (isLocked(mMesh.from_vertex_handle(h)) && isLocked(mMesh.to_vertex_handle(h))) {
            return false;
        }
    }
    return true;
}


PatchResult
PatchRemesher::exportMesh() const
{
    const std::uint32_t sampleCount = std::uint32_t(mCurves.samplePoints.size());
    PatchResult result;
    std::vector<std::uint32_t> index(mMesh.n_vertices(), 0);
    for (const VertexHandle v : mMesh.vertices()) {
        if (mMesh.status(v).deleted()) continue;
        const std::int64_t s = mMesh.property(mSample, v);
        if (s >= 0) {
            index[v.idx()] = std::uint32_t(s);
        } else {
            index[v.idx()] = sampleCount + std::uint32_t(result.innerPoints.size());
            result.innerPoints.push_back(toVec(mMesh.point(v)));
        }
    }
    for (const FaceHandle f : mMesh.faces()) {
        if (mMesh.status(f).deleted()) continue;
        auto it = mMesh.cfv_iter(f);
        const VertexHandle a = *it, b = *++it, c = *++it;
        result.triangles.push_back({index[a.idx()], index[b.idx()], index[c.idx()]});
    }
    return result;
}


PatchResult
PatchRemesher::run()
{
    buildMesh();
    buildReference();
    separateLockedVertices();
    attachCurveSamples();
    separateLockedVertices();
    if (!hasExpectedBoundary()) {
        throw TopologyError(where() + ": the boundary does not match the curve samples");
    }
    // Fallback: the extracted triangles fitted to the samples, should a round go wrong.
    PatchResult fitted = exportMesh();

    for (int it = 0; it < mSettings.iterations; ++it) {
        if (mInterrupt.poll()) return PatchResult();
        splitLongEdges();
        collapseShortEdges();
        equalizeValences();
        removeCaps();
        tangentialRelaxation();
        projectToReference();
    }
    if (!hasExpectedBoundary()) return fitted;
    return exportMesh();
}


/// World size of one voxel per axis from the point keys: the smallest ratio of world to key
/// distance along triangle edges parallel to that axis of the key grid; zeros without keys.
Vec3d
voxelSizeFromKeys(const InterfaceMesh& mesh)
{
    if (mesh.pointKeys.size() != mesh.points.size() || mesh.keyScale <= 0) return Vec3d(0.0);
    const double inf = std::numeric_limits<double>::infinity();
    Vec3d best(inf, inf, inf);
    const std::size_t count = std::min<std::size_t>(mesh.triangles.size(), 4096);
    for (std::size_t t = 0; t < count; ++t) {
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t u = mesh.triangles[t][i], v = mesh.triangles[t][(i + 1) % 3];
            const VertexKey &ku = mesh.pointKeys[u], &kv = mesh.pointKeys[v];
            int axes = 0, axis = 0;
            std::int64_t delta = 0;
            for (int k = 0; k < 3; ++k) {
                if (ku[k] != kv[k]) {
                    ++axes;
                    axis = k;
                    delta = std::abs(ku[k] - kv[k]);
                }
            }
            if (axes != 1) continue;
            const double world = (mesh.points[u] - mesh.points[v]).length();
            best[axis] = std::min(best[axis], world * double(mesh.keyScale) / double(delta));
        }
    }
    const double smallest = std::min({best[0], best[1], best[2]});
    if (!std::isfinite(smallest)) return Vec3d(0.0);
    for (int k = 0; k < 3; ++k) if (!std::isfinite(best[k])) best[k] = smallest;
    return best;
}

} // namespace


InterfaceMesh
remeshPatches(const InterfaceMesh& raw, const RemeshOptions& options)
{
    if (!std::isfinite(options.edgeLength) || options.edgeLength <= 0.0) {
        OPENVDB_THROW(openvdb::ValueError, "remeshing: the edge length must be a finite "
            "number > 0, not " << options.edgeLength);
    }
    if (options.iterations < 0) {
        OPENVDB_THROW(openvdb::ValueError, "remeshing: iterations must be >= 0, not "
            << options.iterations);
    }
    Vec3d voxel = options.voxelSize;
    if (!(voxel[0] > 0.0 && voxel[1] > 0.0 && voxel[2] > 0.0)) voxel = voxelSizeFromKeys(raw);
    if (!(voxel[0] > 0.0 && voxel[1] > 0.0 && voxel[2] > 0.0)) voxel = Vec3d(options.edgeLength);
    const double smallestVoxel = std::min({voxel[0], voxel[1], voxel[2]});

    Settings settings;
    settings.target = options.edgeLength;
    settings.low2 = std::pow(0.8 * options.edgeLength, 2);
    settings.high2 = std::pow(4.0 / 3.0 * options.edgeLength, 2);
    settings.iterations = options.iterations;
    settings.curveBound = voxel * CURVE_BOUND;
    settings.surfaceBound = voxel * SURFACE_BOUND;
    settings.deviation2 = std::pow(DEVIATION * smallestVoxel, 2);

    checkInterrupt(options.interrupter, "remeshing");
    FeatureCurves curves = findFeatureCurves(raw, options.threaded);
    smoothFeatureCurves(curves, raw, settings.curveSmoothing, settings.curveBound,
                        options.threaded);
    resampleFeatureCurves(curves, settings.target, options.threaded);
    checkInterrupt(options.interrupter, "remeshing the patches");

    // Largest patches first, so the long ones do not start last; results go by patch index.
    const std::size_t patchCount = raw.patches.size();
    std::vector<std::size_t> order(patchCount);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
        return raw.patches[x].triangleCount > raw.patches[y].triangleCount;
    });
    std::vector<PatchResult> results(patchCount);
    InterruptFlag interrupt(options.interrupter);
    auto remesh = [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            if (interrupt.poll()) return;
            const std::size_t p = order[i];
            PatchRemesher remesher(raw, p, curves, settings, interrupt);
            results[p] = remesher.run();
        }
    };
    const tbb::blocked_range<std::size_t> all(0, patchCount, 1);
    if (options.threaded) tbb::parallel_for(all, remesh, tbb::simple_partitioner());
    else remesh(all);
    interrupt.throwIfStopped("remeshing");

    InterfaceMesh out;
    const std::uint32_t sampleCount = std::uint32_t(curves.samplePoints.size());
    out.points = std::move(curves.samplePoints);
    std::size_t triangleCount = 0;
    for (const PatchResult& r : results) triangleCount += r.triangles.size();
    out.triangles.reserve(triangleCount);
    out.patches.reserve(patchCount);
    for (std::size_t p = 0; p < patchCount; ++p) {
        const std::uint32_t offset = std::uint32_t(out.points.size()) - sampleCount;
        PatchResult& r = results[p];
        out.points.insert(out.points.end(), r.innerPoints.begin(), r.innerPoints.end());
        InterfacePatch patch;
        patch.a = raw.patches[p].a;
        patch.b = raw.patches[p].b;
        patch.firstTriangle = out.triangles.size();
        patch.triangleCount = r.triangles.size();
        for (const auto& t : r.triangles) {
            openvdb::Vec3I tri;
            for (int k = 0; k < 3; ++k) tri[k] = t[k] < sampleCount ? t[k] : t[k] + offset;
            out.triangles.push_back(tri);
        }
        out.patches.push_back(patch);
        std::vector<Vec3d>().swap(r.innerPoints);
        std::vector<std::array<std::uint32_t, 3>>().swap(r.triangles);
    }
    out.keyScale = 0;
    return out;
}

} // namespace vdbi
