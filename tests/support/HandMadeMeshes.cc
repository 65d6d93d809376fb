// SPDX-License-Identifier: Apache-2.0

#include "HandMadeMeshes.h"

namespace vdbi_test {

vdbi::InterfaceMesh
makeMesh(const std::vector<openvdb::Vec3d>& points, const std::vector<PatchSpec>& patches)
{
    vdbi::InterfaceMesh mesh;
    mesh.points.assign(points.begin(), points.end());
    for (const PatchSpec& spec : patches) {
        vdbi::InterfacePatch patch;
        patch.a = spec.a;
        patch.b = spec.b;
        patch.firstTriangle = mesh.triangles.size();
        patch.triangleCount = spec.triangles.size();
        mesh.triangles.insert(mesh.triangles.end(), spec.triangles.begin(), spec.triangles.end());
        mesh.patches.push_back(patch);
    }
    return mesh;
}

} // namespace vdbi_test
