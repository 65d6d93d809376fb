// SPDX-License-Identifier: Apache-2.0

#include <vdbi/InterfaceMesh.h>

namespace vdbi {

std::vector<std::array<Label, 2>>
InterfaceMesh::triangleLabels() const
{
    std::vector<std::array<Label, 2>> labels(triangles.size());
    for (const InterfacePatch& p : patches) {
        for (std::size_t t = p.firstTriangle; t < p.firstTriangle + p.triangleCount; ++t) {
            labels[t] = {p.a, p.b};
        }
    }
    return labels;
}


void
trianglesAroundPoints(const InterfaceMesh& mesh, std::vector<std::uint32_t>& first,
                      std::vector<std::uint32_t>& around)
{
    first.assign(mesh.points.size() + 1, 0);
    around.resize(3 * mesh.triangles.size());
    for (const openvdb::Vec3I& t : mesh.triangles) {
        for (int i = 0; i < 3; ++i) ++first[t[i] + 1];
    }
    for (std::size_t v = 0; v + 1 < first.size(); ++v) first[v + 1] += first[v];
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        for (int i = 0; i < 3; ++i) around[fill[mesh.triangles[f][i]]++] = f;
    }
}

} // namespace vdbi
