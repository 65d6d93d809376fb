// SPDX-License-Identifier: Apache-2.0

#include "support/MeshQuality.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <utility>
#include <vector>

namespace vdbi_test {

using openvdb::Vec3d;

std::string
MeshQuality::summary() const
{
    char line[400];
    std::snprintf(line, sizeof(line), "%zu triangles, edges in [0.5, 1.5] x target %.2f %%, min "
                  "angle %.1f / 1st pct %.1f / median %.1f deg, radius ratio %.3f / %.3f / %.3f",
                  triangles, 100.0 * inRange, minAngle, angleP1, angleMedian, radiusRatioMin,
                  radiusRatioP1, radiusRatioMedian);
    std::string result = line;
    std::snprintf(line, sizeof(line), "; out of range (short/long): curve %zu/%zu, next to a "
                  "curve %zu/%zu, inner %zu/%zu; under 25 deg with 0/1/2/3 corners on a curve "
                  "%zu/%zu/%zu/%zu", shortCurve, longCurve, shortNearCurve, longNearCurve,
                  shortInner, longInner, sharpByCurveCorners[0], sharpByCurveCorners[1],
                  sharpByCurveCorners[2], sharpByCurveCorners[3]);
    return result + line;
}


MeshQuality
measureMeshQuality(const vdbi::InterfaceMesh& mesh, double target)
{
    MeshQuality q;
    q.triangles = mesh.triangles.size();
    // (edge, patch) of every triangle side: a side met once in its patch is on a curve.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> sides;
    sides.reserve(3 * mesh.triangles.size());
    for (std::uint32_t p = 0; p < mesh.patches.size(); ++p) {
        const vdbi::InterfacePatch& patch = mesh.patches[p];
        for (std::size_t f = patch.firstTriangle; f < patch.firstTriangle + patch.triangleCount;
             ++f) {
            const openvdb::Vec3I& t = mesh.triangles[f];
            for (int i = 0; i < 3; ++i) {
                const std::uint64_t u = t[i], v = t[(i + 1) % 3];
                sides.emplace_back(std::min(u, v) << 32 | std::max(u, v), p);
            }
        }
    }
    std::sort(sides.begin(), sides.end());
    std::vector<std::uint64_t> curveEdges;
    std::vector<char> onCurve(mesh.points.size(), 0);
    for (std::size_t i = 0; i < sides.size();) {
        std::size_t j = i + 1;
        while (j < sides.size() && sides[j] == sides[i]) ++j;
        if (j - i == 1) {
            curveEdges.push_back(sides[i].first);
            onCurve[sides[i].first >> 32] = onCurve[sides[i].first & 0xffffffffu] = 1;
        }
        i = j;
    }
    std::sort(curveEdges.begin(), curveEdges.end());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    edges.reserve(3 * mesh.triangles.size());
    std::vector<double> angles, ratios;
    angles.reserve(mesh.triangles.size());
    ratios.reserve(mesh.triangles.size());
    for (const openvdb::Vec3I& t : mesh.triangles) {
        const Vec3d p[3] = {mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]};
        double smallest = 180.0, len[3];
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t u = t[i], v = t[(i + 1) % 3];
            edges.emplace_back(std::min(u, v), std::max(u, v));
            const Vec3d a = p[(i + 1) % 3] - p[i], b = p[(i + 2) % 3] - p[i];
            const double cosine = a.dot(b) / std::max(1e-300, a.length() * b.length());
            smallest = std::min(smallest, std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / M_PI);
            len[i] = a.length();
        }
        angles.push_back(smallest);
        const double area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
        const double s = 0.5 * (len[0] + len[1] + len[2]);
        // r_in = area / s, r_circ = abc / (4 area).
        ratios.push_back(area > 0.0 ? 8.0 * area * area / (s * len[0] * len[1] * len[2]) : 0.0);
    }
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        if (angles[t] >= 25.0) continue;
        const openvdb::Vec3I& tri = mesh.triangles[t];
        ++q.sharpByCurveCorners[onCurve[tri[0]] + onCurve[tri[1]] + onCurve[tri[2]]];
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    q.edges = edges.size();
    std::size_t good = 0;
    for (const auto& [u, v] : edges) {
        const double l = (mesh.points[u] - mesh.points[v]).length();
        if (l >= 0.5 * target && l <= 1.5 * target) {
            ++good;
            continue;
        }
        const bool curve = std::binary_search(curveEdges.begin(), curveEdges.end(),
                                              std::uint64_t(u) << 32 | v);
        const bool near = !curve && (onCurve[u] || onCurve[v]);
        std::size_t& count = l < 0.5 * target
            ? (curve ? q.shortCurve : near ? q.shortNearCurve : q.shortInner)
            : (curve ? q.longCurve : near ? q.longNearCurve : q.longInner);
        ++count;
    }
    q.inRange = edges.empty() ? 0.0 : double(good) / double(edges.size());
    if (!angles.empty()) {
        std::sort(angles.begin(), angles.end());
        std::sort(ratios.begin(), ratios.end());
        q.minAngle = angles.front();
        q.angleP1 = angles[angles.size() / 100];
        q.angleMedian = angles[angles.size() / 2];
        q.radiusRatioMin = ratios.front();
        q.radiusRatioP1 = ratios[ratios.size() / 100];
        q.radiusRatioMedian = ratios[ratios.size() / 2];
    }
    return q;
}

std::size_t
countTrianglesWithoutArea(const vdbi::InterfaceMesh& mesh)
{
    std::size_t count = 0;
    for (const openvdb::Vec3I& t : mesh.triangles) {
        const openvdb::Vec3d &a = mesh.points[t[0]], &b = mesh.points[t[1]],
                             &c = mesh.points[t[2]];
        const double longest2 =
            std::max({(b - a).lengthSqr(), (c - b).lengthSqr(), (a - c).lengthSqr()});
        count += (b - a).cross(c - a).length() <= 1e-10 * longest2;
    }
    return count;
}

} // namespace vdbi_test
