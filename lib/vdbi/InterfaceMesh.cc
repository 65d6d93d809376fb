// SPDX-License-Identifier: Apache-2.0

#include <vdbi/InterfaceMesh.h>

#include <algorithm>

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
                      std::vector<std::uint32_t>& around, const std::vector<char>* skip)
{
    auto skipped = [&](std::size_t f) { return skip && (*skip)[f]; };
    first.assign(mesh.points.size() + 1, 0);
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
        if (skipped(f)) continue;
        for (int i = 0; i < 3; ++i) ++first[mesh.triangles[f][i] + 1];
    }
    for (std::size_t v = 0; v + 1 < first.size(); ++v) first[v + 1] += first[v];
    around.resize(first.back());
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        if (skipped(f)) continue;
        for (int i = 0; i < 3; ++i) around[fill[mesh.triangles[f][i]]++] = f;
    }
}


std::vector<std::size_t>
patchSizes(const InterfaceMesh& mesh)
{
    std::vector<std::size_t> sizes;
    for (const InterfacePatch& patch : mesh.patches) sizes.push_back(patch.triangleCount);
    return sizes;
}


std::vector<std::uint32_t>
trianglePatches(const InterfaceMesh& mesh)
{
    std::vector<std::uint32_t> patchOf(mesh.triangles.size());
    for (std::uint32_t p = 0; p < mesh.patches.size(); ++p) {
        const InterfacePatch& patch = mesh.patches[p];
        std::fill_n(patchOf.begin() + patch.firstTriangle, patch.triangleCount, p);
    }
    return patchOf;
}


std::int64_t
triangleAcross(const InterfaceMesh& mesh, const std::vector<std::uint32_t>& first,
               const std::vector<std::uint32_t>& around, const std::vector<std::uint32_t>& patchOf,
               std::uint32_t f, std::uint32_t u, std::uint32_t v)
{
    std::int64_t other = -1;
    for (std::uint32_t k = first[u]; k < first[u + 1]; ++k) {
        const std::uint32_t g = around[k];
        const openvdb::Vec3I& t = mesh.triangles[g];
        if (g == f || (t[0] != v && t[1] != v && t[2] != v)) continue;
        if (other >= 0 || patchOf[g] != patchOf[f]) return -1;
        const bool reversed = (t[0] == v && t[1] == u) || (t[1] == v && t[2] == u)
            || (t[2] == v && t[0] == u);
        if (!reversed) return -1;
        other = g;
    }
    return other;
}

} // namespace vdbi
