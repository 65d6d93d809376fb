// SPDX-License-Identifier: Apache-2.0

#include <vdbi/ReferenceSurface.h>

#include <vdbi/Exceptions.h>

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace vdbi {

namespace {

using Vec3d = openvdb::Vec3d;

/// Outgoing neighbours of every point, one per triangle corner (a closed 1-ring lists every
/// neighbour exactly once), in CSR form.
void
buildNeighbours(std::size_t pointCount, const std::vector<openvdb::Vec3I>& triangles,
                std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& neighbours)
{
    start.assign(pointCount + 1, 0);
    for (const openvdb::Vec3I& t : triangles) {
        for (int i = 0; i < 3; ++i) ++start[t[i] + 1];
    }
    for (std::size_t i = 1; i <= pointCount; ++i) start[i] += start[i - 1];
    neighbours.resize(start[pointCount]);
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (const openvdb::Vec3I& t : triangles) {
        for (int i = 0; i < 3; ++i) neighbours[fill[t[i]]++] = t[(i + 1) % 3];
    }
}

/// nanoflann's view of the vertex array.
struct PointCloud
{
    const std::vector<Vec3d>* points = nullptr;

    std::size_t kdtree_get_point_count() const { return points->size(); }
    double kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*points)[i][int(dim)]; }
    template<class BBox> bool kdtree_get_bbox(BBox&) const { return false; }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<double, PointCloud>, PointCloud, 3, std::uint32_t>;

/// Nearest vertices looked at per query; the closest point is searched on their triangles.
constexpr std::size_t NEAREST_VERTICES = 4;

} // namespace


Vec3d
clampDisplacement(const Vec3d& p, const Vec3d& origin, const Vec3d& bound)
{
    const Vec3d d = p - origin;
    const Vec3d scaled(d[0] / bound[0], d[1] / bound[1], d[2] / bound[2]);
    const double s2 = scaled.lengthSqr();
    return s2 > 1.0 ? origin + d / std::sqrt(s2) : p;
}


void
smoothSurfacePoints(std::vector<Vec3d>& points, const std::vector<Vec3d>& original,
                    const std::vector<openvdb::Vec3I>& triangles,
                    const std::vector<std::uint8_t>& fixed, int iterations,
                    const Vec3d& maxDisplacement)
{
    constexpr double LAMBDA = 0.5, MU = -0.53;   // Taubin's pass band pair
    std::vector<std::uint32_t> start, neighbours;
    buildNeighbours(points.size(), triangles, start, neighbours);
    std::vector<std::uint32_t> movable;
    for (std::uint32_t v = 0; v < points.size(); ++v) {
        if (!fixed[v] && start[v + 1] > start[v]) movable.push_back(v);
    }
    std::vector<Vec3d> previous;
    auto step = [&](double factor) {
        previous = points;
        for (std::uint32_t v : movable) {
            Vec3d sum(0.0);
            for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) sum += previous[neighbours[i]];
            const Vec3d mean = sum / double(start[v + 1] - start[v]);
            points[v] = clampDisplacement(previous[v] + (mean - previous[v]) * factor,
                                          original[v], maxDisplacement);
        }
    };
    for (int it = 0; it < iterations; ++it) {
        step(LAMBDA);
        step(MU);
    }
}


struct ReferenceSurface::Impl
{
    std::vector<Vec3d> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<Vec3d> normals;
    std::vector<std::uint32_t> triangleStart, vertexTriangles;   // CSR: triangles per vertex
    PointCloud cloud;
    std::unique_ptr<KdTree> tree;
};


