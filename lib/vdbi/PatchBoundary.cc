// SPDX-License-Identifier: Apache-2.0

#include <vdbi/PatchBoundary.h>

#include <vdbi/ChordOwners.h>
#include <vdbi/Exceptions.h>

#include <algorithm>
#include <sstream>

namespace vdbi {

namespace {

using Vec3d = openvdb::Vec3d;
using Point = TriMesh::Point;
using VertexHandle = TriMesh::VertexHandle;
using HalfedgeHandle = TriMesh::HalfedgeHandle;
using EdgeHandle = TriMesh::EdgeHandle;
using FaceHandle = TriMesh::FaceHandle;

} // namespace


RemeshingPatch::RemeshingPatch(const InterfacePatch& patch, std::uint32_t patchIndex,
                               const PatchReference& reference, const FeatureCurves& curves)
    : mPatch(patch), mReference(reference), mCurves(curves), mPatchIndex(patchIndex)
{
}


bool
RemeshingPatch::mayJoinLocked(VertexHandle u, VertexHandle v) const
{
    return chordOwner(mCurves, std::uint32_t(mMesh.property(mSample, u)),
                      std::uint32_t(mMesh.property(mSample, v))) == mPatchIndex;
}


std::string
RemeshingPatch::where() const
{
    std::ostringstream os;
    os << "remeshing patch (" << mPatch.a << ", " << mPatch.b << ")";
    return os.str();
}


VertexHandle
RemeshingPatch::addInnerVertex(const Point& p, const Point& normal)
{
    const VertexHandle v = mMesh.add_vertex(p);
    mMesh.property(mSample, v) = -1;
    mMesh.property(mRefNormal, v) = normal;
    mMesh.property(mAnchor, v) = normal;
    mMesh.property(mRefTriangle, v) = std::uint32_t(-1);
    return v;
}


Point
RemeshingPatch::midpointNormal(VertexHandle a, VertexHandle b) const
{
    Point normal = refNormal(a) + refNormal(b);
    const double len = normal.norm();
    if (len > 0.0) normal /= len;
    return normal;
}


VertexHandle
RemeshingPatch::splitEdge(EdgeHandle e)
{
    const HalfedgeHandle h = mMesh.halfedge_handle(e, 0);
    const VertexHandle a = mMesh.from_vertex_handle(h), b = mMesh.to_vertex_handle(h);
    const VertexHandle m =
        addInnerVertex((mMesh.point(a) + mMesh.point(b)) * 0.5, midpointNormal(a, b));
    mMesh.property(mRefTriangle, m) = mMesh.property(mRefTriangle, a);
    mMesh.split(e, m);
    return m;
}


bool
RemeshingPatch::wouldStrandMidpoint(EdgeHandle e, double deviation2, double creaseCos) const
{
    const HalfedgeHandle h = mMesh.halfedge_handle(e, 0);
    const VertexHandle a = mMesh.from_vertex_handle(h), b = mMesh.to_vertex_handle(h);
    const Point midpoint = (mMesh.point(a) + mMesh.point(b)) * 0.5;
    const ReferenceSurface::Hit hit =
        reference().closestPointNear(toVec(midpoint), mMesh.property(mRefTriangle, a));
    return (toPoint(hit.point) - midpoint).sqrnorm() > deviation2
        && (toPoint(hit.normal) | midpointNormal(a, b)) < creaseCos;
}


void
RemeshingPatch::buildMesh()
{
    const std::vector<std::uint32_t>& rawPoints = mReference.rawPoints;
    const std::vector<Vec3d>& points = reference().points();
    const std::vector<Vec3d>& normals = reference().vertexNormals();
    mMesh.request_vertex_status();
    mMesh.request_edge_status();
    mMesh.request_halfedge_status();
    mMesh.request_face_status();
    mMesh.add_property(mSample, "v:sample");
    mMesh.add_property(mRefNormal, "v:refnormal");
    mMesh.add_property(mAnchor, "v:anchor");
    mMesh.add_property(mRefTriangle, "v:reftri");
    mMesh.reserve(rawPoints.size() * 2, rawPoints.size() * 6, mReference.triangles.size() * 2);
    for (std::size_t i = 0; i < rawPoints.size(); ++i) {
        const VertexHandle v = addInnerVertex(toPoint(points[i]), toPoint(normals[i]));
        mMesh.property(mSample, v) = mCurves.junctionSample(rawPoints[i]);
        mMesh.property(mRefTriangle, v) = reference().triangleAt(std::uint32_t(i));
    }
    for (const openvdb::Vec3I& t : mReference.triangles) {
        const FaceHandle f = mMesh.add_face(VertexHandle(int(t[0])), VertexHandle(int(t[1])),
                                            VertexHandle(int(t[2])));
        if (!f.is_valid()) {
            throw TopologyError(where() + ": a triangle makes a complex edge or vertex");
        }
    }
}


void
RemeshingPatch::separateLockedVertices()
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
RemeshingPatch::zipCurve(std::uint32_t curveIndex, bool forward)
{
    const std::vector<std::uint32_t>& rawPoints = mReference.rawPoints;
    auto local = [&](std::uint32_t p) {
        auto it = std::lower_bound(rawPoints.begin(), rawPoints.end(), p);
        if (it == rawPoints.end() || *it != p) {
            throw TopologyError(where() + ": a curve point is not in the patch");
        }
        return VertexHandle(int(it - rawPoints.begin()));
    };
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
                                              toPoint(reference().closestPoint(p).normal));
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
    if (m == 1 && n == 1) return;   // the extracted edge is the sample segment

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
        mZippedPoints.insert(mZippedPoints.end(), a.begin() + 1, a.end() - 1);
        for (std::size_t i = 0; i < m; ++i) addFace(c, a[i], a[i + 1]);
        addFace(c, a[m], a[0]);
        return;
    }
    // Zip the two chains by arc length: every triangle has one edge on one chain and its
    // third corner on the other. The faces sit on the outer side of the old boundary.
    mZippedPoints.insert(mZippedPoints.end(), a.begin() + 1, a.end() - 1);
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


