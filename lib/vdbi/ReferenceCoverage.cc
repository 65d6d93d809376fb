// SPDX-License-Identifier: Apache-2.0

#include <vdbi/ReferenceCoverage.h>

#include <algorithm>
#include <limits>

namespace vdbi {

ReferenceCoverage::ReferenceCoverage(RemeshingPatch& patch)
    : mMesh(patch.mesh()), mPoints(patch.reference().points())
{
    mMesh.add_property(mFirst, "f:covered");
    for (const FaceHandle f : mMesh.faces()) mMesh.property(mFirst, f) = 0;
    mNext.assign(mPoints.size(), 0);
    for (std::size_t i = 0; i < mPoints.size(); ++i) {
        if (patch.isCurvePoint(i)) continue;
        const TriMesh::VertexHandle v{int(i)};
        for (const FaceHandle f : mMesh.vf_range(v)) {
            mNext[i] = mMesh.property(mFirst, f);
            mMesh.property(mFirst, f) = int(i) + 1;
            break;
        }
    }
}

ReferenceCoverage::~ReferenceCoverage()
{
    mMesh.remove_property(mFirst);
}

void
ReferenceCoverage::releaseOutside(FaceHandle f)
{
    int& first = mMesh.property(mFirst, f);
    if (first == 0) return;
    int i = first;
    first = 0;
    const bool deleted = mMesh.status(f).deleted();
    const TrianglePoints t = deleted ? TrianglePoints{} : trianglePoints(mMesh, f);
    while (i != 0) {
        const int next = mNext[i - 1];
        openvdb::Vec3d bary(0.0);
        if (!deleted) {
            closestPointOnTriangle(mPoints[i - 1], toVec(t.a), toVec(t.b), toVec(t.c), bary);
        }
        if (bary[0] > 0.0 && bary[1] > 0.0 && bary[2] > 0.0) {
            mNext[i - 1] = first;
            first = i;
        } else {
            mReleased.push_back(i - 1);
        }
        i = next;
    }
}

void
ReferenceCoverage::coverByNearest(const std::vector<FaceHandle>& faces)
{
    if (mReleased.empty()) return;
    mTriangles.resize(faces.size());
    mUnitNormals.resize(faces.size());
    for (std::size_t k = 0; k < faces.size(); ++k) {
        const TrianglePoints& t = mTriangles[k] = trianglePoints(mMesh, faces[k]);
        const Point n = (t.b - t.a) % (t.c - t.a);
        const double length = n.norm();
        mUnitNormals[k] = length > 0.0 ? n / length : Point(0, 0, 0);
    }
    for (const int i : mReleased) {
        const Point q = toPoint(mPoints[i]);
        std::size_t best = 0;
        double bestDistance = std::numeric_limits<double>::infinity();
        // Nothing is nearer than 0: the first face touching the point is the first of equals
        // (a point at a corner of the fan, a fifth of them in the first round).
        for (std::size_t k = 0; k < faces.size() && bestDistance > 0.0; ++k) {
            const TrianglePoints& t = mTriangles[k];
            // The distance to the face's plane bounds the distance to the face from below: a
            // face whose plane is farther than the best so far is skipped (with a margin for
            // rounding: the choice stays the one the full distances make).
            const double height = mUnitNormals[k] | (q - t.a);
            if (height * height > bestDistance * (1.0 + 1e-9)) continue;
            const double d = squaredDistanceToTriangle(q, t.a, t.b, t.c);
            if (d < bestDistance) {
                bestDistance = d;
                best = k;
            }
        }
        int& first = mMesh.property(mFirst, faces[best]);
        mNext[i] = first;
        first = i + 1;
    }
}

bool
ReferenceCoverage::allWithin(FaceHandle f, const TrianglePoints& t, double limit2) const
{
    for (int i = mMesh.property(mFirst, f); i != 0; i = mNext[i - 1]) {
        const Point q = toPoint(mPoints[i - 1]);
        if (squaredDistanceToTriangle(q, t.a, t.b, t.c) > limit2) return false;
    }
    return true;
}

bool
ReferenceCoverage::keepsCovered(const std::vector<FaceHandle>& faces,
                                const std::vector<TrianglePoints>& triangles, double limit2,
                                const std::vector<Point>* before, std::size_t checkCount) const
{
    const std::size_t count = triangles.size();
    for (std::size_t k = 0; k < std::min(checkCount, faces.size()); ++k) {
        const FaceHandle f = faces[k];
        const int first = mMesh.property(mFirst, f);
        if (first == 0) continue;
        for (int i = first; i != 0; i = mNext[i - 1]) {
            const Point q = toPoint(mPoints[i - 1]);
            // The triangle at the same place in the list first: mostly the face itself.
            double nearest = std::numeric_limits<double>::infinity();
            for (std::size_t j = 0; j < count && nearest > limit2; ++j) {
                const TrianglePoints& t = triangles[(k + j) % count];
                nearest = std::min(nearest, squaredDistanceToTriangle(q, t.a, t.b, t.c));
            }
            if (nearest <= limit2) continue;
            // Rare: only now is the face as it was needed.
            TrianglePoints old = trianglePoints(mMesh, f);
            if (before) {
                auto it = mMesh.cfv_iter(f);
                const TriMesh::VertexHandle a = *it, b = *++it, c = *++it;
                old = {(*before)[a.idx()], (*before)[b.idx()], (*before)[c.idx()]};
            }
            if (nearest > squaredDistanceToTriangle(q, old.a, old.b, old.c)) return false;
        }
    }
    return true;
}

} // namespace vdbi