ReferenceSurface::ReferenceSurface(std::vector<Vec3d> points,
                                   std::vector<openvdb::Vec3I> triangles)
    : mImpl(new Impl)
{
    Impl& m = *mImpl;
    m.points = std::move(points);
    m.triangles = std::move(triangles);
    const std::size_t n = m.points.size();
    m.normals.assign(n, Vec3d(0.0));
    m.triangleStart.assign(n + 1, 0);
    for (const openvdb::Vec3I& t : m.triangles) {
        const Vec3d& a = m.points[t[0]];
        const Vec3d normal = (m.points[t[1]] - a).cross(m.points[t[2]] - a);
        for (int i = 0; i < 3; ++i) {
            m.normals[t[i]] += normal;
            ++m.triangleStart[t[i] + 1];
        }
    }
    for (Vec3d& normal : m.normals) {
        const double len = normal.length();
        if (len > 0.0) normal /= len;
    }
    for (std::size_t i = 1; i <= n; ++i) m.triangleStart[i] += m.triangleStart[i - 1];
    m.vertexTriangles.resize(m.triangleStart[n]);
    std::vector<std::uint32_t> fill(m.triangleStart.begin(), m.triangleStart.end() - 1);
    for (std::uint32_t f = 0; f < m.triangles.size(); ++f) {
        for (int i = 0; i < 3; ++i) m.vertexTriangles[fill[m.triangles[f][i]]++] = f;
    }
    m.cloud.points = &m.points;
    m.tree.reset(new KdTree(3, m.cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16)));
}

ReferenceSurface::~ReferenceSurface() = default;
ReferenceSurface::ReferenceSurface(ReferenceSurface&&) noexcept = default;
ReferenceSurface& ReferenceSurface::operator=(ReferenceSurface&&) noexcept = default;

const std::vector<Vec3d>& ReferenceSurface::points() const { return mImpl->points; }
const std::vector<openvdb::Vec3I>& ReferenceSurface::triangles() const { return mImpl->triangles; }
const std::vector<Vec3d>& ReferenceSurface::vertexNormals() const { return mImpl->normals; }


namespace {

/// True if triangle @a t has a corner among the @a count vertices at @a vertices.
inline bool
hasCornerAmong(const openvdb::Vec3I& t, const std::uint32_t* vertices, std::size_t count)
{
    for (std::size_t j = 0; j < count; ++j) {
        if (std::uint32_t(t[0]) == vertices[j] || std::uint32_t(t[1]) == vertices[j]
            || std::uint32_t(t[2]) == vertices[j]) {
            return true;
        }
    }
    return false;
}

/// @brief Keeps in @a hit the closest of the triangles around the given vertices, the smaller
/// index among equally close ones; a triangle at one of the @a searchedCount vertices
/// @a searched was tested before and is skipped, as is one met around an earlier vertex.
/// Flattened: closestPointOnTriangle() is computed in place, not called through the PLT.
template<typename Impl>
[[gnu::flatten]] bool
searchAround(const Impl& m, const Vec3d& query, const std::uint32_t* vertices, std::size_t count,
             const std::uint32_t* searched, std::size_t searchedCount,
             ReferenceSurface::Hit& hit, Vec3d& bary, double& best)
{
    bool found = false;
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t v = vertices[k];
        for (std::uint32_t i = m.triangleStart[v]; i < m.triangleStart[v + 1]; ++i) {
            const std::uint32_t f = m.vertexTriangles[i];
            const openvdb::Vec3I& t = m.triangles[f];
            if (hasCornerAmong(t, vertices, k) || hasCornerAmong(t, searched, searchedCount)) {
                continue;
            }
            Vec3d b;
            const Vec3d c = closestPointOnTriangle(query, m.points[t[0]], m.points[t[1]],
                                                   m.points[t[2]], b);
            const double d2 = (c - query).lengthSqr();
            if (d2 < best || (d2 == best && f < hit.triangle)) {
                best = d2;
                hit.point = c;
                hit.triangle = f;
                bary = b;
                found = true;
            }
        }
    }
    return found;
}

