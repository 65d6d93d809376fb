// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/MeetingEdgeCollapses.h
/// @brief Separation's last resort: a free corner of a triangle that still meets another is
/// collapsed into a neighbour where that leaves fewer meeting pairs (ALGORITHM.md §5); and
/// the edges under half the target length left, collapsed with every patch in sight.

#ifndef VDBI_MEETING_EDGE_COLLAPSES_HAS_BEEN_INCLUDED
#define VDBI_MEETING_EDGE_COLLAPSES_HAS_BEEN_INCLUDED

#include <vdbi/CandidateGrid.h>
#include <vdbi/InterfaceMesh.h>
#include <vdbi/RawPatchDistance.h>

#include <cstdint>
#include <functional>
#include <vector>

namespace vdbi {

/// @brief Collapses inner edges at the corners of the triangles that meet others
/// (trianglesMeet() of TriangleCrossing.h) where that leaves fewer meeting pairs; then
/// drops the triangles and points the collapses removed.
/// @details Where a patch is crumpled into a small knot (menger at 2 voxels: six triangles
/// of one patch around six free vertices, folded through each other within two voxels), no
/// move within separation's reach and no flip frees it, but removing a vertex or two does.
/// Every meeting triangle, in index order, collapses the free corner u into the neighbour v
/// that frees the most pairs, if any, v staying where it is or, if it is free too, moving
/// half way to u or to u's place (the first of equals in that order). Allowed only if the
/// edge (u, v) has one triangle on either side, of u's patch; u and v have no other common
/// neighbour in that patch (the link condition: the patch stays a 2-manifold with the same
/// boundary); no new edge joins two fixed points (another patch on the same curves could
/// have that edge); the points across the edge keep three triangles of the patch (one on
/// its boundary); and no new triangle is without area. The points and triangles around a
/// collapse wait for the next pass. The result does not depend on the number of threads.
/// @param mesh      [in,out] the separated patches; the points no triangle uses any more
///                  are removed (later points move down: @a movable no longer fits it)
/// @param movable   one flag per point: nonzero for a free (inner) vertex
/// @param cellSize  about the edge length: the width of the grid of candidate pairs
/// @param threaded  build the grid with TBB (the result is the same either way)
/// @param pairs     every pair of triangles that meets (as flipMeetingEdges() leaves them)
/// @param left      if given, set to the pairs still meeting, in the new indices, ascending
/// @return the number of edges collapsed
std::size_t collapseMeetingEdges(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                                 double cellSize, bool threaded, const TrianglePairs& pairs,
                                 TrianglePairs* left = nullptr);

/// Settings of collapseMeetingAndShortEdges().
struct ShortEdgeCollapseSettings
{
    /// Edges shorter than @a shortLength collapse where allowed; no collapse makes an edge
    /// longer than @a longLength.
    double shortLength = 0.0, longLength = 0.0;
    /// About the edge length: the width of the grid of candidate pairs.
    double cellSize = 1.0;
    /// Build the grid with TBB (the result is the same either way).
    bool threaded = true;
    /// May patch p join fixed points a and b by a new inner edge (no other patch can)?
    std::function<bool(std::uint32_t p, std::uint32_t a, std::uint32_t b)> mayJoinFixed =
        [](std::uint32_t, std::uint32_t, std::uint32_t) { return false; };
    /// If set: the surfaces the patches were made from (as SeparationSettings::source). A
    /// collapse may then not take a moved point farther than @a sourceLimit voxels from its
    /// patch's, nor uncover a face centre or centroid of them
    /// (RawPatchDistance::keepsCovered()).
    RawPatchDistance* source = nullptr;
    double sourceLimit = 1.0;
};

/// @brief collapseMeetingEdges(), then passes over the edges shorter than
/// settings.shortLength, shortest first, each collapsed the best way allowed.
/// @details Every patch is remeshed on its own and cannot see the others, so it keeps short
/// edges where a collapse might make it cross another, and next to a curve it may not join
/// two curve samples that another patch may join too. Here, after separation, every patch
/// is in sight: an edge with a free end u collapses into its other end v (v staying, or, if
/// free, moving to the midpoint or to u) as collapseMeetingEdges() allows, except that a
/// new inner edge may join two fixed points where settings.mayJoinFixed allows; and only if
/// no new edge is longer than settings.longLength, no triangle turns over, the triangles
/// around u and v meet no other before or after, their fan gets no more triangles under
/// SHARP_TRIANGLE_DEGREES (FanShape.h) and no smaller smallest angle (unless it stays over
/// that), and the source bound holds; the dear tests (meeting pairs, source) look at the
/// best two of the ways the others allow, by the fan they leave. (A free point whose
/// three neighbours are fixed leaves the triangle of those three: in one patch only, as the
/// same triangle twice meets itself.) A pass after the first looks at the edges around the
/// points the pass before changed. Serial, in the order of the edges: the result depends on
/// the mesh alone.
/// @param mesh     [in,out] the separated patches; the points no triangle uses any more are
///                 removed (later points move down: @a movable no longer fits it)
/// @param movable  one flag per point: nonzero for a free (inner) vertex
/// @param pairs    every pair of triangles that meets
/// @return the number of edges collapsed
std::size_t collapseMeetingAndShortEdges(InterfaceMesh& mesh,
                                         const std::vector<std::uint8_t>& movable,
                                         const ShortEdgeCollapseSettings& settings,
                                         const TrianglePairs& pairs);

} // namespace vdbi

#endif // VDBI_MEETING_EDGE_COLLAPSES_HAS_BEEN_INCLUDED
