// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/MeetingEdgeCollapses.h
/// @brief Separation's last resort: a free corner of a triangle that still meets another is
/// collapsed into a neighbour where that leaves fewer meeting pairs (ALGORITHM.md §5).

#ifndef VDBI_MEETING_EDGE_COLLAPSES_HAS_BEEN_INCLUDED
#define VDBI_MEETING_EDGE_COLLAPSES_HAS_BEEN_INCLUDED

#include <vdbi/CandidateGrid.h>
#include <vdbi/InterfaceMesh.h>

#include <cstdint>
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

} // namespace vdbi

#endif // VDBI_MEETING_EDGE_COLLAPSES_HAS_BEEN_INCLUDED