/// @brief The points of triangles [begin, end) of @a mesh, ascending (@a rawPoints), and the
/// triangles in those local indices.
/// @details Through a table over the patch's range of point indices when that range is
/// small against the patch (the extraction numbers points block by block, so most patches
/// are compact); else by binary search in the sorted points.
void
numberPatchPoints(const InterfaceMesh& mesh, std::size_t begin, std::size_t end,
                  std::vector<std::uint32_t>& rawPoints, std::vector<openvdb::Vec3I>& triangles)
{
    triangles.resize(end - begin);
    if (begin == end) return;
    std::uint32_t low = ~std::uint32_t(0), high = 0;
    for (std::size_t t = begin; t < end; ++t) {
        for (int i = 0; i < 3; ++i) {
            low = std::min(low, std::uint32_t(mesh.triangles[t][i]));
            high = std::max(high, std::uint32_t(mesh.triangles[t][i]));
        }
    }
    const std::size_t range = std::size_t(high - low) + 1, corners = 3 * (end - begin);
    if (range <= 4 * corners) {
        constexpr std::uint32_t UNUSED = ~std::uint32_t(0);
        std::vector<std::uint32_t> local(range, UNUSED);
        for (std::size_t t = begin; t < end; ++t) {
            for (int i = 0; i < 3; ++i) local[mesh.triangles[t][i] - low] = 0;
        }
        rawPoints.clear();
        for (std::size_t p = 0; p < range; ++p) {
            if (local[p] == UNUSED) continue;
            local[p] = std::uint32_t(rawPoints.size());
            rawPoints.push_back(std::uint32_t(low + p));
        }
        for (std::size_t t = begin; t < end; ++t) {
            const openvdb::Vec3I& tri = mesh.triangles[t];
            triangles[t - begin] = openvdb::Vec3I(local[tri[0] - low], local[tri[1] - low],
                                                  local[tri[2] - low]);
        }
        return;
    }
    rawPoints.reserve(corners);
    for (std::size_t t = begin; t < end; ++t) {
        for (int i = 0; i < 3; ++i) rawPoints.push_back(mesh.triangles[t][i]);
    }
    std::sort(rawPoints.begin(), rawPoints.end());
    rawPoints.erase(std::unique(rawPoints.begin(), rawPoints.end()), rawPoints.end());
    auto local = [&](std::uint32_t p) {
        return std::uint32_t(std::lower_bound(rawPoints.begin(), rawPoints.end(), p)
                             - rawPoints.begin());
    };
    for (std::size_t t = begin; t < end; ++t) {
        const openvdb::Vec3I& tri = mesh.triangles[t];
        triangles[t - begin] = openvdb::Vec3I(local(tri[0]), local(tri[1]), local(tri[2]));
    }
}

} // namespace


void
ReferenceSurface::finishHit(Hit& hit, const Vec3d& bary) const
{
    const Impl& m = *mImpl;
    hit.barycentric = bary;
    const openvdb::Vec3I& t = m.triangles[hit.triangle];
    Vec3d normal = m.normals[t[0]] * bary[0] + m.normals[t[1]] * bary[1]
        + m.normals[t[2]] * bary[2];
    const double len = normal.length();
    if (len > 1e-12) {
        hit.normal = normal / len;
    } else {
        normal = (m.points[t[1]] - m.points[t[0]]).cross(m.points[t[2]] - m.points[t[0]]);
        const double l2 = normal.length();
        hit.normal = l2 > 0.0 ? normal / l2 : Vec3d(0, 0, 1);
    }
}


ReferenceSurface::Hit
ReferenceSurface::closestPoint(const Vec3d& query) const
{
    const Impl& m = *mImpl;
    std::uint32_t nearest[NEAREST_VERTICES];
    double dist2[NEAREST_VERTICES];
    const double q[3] = {query[0], query[1], query[2]};
    const std::size_t found = m.tree->knnSearch(q, NEAREST_VERTICES, nearest, dist2);

    Hit hit;
    Vec3d bary(1, 0, 0);
    double best = std::numeric_limits<double>::infinity();
    if (!searchAround(m, query, nearest, found, nullptr, 0, hit, bary, best)) {
        // Isolated vertices only: no triangle around them.
        hit.point = found ? m.points[nearest[0]] : query;
        hit.normal = found ? m.normals[nearest[0]] : Vec3d(0, 0, 1);
        return hit;
    }
    finishHit(hit, bary);
    return hit;
}


ReferenceSurface::Hit
ReferenceSurface::closestPointNear(const Vec3d& query, std::uint32_t start) const
{
    const Impl& m = *mImpl;
    if (start >= m.triangles.size()) return closestPoint(query);
    Hit hit;
    hit.triangle = start;
    Vec3d bary(1, 0, 0);
    double best = std::numeric_limits<double>::infinity();
    // The best of a step is the closest of the triangles around its corners, so no triangle
    // there beats it: the next step, from the best, skips them.
    std::uint32_t searched[3];
    std::size_t searchedCount = 0;
    for (int step = 0; step < 8; ++step) {
        const std::uint32_t current = hit.triangle;
        const openvdb::Vec3I& t = m.triangles[current];
        const std::uint32_t corners[3] = {t[0], t[1], t[2]};
        searchAround(m, query, corners, 3, searched, searchedCount, hit, bary, best);
        if (hit.triangle == current) {
            finishHit(hit, bary);
            return hit;
        }
        std::copy(corners, corners + 3, searched);
        searchedCount = 3;
    }
    return closestPoint(query);
}


