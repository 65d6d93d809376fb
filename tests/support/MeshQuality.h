// SPDX-License-Identifier: Apache-2.0
/// @file support/MeshQuality.h
/// @brief Shape figures of a triangle mesh, as the remeshing issue reports them: the
/// smallest angle of every triangle, its radius ratio and the edge lengths against a target.

#pragma once

#include <vdbi/InterfaceMesh.h>

#include <string>

namespace vdbi_test {

struct MeshQuality
{
    std::size_t triangles = 0, edges = 0;
    double inRange = 0.0;   ///< fraction of edges within [0.5, 1.5] x target
    /// Edges out of range, by kind: on a feature curve (a patch boundary), inner with an end
    /// on a curve, inner away from the curves; too short and too long.
    std::size_t shortCurve = 0, shortNearCurve = 0, shortInner = 0;
    std::size_t longCurve = 0, longNearCurve = 0, longInner = 0;
    /// Triangles with a smallest angle below 25 degrees, by how many corners lie on a
    /// feature curve (0, 1, 2 or 3).
    std::size_t sharpByCurveCorners[4] = {0, 0, 0, 0};
    /// Smallest angle of every triangle, in degrees: min, 1st percentile, median.
    double minAngle = 0.0, angleP1 = 0.0, angleMedian = 0.0;
    /// Radius ratio 2 r_in / r_circ of every triangle (1 for an equilateral one): min, 1st
    /// percentile, median.
    double radiusRatioMin = 0.0, radiusRatioP1 = 0.0, radiusRatioMedian = 0.0;

    /// One line: "N triangles, edges in range X %, min angle ..., radius ratio ...".
    std::string summary() const;
};

/// @brief Measures every triangle and every (undirected) edge of @a mesh.
MeshQuality measureMeshQuality(const vdbi::InterfaceMesh& mesh, double target);

/// @brief How many triangles of @a mesh have no area: twice the area at most 1e-10 times the
/// longest edge squared (a corner on the line through the other two has no normal).
std::size_t countTrianglesWithoutArea(const vdbi::InterfaceMesh& mesh);

} // namespace vdbi_test
