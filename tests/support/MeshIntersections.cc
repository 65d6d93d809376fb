// SPDX-License-Identifier: Apache-2.0

#include "support/MeshIntersections.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace vdbi_test {

using openvdb::Vec3d;
using openvdb::Vec3I;
using openvdb::Vec3i;

namespace {

/// Six times the signed volume of tetrahedron (a, b, c, d): positive when d lies on the side
/// of triangle (a, b, c) its counter-clockwise normal points to.
double
orient3d(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& d)
{
    return (b - a).cross(c - a).dot(d - a);
}

/// Twice the signed area of the 2D triangle (a, b, c).
double
orient2d(const Vec3d& a, const Vec3d& b, const Vec3d& c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/// Do the closed 2D segments ab and cd share a point?
bool
segmentsMeet2d(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& d)
{
    const double o1 = orient2d(a, b, c), o2 = orient2d(a, b, d);
    const double o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
    if (o1 == 0.0 && o2 == 0.0) {
        // Collinear: the projections onto the line overlap?
        const int k = std::abs(b[0] - a[0]) >= std::abs(b[1] - a[1]) ? 0 : 1;
        const double lo = std::min(a[k], b[k]), hi = std::max(a[k], b[k]);
        return std::max(lo, std::min(c[k], d[k])) <= std::min(hi, std::max(c[k], d[k]));
    }
    return (o1 * o2 <= 0.0) && (o3 * o4 <= 0.0);
}

/// Is 2D point p in the closed triangle (a, b, c) (either orientation)?
bool
insideTriangle2d(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c)
{
    const double o1 = orient2d(a, b, p), o2 = orient2d(b, c, p), o3 = orient2d(c, a, p);
    return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
}

/// Drops the coordinate along which @a normal is largest: the plane's 2D view.
Vec3d
project(const Vec3d& p, const Vec3d& normal)
{
    const Vec3d n(std::abs(normal[0]), std::abs(normal[1]), std::abs(normal[2]));
    if (n[0] >= n[1] && n[0] >= n[2]) return Vec3d(p[1], p[2], 0.0);
    if (n[1] >= n[2]) return Vec3d(p[2], p[0], 0.0);
    return Vec3d(p[0], p[1], 0.0);
}

/// Does the closed 2D segment pq meet the closed 2D triangle (a, b, c)?
bool
segmentMeetsTriangle2d(const Vec3d& p, const Vec3d& q, const Vec3d& a, const Vec3d& b,
                       const Vec3d& c)
{
    return segmentsMeet2d(p, q, a, b) || segmentsMeet2d(p, q, b, c)
        || segmentsMeet2d(p, q, c, a) || insideTriangle2d(p, a, b, c);
}

/// Does the closed segment pq meet the closed triangle (a, b, c)? Orientations within
/// @a zero of 0 count as 0 (see disjointTrianglesIntersect()): an end in the plane is tested
/// in the plane's 2D view, and so is a segment in the plane. The signs of the volumes the
/// segment makes with the triangle's edges tell the rest; they are noise when all the points
/// are that close to one plane.
bool
segmentMeetsTriangle(const Vec3d& p, const Vec3d& q, const Vec3d& a, const Vec3d& b,
                     const Vec3d& c, double zero)
{
    const double op = orient3d(a, b, c, p), oq = orient3d(a, b, c, q);
    if ((op > zero && oq > zero) || (op < -zero && oq < -zero)) return false;
    const bool pIn = std::abs(op) <= zero, qIn = std::abs(oq) <= zero;
    if (pIn || qIn) {
        const Vec3d normal = (b - a).cross(c - a);
        const Vec3d a2 = project(a, normal), b2 = project(b, normal), c2 = project(c, normal);
        if (pIn && qIn) {
            return segmentMeetsTriangle2d(project(p, normal), project(q, normal), a2, b2, c2);
        }
        return insideTriangle2d(project(pIn ? p : q, normal), a2, b2, c2);
    }
    const double s1 = orient3d(p, q, a, b), s2 = orient3d(p, q, b, c), s3 = orient3d(p, q, c, a);
    return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

/// Orientations of four points within this fraction of the cube of the triangles' longest
/// edge count as 0: the points are in one plane. Rounding gives those of points in one plane
/// any sign, and the tests in 3D then found crossings between triangles of a flat patch that
/// do not even share a bounding box (monu16 at 1 voxel: 19 of 23 pairs).
constexpr double FLAT = 1e-9;

/// Triangles without a common corner.
bool
disjointTrianglesIntersect(const Vec3d s[3], const Vec3d t[3])
{
    for (int k = 0; k < 3; ++k) {
        if (std::max({s[0][k], s[1][k], s[2][k]}) < std::min({t[0][k], t[1][k], t[2][k]})
            || std::max({t[0][k], t[1][k], t[2][k]}) < std::min({s[0][k], s[1][k], s[2][k]})) {
            return false;   // apart along axis k
        }
    }
    double longest2 = 0.0;
    for (int i = 0; i < 3; ++i) {
        longest2 = std::max({longest2, (s[(i + 1) % 3] - s[i]).lengthSqr(),
                             (t[(i + 1) % 3] - t[i]).lengthSqr()});
    }
    const double zero = FLAT * longest2 * std::sqrt(longest2);
    const double d0 = orient3d(s[0], s[1], s[2], t[0]), d1 = orient3d(s[0], s[1], s[2], t[1]),
                 d2 = orient3d(s[0], s[1], s[2], t[2]);
    if ((d0 > zero && d1 > zero && d2 > zero) || (d0 < -zero && d1 < -zero && d2 < -zero)) {
        return false;
    }
    if (std::abs(d0) <= zero && std::abs(d1) <= zero && std::abs(d2) <= zero) {
        const Vec3d normal = (s[1] - s[0]).cross(s[2] - s[0]);
        Vec3d s2[3], t2[3];
        for (int i = 0; i < 3; ++i) {
            s2[i] = project(s[i], normal);
            t2[i] = project(t[i], normal);
        }
        for (int i = 0; i < 3; ++i) {
            if (segmentMeetsTriangle2d(s2[i], s2[(i + 1) % 3], t2[0], t2[1], t2[2])) return true;
        }
        return insideTriangle2d(t2[0], s2[0], s2[1], s2[2]);
    }
    for (int i = 0; i < 3; ++i) {
        if (segmentMeetsTriangle(s[i], s[(i + 1) % 3], t[0], t[1], t[2], zero)) return true;
        if (segmentMeetsTriangle(t[i], t[(i + 1) % 3], s[0], s[1], s[2], zero)) return true;
    }
    return false;
}

/// Is direction d in the closed planar cone spanned by e1, e2 (normal n = e1 x e2)?
/// The last test keeps d off the opposite cone: it needs the bisector, e1 + e2 is not one
/// when the edges differ in length (a wide cone then missed directions near its short edge).
bool
inCone(const Vec3d& d, const Vec3d& e1, const Vec3d& e2, const Vec3d& n)
{
    return e1.cross(d).dot(n) >= 0.0 && d.cross(e2).dot(n) >= 0.0
        && d.dot(e1 / e1.length() + e2 / e2.length()) > 0.0;
}

/// Is direction d strictly inside the 2D cone from e1 to e2 (either orientation)?
bool
strictlyInCone2d(const Vec3d& d, const Vec3d& e1, const Vec3d& e2)
{
    const Vec3d o(0.0);
    const double turn = orient2d(o, e1, e2);
    const double a = orient2d(o, e1, d), b = orient2d(o, d, e2);
    return turn > 0 ? (a > 0 && b > 0) : (a < 0 && b < 0);
}

/// Triangles with exactly one common corner v; e*, f* the edges from v.
bool
conesOverlap(const Vec3d& e1, const Vec3d& e2, const Vec3d& f1, const Vec3d& f2)
{
    const Vec3d ns = e1.cross(e2), nt = f1.cross(f2);
    const Vec3d d = ns.cross(nt);
    // Near v each triangle is its cone, and each lies inside it: the triangles meet beyond v
    // exactly when the cones share a ray (on the planes' common line, or in a common plane).
    if (d.lengthSqr() > 1e-24 * ns.lengthSqr() * nt.lengthSqr()) {
        return (inCone(d, e1, e2, ns) && inCone(d, f1, f2, nt))
            || (inCone(-d, e1, e2, ns) && inCone(-d, f1, f2, nt));
    }
    const Vec3d a1 = project(e1, ns), a2 = project(e2, ns), b1 = project(f1, ns),
                b2 = project(f2, ns);
    const Vec3d abis = a1 / a1.length() + a2 / a2.length();
    const Vec3d bbis = b1 / b1.length() + b2 / b2.length();
    return strictlyInCone2d(b1, a1, a2) || strictlyInCone2d(b2, a1, a2)
        || strictlyInCone2d(a1, b1, b2) || strictlyInCone2d(a2, b1, b2)
        || strictlyInCone2d(bbis, a1, a2) || strictlyInCone2d(abis, b1, b2);
}

/// Closest distance from p to triangle (a, b, c): the nearest of the plane foot point (when
/// it lies inside) and the three edges.
double
pointTriangleDistance(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c)
{
    auto toSegment = [&](const Vec3d& u, const Vec3d& v) {
        const Vec3d uv = v - u;
        const double len2 = uv.lengthSqr();
        const double t = len2 > 0 ? std::clamp((p - u).dot(uv) / len2, 0.0, 1.0) : 0.0;
        return (u + uv * t - p).lengthSqr();
    };
    double best = std::min({toSegment(a, b), toSegment(b, c), toSegment(c, a)});
    const Vec3d n = (b - a).cross(c - a);
    const double n2 = n.lengthSqr();
    if (n2 > 0) {
        const Vec3d foot = p - n * ((p - a).dot(n) / n2);
        const double u = (b - a).cross(foot - a).dot(n), v = (c - b).cross(foot - b).dot(n),
                     w = (a - c).cross(foot - c).dot(n);
        if (u >= 0 && v >= 0 && w >= 0) best = std::min(best, (foot - p).lengthSqr());
    }
    return std::sqrt(best);
}

} // namespace


TriangleGrid::TriangleGrid(const vdbi::PointArray& points, const vdbi::TriangleArray& triangles,
                           std::size_t first, std::size_t count, double cellSize)
    : mPoints(points), mTriangles(triangles), mCellSize(cellSize), mFirst(first)
{
    mLow.resize(count);
    mHigh.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        const Vec3I& t = triangles[first + i];
        Vec3d lo = points[t[0]], hi = points[t[0]];
        for (int k = 1; k < 3; ++k) {
            lo = openvdb::math::minComponent(lo, points[t[k]]);
            hi = openvdb::math::maxComponent(hi, points[t[k]]);
        }
        mLow[i] = cellCoord(lo);
        mHigh[i] = cellCoord(hi);
        for (int x = mLow[i][0]; x <= mHigh[i][0]; ++x) {
            for (int y = mLow[i][1]; y <= mHigh[i][1]; ++y) {
                for (int z = mLow[i][2]; z <= mHigh[i][2]; ++z) {
                    mCells[cellOf(Vec3i(x, y, z))].push_back(std::uint32_t(i));
                }
            }
        }
    }
}


TriangleGrid::CellKey
TriangleGrid::cellOf(const Vec3i& c) const
{
    // 21 bits per axis, offset so that negative cells stay distinct.
    const std::uint64_t mask = (std::uint64_t(1) << 21) - 1;
    return (std::uint64_t(c[0] + (1 << 20)) & mask) << 42
        | (std::uint64_t(c[1] + (1 << 20)) & mask) << 21
        | (std::uint64_t(c[2] + (1 << 20)) & mask);
}


Vec3i
TriangleGrid::cellCoord(const Vec3d& p) const
{
    return Vec3i(int(std::floor(p[0] / mCellSize)), int(std::floor(p[1] / mCellSize)),
                 int(std::floor(p[2] / mCellSize)));
}


double
TriangleGrid::distanceWithin(const Vec3d& q, double radius) const
{
    const Vec3i lo = cellCoord(q - Vec3d(radius)), hi = cellCoord(q + Vec3d(radius));
    double best = 2.0 * radius + 1.0;
    for (int x = lo[0]; x <= hi[0]; ++x) {
        for (int y = lo[1]; y <= hi[1]; ++y) {
            for (int z = lo[2]; z <= hi[2]; ++z) {
                const auto it = mCells.find(cellOf(Vec3i(x, y, z)));
                if (it == mCells.end()) continue;
                for (const std::uint32_t i : it->second) {
                    const Vec3I& t = mTriangles[mFirst + i];
                    best = std::min(best, pointTriangleDistance(q, mPoints[t[0]], mPoints[t[1]],
                                                                mPoints[t[2]]));
                }
            }
        }
    }
    return best;
}


bool
trianglesIntersect(const vdbi::PointArray& points, const Vec3I& s, const Vec3I& t)
{
    int shared = 0, si = -1, ti = -1;   // the last common corner's positions
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (s[i] == t[j]) {
                ++shared;
                si = i;
                ti = j;
            }
        }
    }
    const Vec3d S[3] = {points[s[0]], points[s[1]], points[s[2]]};
    const Vec3d T[3] = {points[t[0]], points[t[1]], points[t[2]]};
    if (shared == 3) return true;
    if (shared == 0) return disjointTrianglesIntersect(S, T);
    if (shared == 1) {
        return conesOverlap(S[(si + 1) % 3] - S[si], S[(si + 2) % 3] - S[si],
                            T[(ti + 1) % 3] - T[ti], T[(ti + 2) % 3] - T[ti]);
    }
    // A common edge (u, v): the triangles meet elsewhere only when folded onto one plane,
    // their third corners on the same side of the edge.
    std::uint32_t sw = 0, tw = 0;
    for (int i = 0; i < 3; ++i) {
        if (s[i] != t[0] && s[i] != t[1] && s[i] != t[2]) sw = s[i];
        if (t[i] != s[0] && t[i] != s[1] && t[i] != s[2]) tw = t[i];
    }
    std::uint32_t u = 0, v = 0;
    for (int i = 0, k = 0; i < 3; ++i) {
        if (s[i] != sw) (k++ == 0 ? u : v) = s[i];
    }
    const Vec3d &pu = points[u], &pv = points[v], &ps = points[sw], &pt = points[tw];
    const Vec3d ns = (pv - pu).cross(ps - pu), nt = (pv - pu).cross(pt - pu);
    const double volume = std::abs(orient3d(pu, pv, ps, pt));
    const double scale = (pv - pu).length() * (ps - pu).length() * (pt - pu).length();
    return volume <= 1e-12 * scale && ns.dot(nt) > 0.0;
}