std::uint32_t
ReferenceSurface::triangleAt(std::uint32_t v) const
{
    const Impl& m = *mImpl;
    if (v >= m.points.size() || m.triangleStart[v] == m.triangleStart[v + 1]) {
        return std::uint32_t(-1);
    }
    return m.vertexTriangles[m.triangleStart[v]];
}


PatchReference
buildPatchReference(const InterfaceMesh& mesh, std::size_t patch, const FeatureCurves& curves,
                    int iterations, const Vec3d& maxDisplacement)
{
    const InterfacePatch& info = mesh.patches[patch];
    auto fail = [&](const char* problem) {
        std::ostringstream os;
        os << "reference surface of patch (" << info.a << ", " << info.b << "): " << problem;
        throw TopologyError(os.str());
    };
    PatchReference result;
    const std::size_t begin = info.firstTriangle, end = begin + info.triangleCount;
    numberPatchPoints(mesh, begin, end, result.rawPoints, result.triangles);
    const std::vector<std::uint32_t>& rawPoints = result.rawPoints;

    const std::size_t n = rawPoints.size();
    std::vector<Vec3d> original(n), points(n);
    std::vector<std::uint8_t> fixed(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        original[i] = points[i] = mesh.points[rawPoints[i]];
        fixed[i] = curves.junctionSample(rawPoints[i]) >= 0;
    }
    // A triangle edge whose reverse is in no triangle is a boundary edge; the boundary runs
    // against it. Boundary points move onto their smoothed feature curve and stay there.
    // Reverses are looked up among the edges leaving each point (a handful), not in a sorted
    // list of all edges: linear time, and no sort of 3 x the triangle count.
    std::vector<std::uint32_t> firstOut(n + 1, 0), outTo(3 * result.triangles.size());
    for (const openvdb::Vec3I& t : result.triangles) {
        for (int i = 0; i < 3; ++i) ++firstOut[t[i] + 1];
    }
    for (std::size_t i = 1; i <= n; ++i) firstOut[i] += firstOut[i - 1];
    std::vector<std::uint32_t> fill(firstOut.begin(), firstOut.end() - 1);
    for (const openvdb::Vec3I& t : result.triangles) {
        for (int i = 0; i < 3; ++i) outTo[fill[t[i]]++] = t[(i + 1) % 3];
    }
    for (std::uint32_t v = 0; v < n; ++v) {
        for (std::uint32_t k = firstOut[v]; k < firstOut[v + 1]; ++k) {
            const std::uint32_t u = outTo[k];
            const auto from = outTo.begin() + firstOut[u], to = outTo.begin() + firstOut[u + 1];
            if (std::find(from, to, v) != to) continue;
            // v -> u has no reverse: the boundary runs u -> v.
            const FeatureEdge* edge = curves.findEdge(rawPoints[u], rawPoints[v]);
            if (!edge) fail("a boundary edge is no feature edge");
            const FeatureCurve& curve = curves.curves[edge->curve];
            const bool forward = curve.points[edge->segment] == rawPoints[u];
            points[u] = curve.smoothed[edge->segment + (forward ? 0 : 1)];
            points[v] = curve.smoothed[edge->segment + (forward ? 1 : 0)];
            fixed[u] = fixed[v] = 1;
            result.curveDirections.emplace_back(edge->curve, forward);
        }
    }
    auto& directions = result.curveDirections;
    std::sort(directions.begin(), directions.end());
    directions.erase(std::unique(directions.begin(), directions.end()), directions.end());
    for (std::size_t i = 1; i < directions.size(); ++i) {
        if (directions[i].first == directions[i - 1].first) {
            fail("the boundary runs both ways along a curve");
        }
    }
    smoothSurfacePoints(points, original, result.triangles, fixed, iterations, maxDisplacement);
    result.onCurve = std::move(fixed);
    result.surface.reset(new ReferenceSurface(std::move(points), result.triangles));
    return result;
}

} // namespace vdbi
