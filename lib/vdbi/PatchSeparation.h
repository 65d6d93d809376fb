// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/PatchSeparation.h
/// @brief After remeshing: triangles that cross each other, of two patches near a shared
/// feature curve or of one folded patch, are pushed apart by moving their inner vertices
/// (ALGORITHM.md §5).

#ifndef VDBI_PATCH_SEPARATION_HAS_BEEN_INCLUDED
#define VDBI_PATCH_SEPARATION_HAS_BEEN_INCLUDED

#include <vdbi/CandidateGrid.h>
#include <vdbi/FaceCentreCoverage.h>
#include <vdbi/InterfaceMesh.h>
#include <vdbi/RawPatchDistance.h>

#include <openvdb/Types.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace vdbi {

/// Settings of separatePatches().
struct SeparationSettings
{
    /// About the edge length: the grid of candidate pairs has cells this wide plus twice
    /// maxMove.
    double cellSize = 1.0;
    /// Distance a vertex moves per round, and the most it may move over all rounds.
    double step = 0.1, maxMove = 0.3;
    int rounds = 16;
    /// Look for crossing pairs with TBB (the result is the same either way).
    bool threaded = true;
    /// @brief If set: the surfaces the mesh's patches were made from (same indices). A move
    /// may then not take a point farther from those of its patches than @a sourceLimit
    /// voxels, or than its start was if that is farther; nor take the triangles around it
    /// farther than that from a face centre or centroid of their source that they passed
    /// within it of (RawPatchDistance::keepsCovered()).
    RawPatchDistance* source = nullptr;
    double sourceLimit = 1.0;
    /// The smallest side of a voxel (world length): a move by d changes a distance in voxels
    /// by at most d / sourceUnit.
    double sourceUnit = 1.0;
};

/// @brief Moves inner vertices so that triangles cross less, of different patches or of one.
/// @details Every patch is remeshed on its own, so near a curve shared with another patch the
/// strip of triangles along the curve may swing through the other patch where the label
/// between them is thin (a wedge of one voxel). Two such patches usually share a label; the
/// wedge of that label has turned inside out. Each round finds the pairs of triangles that
/// meet other than in shared corners and edges (trianglesTouch() of TriangleCrossing.h:
/// edges through or touching triangles, triangles in one plane overlapping or touching, and
/// triangles sharing an edge folded onto each other; a uniform grid gives the candidates)
/// and moves each free corner of such a triangle one step along its vertex normal, away
/// from the shared label:
/// both sides turn back and the wedge opens. A corner takes the first move that leaves fewer
/// meeting pairs around it: that push, the mean of its neighbours (which opens a folded fan,
/// as within one patch), half way there; else the push if it adds none; else the nearest
/// point along or against its normal, whole steps away, that removes one; else the nearest
/// such point along one of the 26 lattice directions (sideways, out of a wedge). Pairs that
/// no corner frees alone are then tried with the free corners of one triangle moving
/// together, by one offset, then with those of the meeting triangles of its patch around
/// them too. Pairs within one
/// patch and of patches sharing no label have no push.
/// The grid is built once, every triangle's box widened by maxMove; a round tests only the
/// pairs of triangles whose vertices moved in the round before. A move is not made if it
/// would turn one of the vertex's triangles over (one facing against the vertex normal may
/// turn to face with it), take the vertex farther than maxMove from its start or (with a
/// source) from the voxel faces than the source bound allows, or add to
/// the pairs of triangles (of any patches, one of them the vertex's) that meet: a push
/// through a third triangle is how separation used to make new crossings.
/// The pairs are found in parallel; their pushes add up before any vertex moves, and
/// vertices move serially in index order: the result depends on the mesh alone.
/// @param mesh     [in,out] the remeshed patches
/// @param movable  one flag per point: nonzero for a free (inner) vertex
/// @param start    where every point started, for the maxMove bound: the points of @a mesh
///                 if null
/// @param meeting  if given, set to the pairs left, ascending: those the first round found
///                 and no vertex of which moved since, and those found since
/// @param known    if given, every pair meeting now (as @a meeting of an earlier call left
///                 them, with nothing moved since): the first round starts from them instead
///                 of searching the whole mesh. Same result, less time: on frog at 2 voxels
///                 the search took 0.4 s on 2 threads
/// @return the number of meeting pairs left
std::size_t separatePatches(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                            const SeparationSettings& settings,
                            const PointArray* start = nullptr,
                            TrianglePairs* meeting = nullptr,
                            const TrianglePairs* known = nullptr);

