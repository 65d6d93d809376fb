// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/GeometryArrays.h
/// @brief What a host application (the Houdini SOP) needs around the pipeline: the result as
/// flat arrays ready for block copies into its geometry, and its string parameters parsed.
/// @details The SOP makes only HDK calls; everything it computes is here, so that it is tested
/// without Houdini. Nothing here depends on Houdini or on a mesh library.

#ifndef VDBI_GEOMETRY_ARRAYS_HAS_BEEN_INCLUDED
#define VDBI_GEOMETRY_ARRAYS_HAS_BEEN_INCLUDED

#include <vdbi/InterfaceMesh.h>
#include <vdbi/Types.h>

#include <string>
#include <vector>

namespace vdbi {

/// @brief An InterfaceMesh as flat arrays, one entry per point, per vertex or per primitive.
/// @details Primitives are the triangles of the mesh, in the same order (patch by patch).
struct GeometryArrays
{
    /// [out] #points * 3 coordinates x0 y0 z0 x1 ..., world space, rounded to float (the
    /// precision of Houdini's P).
    std::vector<float> points;
    /// [out] #triangles * 3 point indices, counter-clockwise seen from label b (the patch
    /// orientation of InterfaceMesh). int, as GU_PrimPoly::buildBlock takes them.
    std::vector<int> vertices;
    /// [out] #primitives vertex counts (all 3): the list GEO_PolyCounts is built from.
    std::vector<int> polyCounts;
    /// [out] #primitives labels: the patch's a and b (a < b).
    std::vector<Label> labelA, labelB;
    /// [out] #primitives index into patchNames (the patch of the triangle).
    std::vector<int> patch;
    /// [out] #patches names, in patch order, see patchName().
    std::vector<std::string> patchNames;

    std::size_t pointCount() const { return points.size() / 3; }
    std::size_t primitiveCount() const { return polyCounts.size(); }
};

/// @brief Flat arrays of @a mesh for block copies into host geometry.
/// @throw openvdb::ValueError if the mesh has more points than an int can index, or a
/// triangle or patch refers past the end of the points or triangles (a malformed mesh)
GeometryArrays makeGeometryArrays(const InterfaceMesh& mesh);

/// @brief The name of the patch between labels @a a and @a b: "patch_A_B", with a negative
/// label written as "m" and its magnitude, e.g. patchName(-3, 5) == "patch_m3_5".
/// @details Names contain only letters, digits and underscores, so they are valid Houdini
/// group and attribute-value tokens and distinct for distinct (a, b).
std::string patchName(Label a, Label b);

/// @brief Parses separation constraints written "A B C; D E F": each constraint is three
/// integer labels, "A and B are always separated by C"; constraints are separated by ';' or
/// a line break, the labels of one constraint by spaces, tabs or commas. Empty constraints
/// (an empty string, a trailing ';') are skipped.
/// @details Only the syntax is checked here; validateConstraints() checks the set.
/// @throw openvdb::ValueError naming the bad token (not an integer, out of range) or the
/// constraint that has other than three labels
std::vector<SeparationConstraint> parseConstraints(const std::string& text);

/// @brief Parses a label list "L1 L2 ..." or "L1, L2, ...", e.g. the priority order for
/// LabelPriority. Spaces, tabs, line breaks and commas separate labels; an empty string gives
/// an empty list.
/// @throw openvdb::ValueError naming the bad token (not an integer, out of range)
std::vector<Label> parseLabels(const std::string& text);

} // namespace vdbi

#endif // VDBI_GEOMETRY_ARRAYS_HAS_BEEN_INCLUDED
