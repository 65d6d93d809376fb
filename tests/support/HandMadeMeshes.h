// SPDX-License-Identifier: Apache-2.0
/// @file support/HandMadeMeshes.h
/// @brief Interface meshes written out by hand in tests: points and the triangles of each
/// patch.

#pragma once

#include <vdbi/InterfaceMesh.h>

#include <vector>

namespace vdbi_test {

/// One patch (a, b) of consecutive triangles.
struct PatchSpec
{
    vdbi::Label a, b;
    std::vector<openvdb::Vec3I> triangles;
};

/// The mesh of @a points and @a patches, in that order (sorted by (a, b) if the test needs
/// that).
vdbi::InterfaceMesh makeMesh(const std::vector<openvdb::Vec3d>& points,
                             const std::vector<PatchSpec>& patches);

} // namespace vdbi_test