std::vector<Intersection>
findSelfIntersections(const vdbi::InterfaceMesh& mesh, double cellSize, std::size_t limit)
{
    std::vector<Intersection> found;
    const TriangleGrid grid(mesh.points, mesh.triangles, 0, mesh.triangles.size(), cellSize);
    grid.forEachCandidatePair([&](std::uint32_t a, std::uint32_t b) {
        if (found.size() >= limit) return;
        if (trianglesIntersect(mesh.points, mesh.triangles[a], mesh.triangles[b])) {
            found.push_back({std::min(a, b), std::max(a, b)});
        }
    });
    std::sort(found.begin(), found.end(), [](const Intersection& x, const Intersection& y) {
        return x.first != y.first ? x.first < y.first : x.second < y.second;
    });
    return found;
}


std::string
describeIntersections(const vdbi::InterfaceMesh& mesh, const std::vector<Intersection>& found)
{
    if (found.empty()) return "";
    auto patchOf = [&](std::uint32_t t) {
        for (const vdbi::InterfacePatch& p : mesh.patches) {
            if (t >= p.firstTriangle && t < p.firstTriangle + p.triangleCount) {
                std::ostringstream os;
                os << "(" << p.a << ", " << p.b << ")";
                return os.str();
            }
        }
        return std::string("(none)");
    };
    std::ostringstream os;
    os << found.size() << " intersecting triangle pairs, e.g.";
    for (std::size_t i = 0; i < std::min<std::size_t>(found.size(), 5); ++i) {
        const Intersection& x = found[i];
        os << " [" << x.first << " of " << patchOf(x.first) << " at " << mesh.points[
            mesh.triangles[x.first][0]] << " x " << x.second << " of " << patchOf(x.second)
           << "]";
    }
    return os.str();
}


