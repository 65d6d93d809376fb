// SPDX-License-Identifier: Apache-2.0

#include <vdbi/PatchMeshes.h>

#include <vdbi/Exceptions.h>
#include <vdbi/ParallelRanges.h>

#include <sstream>
#include <unordered_map>

namespace vdbi {

namespace {

void
convertPatch(const InterfaceMesh& in, const InterfacePatch& patch, PatchMesh& out)
{
    out.a = patch.a;
    out.b = patch.b;
    std::unordered_map<std::uint32_t, TriMesh::VertexHandle> handles;
    handles.reserve(patch.triangleCount);
    auto vertexOf = [&](std::uint32_t p) {
        auto it = handles.find(p);
        if (it != handles.end()) return it->second;
        const openvdb::Vec3d& q = in.points[p];
        const TriMesh::VertexHandle vh = out.mesh.add_vertex(toPoint(q));
        out.pointIndex.push_back(p);
        handles.emplace(p, vh);
        return vh;
    };
    const std::size_t end = patch.firstTriangle + patch.triangleCount;
    for (std::size_t t = patch.firstTriangle; t < end; ++t) {
        const openvdb::Vec3I& tri = in.triangles[t];
        const TriMesh::FaceHandle fh = out.mesh.add_face(vertexOf(tri[0]), vertexOf(tri[1]),
                                                         vertexOf(tri[2]));
        if (!fh.is_valid()) {
            std::ostringstream os;
            os << "patch (" << patch.a << ", " << patch.b << "): triangle " << t
               << " makes a complex edge or vertex";
            throw TopologyError(os.str());
        }
    }
}

} // namespace

std::vector<PatchMesh>
toPatchMeshes(const InterfaceMesh& mesh, bool threaded)
{
    std::vector<PatchMesh> patches(mesh.patches.size());
    forEachRange(patches.size(), 1, threaded, [&](std::size_t begin, std::size_t end) {
        for (std::size_t p = begin; p < end; ++p) convertPatch(mesh, mesh.patches[p], patches[p]);
    });
    return patches;
}

} // namespace vdbi
