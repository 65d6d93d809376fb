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
    char line[320];
    std::snprintf(line, sizeof(line), "%zu triangles, edges in [0.5, 1.5] x target %.2f %%, min "
                  "angle %.1f / 1st pct %.1f / median %.1f deg, radius ratio %.3f / %.3f / %.3f",
                  triangles, 100.0 * inRange, minAngle, angleP1, angleMedian, radiusRatioMin,
                  radiusRatioP1, radiusRatioMedian);
    return line;
}


MeshQuality
measureMeshQuality(const vdbi::InterfaceMesh& mesh, double target)
{
    MeshQuality q;
    q.triangles = mesh.triangles.size();
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
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    q.edges = edges.size();
    std::size_t good = 0;
    for (const auto& [u, v] : edges) {
        const double l = (mesh.points[u] - mesh.points[v]).length();
        good += (l >= 0.5 * target && l <= 1.5 * target);
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

} // namespace vdbi_test