Closeness
measureCloseness(const vdbi::InterfaceMesh& raw, const vdbi::InterfaceMesh& out,
                 const Vec3d& voxelSize, double radius)
{
    auto scaled = [&](const vdbi::PointArray& points) {
        vdbi::PointArray result(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) {
            for (int k = 0; k < 3; ++k) result[i][k] = points[i][k] / voxelSize[k];
        }
        return result;
    };
    const vdbi::PointArray rawPoints = scaled(raw.points), outPoints = scaled(out.points);
    Closeness result;
    std::vector<std::uint32_t> vertices;
    for (std::size_t p = 0; p < raw.patches.size(); ++p) {
        const vdbi::InterfacePatch &rp = raw.patches[p], &op = out.patches[p];
        const TriangleGrid rawGrid(rawPoints, raw.triangles, rp.firstTriangle, rp.triangleCount,
                                   1.0);
        const TriangleGrid outGrid(outPoints, out.triangles, op.firstTriangle, op.triangleCount,
                                   1.0);
        vertices.clear();
        for (std::size_t t = op.firstTriangle; t < op.firstTriangle + op.triangleCount; ++t) {
            for (int i = 0; i < 3; ++i) vertices.push_back(out.triangles[t][i]);
        }
        std::sort(vertices.begin(), vertices.end());
        vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
        for (const std::uint32_t v : vertices) {
            result.vertexToRaw = std::max(result.vertexToRaw,
                                          rawGrid.distanceWithin(outPoints[v], radius));
        }
        for (std::size_t t = rp.firstTriangle; t < rp.firstTriangle + rp.triangleCount; ++t) {
            const Vec3I& tri = raw.triangles[t];
            const Vec3d centre = (rawPoints[tri[0]] + rawPoints[tri[1]] + rawPoints[tri[2]]) / 3.0;
            result.rawToOutput = std::max(result.rawToOutput,
                                          outGrid.distanceWithin(centre, radius));
            const Vec3d faceCentre =
                voxelFaceCentre(rawPoints[tri[0]], rawPoints[tri[1]], rawPoints[tri[2]]);
            result.faceCentreToOutput = std::max(result.faceCentreToOutput,
                                                 outGrid.distanceWithin(faceCentre, radius));
        }
    }
    return result;
}


std::set<std::pair<std::uint32_t, std::uint32_t>>
intersectingPairs(const vdbi::InterfaceMesh& mesh, double cellSize)
{
    std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (const Intersection& x : findSelfIntersections(mesh, cellSize, std::size_t(-1))) {
        pairs.insert({x.first, x.second});
    }
    return pairs;
}

} // namespace vdbi_test
