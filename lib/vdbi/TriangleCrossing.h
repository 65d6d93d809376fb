// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/TriangleCrossing.h
/// @brief Crossings between triangles of one mesh, other than in the corners and edges they
/// share: what the remesher counts before and after an operation, so that none folds one
/// triangle through another.
/// @details Predicates are orientation determinants in double precision. Exactly coplanar
/// triangles are common (a flat stretch of the reference surface stays exactly flat), so
/// they are handled in their plane; otherwise touching does not count as crossing.

#ifndef VDBI_TRIANGLE_CROSSING_HAS_BEEN_INCLUDED
#define VDBI_TRIANGLE_CROSSING_HAS_BEEN_INCLUDED

#include <vdbi/PatchMeshes.h>

#include <algorithm>
#include <vector>

namespace vdbi {

/// A triangle by its corner positions and the ids of its corners (vertex indices): corners
/// with equal ids are the same point.
struct CornerTriangle
{
    using Point = TriMesh::Point;
    Point p[3];
    int id[3] = {-1, -1, -1};
    Point low, high;   ///< bounding box
    Point normal;      ///< (p1 - p0) x (p2 - p0)

    CornerTriangle() = default;
    CornerTriangle(const Point& a, const Point& b, const Point& c, int ia, int ib, int ic)
        : p{a, b, c}, id{ia, ib, ic}, normal((b - a) % (c - a))
    {
        for (int k = 0; k < 3; ++k) {
            low[k] = std::min({a[k], b[k], c[k]});
            high[k] = std::max({a[k], b[k], c[k]});
        }
    }
    bool hasCorner(int i) const { return id[0] == i || id[1] == i || id[2] == i; }
};

/// Has triangle (a, b, c) no area to speak of (a corner on the line through the others, as a
/// split's midpoint is)? Its normal is noise: no fold or crossing test can judge it.
bool hasNoArea(const CornerTriangle::Point& a, const CornerTriangle::Point& b,
               const CornerTriangle::Point& c);

/// @brief Do @a s and @a t have a common point other than the corners and edge they share?
/// @details Sharing an edge, they cross when they fold onto each other (their normals turn by
/// more than 175 degrees: a knife edge of a one-voxel fin turns less); sharing a corner, when
/// the opposite edge of one passes through the other or, in one plane, when their angles at
/// the corner overlap; sharing nothing, when an edge of one passes through the other or, in
/// one plane, when they overlap. Three shared corners make the same triangle: it crosses.
bool trianglesCross(const CornerTriangle& s, const CornerTriangle& t);

/// @brief Like trianglesCross(), but touching counts too: do @a s and @a t have a common point
/// other than the corners and edge they share, their edges and corners included?
/// @details Sharing a corner in one plane, or an edge, the answer is trianglesCross()'s. Two
/// triangles without area are passed to trianglesCross().
bool trianglesTouch(const CornerTriangle& s, const CornerTriangle& t);

/// @brief Do triangles @a s and @a t of a mesh (corner indices into @a points) meet other
/// than in the corners and edges they share?
/// @details trianglesTouch(): touching counts, as curve samples and vertices projected onto
/// a flat stretch of the reference surface can line up exactly, and a wedge of label pinched
/// to a point or a line is no better than one turned inside out. It reads a fold of two
/// triangles sharing an edge from normals turned by almost 180 degrees: that holds for two
/// triangles running along the edge in opposite directions, as within a consistently
/// oriented patch. Every patch is oriented by its own label pair, so a triangle of another
/// patch running along the edge the same way is turned around first. A triangle without
/// area has no plane to test the other against, so it is passed second.
bool trianglesMeet(const PointArray& points, const openvdb::Vec3I& s, const openvdb::Vec3I& t);

/// @brief Crossing pairs between @a changed and @a around plus those within @a changed.
/// @param suspect   if given, only pairs with a flagged triangle of @a changed are tested
/// @param embedded  the triangles of @a changed are known to meet each other only in the
///                  corners and edges they share (see looksUnfolded()): of their pairs only
///                  those sharing an edge are tested (they may still fold onto each other)
int countCrossings(const std::vector<CornerTriangle>& changed,
                   const std::vector<CornerTriangle>& around,
                   const std::vector<char>* suspect = nullptr, bool embedded = false);

/// @brief The cheap test before counting crossings: does nothing in @a fan look folded?
/// @details Looks at the turn (the angle between the normals) of every two triangles of
/// @a fan sharing an edge, and of every triangle @a outer[k] with the fan triangle
/// @a outerOf[k] across its edge; and, if @a centre >= 0 (then every triangle of @a fan has
/// that corner), whether they all face the way of their sum and go around it once. A fold
/// needs a sharp turn or a fan that winds twice.
/// @param turnCos  cosine of the largest turn that is not sharp
/// @param suspect   set to 1 for every triangle of @a fan at a sharp turn, and for all at the
///                  centre if they wind more than once; 0 for the others
/// @param embedded  if given, set to whether the fan has a centre and goes around it once:
///                  seen from the way of their sum its triangles then cover disjoint angles,
///                  so they meet each other only in the corners and edges they share
/// @return true if no triangle is suspect
bool looksUnfolded(const std::vector<CornerTriangle>& fan,
                   const std::vector<CornerTriangle>& outer, const std::vector<int>& outerOf,
                   int centre, double turnCos, std::vector<char>& suspect,
                   bool* embedded = nullptr);

} // namespace vdbi

#endif // VDBI_TRIANGLE_CROSSING_HAS_BEEN_INCLUDED