/// @brief Splits an inner edge of every triangle with at most one free corner that still
/// meets another after separatePatches(), so that a next separation has a free vertex there
/// to move.
/// @details Some meeting triangles have no free corner (all three on feature curves), or
/// one whose moves turn a whole fan. Each such triangle, in index order, splits its longest
/// inner edge (see @a source) (one of its patch only, never a feature curve segment, which other patches
/// share) whose other triangle no split changed yet, at its midpoint: a new free point, no
/// change of shape. A patch's new triangles follow its others. Triangles with two or three
/// free corners are left to separation: splitting them too makes more short edges and sharp
/// triangles and leaves more meeting pairs, not fewer (frog at 2 voxels: 230 pairs instead of
/// 206, edges in range 97.47 instead of 97.48 %, 1st-percentile smallest angle 18.96 instead
/// of 18.99 degrees; 292 pairs, 97.52 % and 19.08 degrees without splits).
/// @param mesh     [in,out] the patches
/// @param movable  [in,out] one flag per point; 1 is appended for every new point
/// @param start    [in,out] where every point started; a new point's is the midpoint of its
///                 edge's
/// @param pairs    the meeting pairs separatePatches() left
/// @param source   if given, the voxel faces of the patches (as SeparationSettings::source):
///                 an edge whose midpoint lies within @a sourceLimit of them is split before
///                 a longer one whose midpoint does not (a chord over a concave bend: monu16
///                 at 4 voxels kept such a midpoint 1.15 voxels from the faces, 0.94 now)
/// @return the number of edges split
std::size_t splitMeetingTriangles(InterfaceMesh& mesh, std::vector<std::uint8_t>& movable,
                                  PointArray& start, const TrianglePairs& pairs,
                                  RawPatchDistance* source = nullptr, double sourceLimit = 0.0);

/// @brief separatePatches() near the points from @a firstPoint on (those splitMeetingTriangles()
/// made): only they and the movable corners of their triangles move, and only the triangles
/// that these can come to meet are looked at.
/// @return the number of meeting pairs left (of those looked at in the last round)
std::size_t separateAround(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                           const PointArray& start, const SeparationSettings& settings,
                           std::size_t firstPoint);

/// @brief Moves each of @a points (movable, inner) that lies farther than
/// settings.sourceLimit from its patch's source (settings.source, which must be set) towards
/// the nearest point there, by eighths of the way: to the first place within the limit that
/// turns no triangle over and adds no meeting pair around the point; else, nearest to the
/// source first, to one that only comes closer.
/// @details What separation leaves this far: vertices remeshing could not project onto their
/// reference surface across a crease, and the midpoints that splitMeetingTriangles() made on
/// chords over a concave bend. The moves are serial, in the order of @a points: the result
/// depends on the mesh alone.
/// @return the number of points moved
std::size_t pullTowardsSource(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                              const SeparationSettings& settings,
                              const std::vector<std::uint32_t>& points);

/// @brief Brings each of @a centres (voxel face centres farther than settings.sourceLimit
/// from their patch: findFarFaceCentres()) within the limit of its patch where one move of a
/// free corner of the patch's nearest triangle does: the corner nearest to the centre's
/// nearest point first, towards the centre by eighths of the way, to the nearest place that
/// brings it within the limit.
/// @details Remeshing keeps its surface near the smoothed staircase, not near the face
/// centres: at long edge lengths it can leave the centre of a thin tip's face over a voxel
/// from the patch (frog at 4 voxels, had the extraction kept the untouched voxels of a
/// repair whole: 1.005 voxels). A move passes separation's guards (settings.source must be
/// set): no triangle turned over, within settings.maxMove of where the point was, the point
/// within the limit of its source or no farther, the centres within the limit kept there, no
/// pair of triangles meeting that did not. Serial, in the order of @a centres: the result
/// depends on the mesh alone.
/// @return the number of centres left farther than the limit
std::size_t pullTowardsFaceCentres(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                                   const SeparationSettings& settings,
                                   const std::vector<FaceCentre>& centres);

/// @brief After separation: each of @a points (movable, inner) with a triangle under
/// SHARP_TRIANGLE_DEGREES (FanShape.h) moves a short step aside in the plane of its normal,
/// where that leaves its fan fewer sharp triangles (or as many and a larger smallest angle)
/// and no smaller smallest angle, and passes separation's guards: no triangle turned over,
/// within settings.maxMove of where it was, the source bound kept (settings.source, if set),
/// and no pair of triangles meeting that did not (of any patches: what a patch remeshed on
/// its own cannot see).
/// @details SharpFanSmoothing.h leaves the fans next to a tight part of a patch boundary as
/// they are: there, other patches come close. Here every patch is in sight. Fans with an
/// angle under SHARP_FAN_DEGREES but no sharp triangle stay: at 4 voxels, shaping them too
/// doubled the time of this step (frog: about 17 s instead of 9 s on 2 threads) for 0.1
/// degree at the 1st percentile. The points move in blocks that cannot see each other's
/// moves (GuardedMoves::independentBlocks()), those of a colour in parallel if
/// settings.threaded, each block's in its order: the result depends on the mesh alone.
/// @return the number of points moved
std::size_t shapeSharpFans(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                           const SeparationSettings& settings,
                           const std::vector<std::uint32_t>& points);

} // namespace vdbi

#endif // VDBI_PATCH_SEPARATION_HAS_BEEN_INCLUDED
