// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/MeetingEdgeFlips.h
/// @brief After separation: an inner edge of a triangle that still meets another is flipped
/// where the other diagonal of its two triangles meets fewer (ALGORITHM.md §5).

#ifndef VDBI_MEETING_EDGE_FLIPS_HAS_BEEN_INCLUDED
#define VDBI_MEETING_EDGE_FLIPS_HAS_BEEN_INCLUDED

#include <vdbi/CandidateGrid.h>
#include <vdbi/InterfaceMesh.h>
#include <vdbi/RawPatchDistance.h>

#include <cstdint>
#include <vector>

namespace vdbi {

/// @brief Flips inner edges of the triangles that meet others (trianglesMeet() of
/// TriangleCrossing.h) where that leaves fewer meeting pairs.
/// @details Separation moves vertices; some crossings are of an edge that runs the wrong way
/// round a curve point: the edge from an inner vertex past a corner of another patch's
/// triangle runs through that patch, and no move within reach frees it, while the other
/// diagonal of the edge's two triangles goes round (frog at one voxel: the last 5 pairs,
/// at a patch of three curve samples). Every meeting triangle, in index order, flips the
/// one of its edges that frees the most pairs, if any: an edge of its patch only (never a
/// feature curve segment), whose new diagonal is no edge yet and joins at least one inner
/// vertex (another patch on the same curves could make an edge between two samples too),
/// whose two new triangles have area and face the way the old pair did. Triangles at a
/// corner of a flipped pair wait for another call. Shapes of the patches are kept (no
/// point moves); the mesh stays a consistently oriented 2-manifold with the same
/// boundaries.
/// @param mesh      [in,out] the separated patches
/// @param movable   one flag per point: nonzero for a free (inner) vertex
/// @param cellSize  about the edge length: the width of the grid of candidate pairs
/// @param threaded  build the grid of candidate pairs with TBB (the result is the same
///                  either way)
/// @param suspects  points such that every meeting pair has a triangle with a corner among
///                  them: the triangles around them and those they meet are looked at, not
///                  the whole mesh (every point for a search of the whole mesh)
/// @param left      if given, set to the pairs of triangles that still meet, ascending
/// @param source    if given, the surfaces the patches were made from (same indices): no flip
///                  takes a patch farther than @a sourceLimit voxels from a voxel face centre
///                  or centroid of their triangles that it passed within that (a flip
///                  across a thin tip would cut the tip off)
/// @return the number of edges flipped
std::size_t flipMeetingEdges(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                             double cellSize, bool threaded,
                             const std::vector<std::uint32_t>& suspects,
                             TrianglePairs* left = nullptr, RawPatchDistance* source = nullptr,
                             double sourceLimit = 0.0);

} // namespace vdbi

#endif // VDBI_MEETING_EDGE_FLIPS_HAS_BEEN_INCLUDED
