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

} // namespace vdbi