void
RemeshingPatch::attachCurveSamples()
{
    buildMesh();
    separateLockedVertices();
    for (const auto& [curveIndex, forward] : mReference.curveDirections) {
        zipCurve(curveIndex, forward);
    }
    std::sort(mExpectedBoundary.begin(), mExpectedBoundary.end());
    separateLockedVertices();
    relaxZippedPoints();
    if (!hasExpectedBoundary()) {
        throw TopologyError(where() + ": the boundary does not match the curve samples");
    }
}


void
RemeshingPatch::relaxZippedPoints()
{
    // The zipper's triangles are slivers between points of one curve (the samples lie on the
    // polyline of the extracted points), folded wherever the curve bends: most of the
    // crossings the remesher starts with. Three sweeps of moving the extracted points to the
    // mean of their neighbours open the strip into the patch; projection takes them back
    // onto the reference surface.
    std::vector<VertexHandle> points;
    for (const VertexHandle v : mZippedPoints) {
        if (isFree(v)) points.push_back(v);
    }
    std::vector<Point> moved(points.size());
    for (int sweep = 0; sweep < 3; ++sweep) {
        for (std::size_t k = 0; k < points.size(); ++k) {
            Point sum(0, 0, 0);
            double count = 0.0;
            for (const VertexHandle w : mMesh.vv_range(points[k])) {
                sum += mMesh.point(w);
                count += 1.0;
            }
            moved[k] = count > 0.0 ? sum / count : mMesh.point(points[k]);
        }
        for (std::size_t k = 0; k < points.size(); ++k) mMesh.set_point(points[k], moved[k]);
    }
}


bool
RemeshingPatch::hasExpectedBoundary() const
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
        const VertexHandle u = mMesh.from_vertex_handle(h), v = mMesh.to_vertex_handle(h);
        if (isLocked(u) && isLocked(v) && !mayJoinLocked(u, v)) return false;
    }
    return true;
}


PatchResult
RemeshingPatch::exportMesh(bool measureReference) const
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
            const openvdb::Vec3d p = toVec(mMesh.point(v));
            result.innerPoints.push_back(p);
            if (!measureReference) continue;
            const ReferenceSurface::Hit hit =
                reference().closestPointNear(p, mMesh.property(mRefTriangle, v));
            result.referenceDistances.push_back((hit.point - p).length());
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

} // namespace vdbi
