// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/GuardedMoves.h
/// @brief The guarded move of one inner point of the assembled patches, which the passes
/// after remeshing share (PatchSeparation.h): a move is made only if it turns no triangle
/// over, stays within reach of where the point started and of the voxel faces, and adds no
/// pair of triangles (of any patches) that meet.

#ifndef VDBI_GUARDED_MOVES_HAS_BEEN_INCLUDED
#define VDBI_GUARDED_MOVES_HAS_BEEN_INCLUDED

#include <vdbi/CandidateGrid.h>
#include <vdbi/FanShape.h>
#include <vdbi/InterfaceMesh.h>
#include <vdbi/PatchSeparation.h>
#include <vdbi/RawPatchDistance.h>

#include <openvdb/Types.h>

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace vdbi {

/// @a patches: those of the triangles [@a first, @a last), ascending (@a patchOf:
/// trianglePatches()).
void patchesOf(const std::uint32_t* first, const std::uint32_t* last,
               const std::vector<std::uint32_t>& patchOf, std::vector<std::uint32_t>& patches);

/// patchesOf() the triangles around point @a v (@a first and @a around:
/// trianglesAroundPoints()).
void patchesAround(std::uint32_t v, const std::vector<std::uint32_t>& first,
                   const std::vector<std::uint32_t>& around,
                   const std::vector<std::uint32_t>& patchOf,
                   std::vector<std::uint32_t>& patches);

/// @brief The state the passes after remeshing move points with: the triangles around every
/// point, the candidate grid, where every point started; and moveTo(), with its guards.
/// @details The passes derive from it (PatchSeparation.cc). The result depends on the mesh
/// and the order of the moves alone. A copy shares the state with the original and has its
/// own scratch: copies may move points on other threads where the moves cannot see each
/// other (independentBlocks()), the source's cells built beforehand (buildSourceCells()).
class GuardedMoves
{
public:
    using Vec3d = openvdb::Vec3d;
    using Pairs = TrianglePairs;

    /// @param start  where every point started, for the maxMove bound: the points of
    ///               @a mesh if null
    GuardedMoves(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                 const SeparationSettings& settings, const PointArray* start);
    GuardedMoves(const GuardedMoves& other);
    GuardedMoves& operator=(const GuardedMoves&) = delete;

    /// @brief Points to move, in blocks whose moves cannot see each other: a block's moves,
    /// in its order, have the same result whether the other blocks of its colour move
    /// before, after or at the same time (on other threads, by copies of this).
    /// @details The guards of a move read the triangles in the grid cells of the point's
    /// fan and in those a few cells around (the source bound's search); a block is wider
    /// than that and than any fan, and a colour is one of the 8 parities of the blocks'
    /// indices: two blocks of a colour have a block between them.
    struct IndependentBlocks
    {
        std::vector<std::uint32_t> points;   ///< ascending within a block
        /// Block b is points [blockStart[b], blockStart[b + 1]); colour c is blocks
        /// [colourStart[c], colourStart[c + 1]).
        std::vector<std::size_t> blockStart, colourStart;
    };
    /// Those of @a points that are movable and have triangles, in IndependentBlocks.
    IndependentBlocks independentBlocks(const std::vector<std::uint32_t>& points) const;

    /// Builds the source's cells (RawPatchDistance::buildCells()) of the patches around
    /// @a points, for copies on other threads to read.
    void buildSourceCells(const std::vector<std::uint32_t>& points);

protected:
    /// What every copy shares.
    struct State
    {
        State(InterfaceMesh& mesh, const SeparationSettings& settings, const PointArray* start);

        const PointArray ownOrigin;
        const PointArray& origin;
        const std::vector<std::uint32_t> patchOf;
        const CandidateGrid grid;
        std::vector<std::uint32_t> start, around;
        /// Per point, its start's distance to its source (NaN until asked): written only by
        /// the mover of that point.
        std::vector<double> startDistance;
    };

    /// @brief Moves @a v to @a next if that leaves at most @a limit meeting pairs around it,
    /// keeps it within maxMove of its start and turns no triangle around it over.
    /// @details A triangle that faced against the vertex normal @a normal (a fold, or no
    /// area) may turn to face with it: that is how a folded fan opens.
    bool moveTo(std::uint32_t v, const Vec3d& next, const Vec3d& normal, std::size_t limit);

    /// Pairs that meet among the triangles around @a v and those near them (TriangleCrossing.h's
    /// test, pairs within one patch too): a move may not add any.
    /// @param pairs  if given, set to those pairs
    std::size_t meetingsAround(std::uint32_t v, Pairs* pairs = nullptr) const;

    /// Pairs that meet among the triangles [first, last) and those near them, each once.
    std::size_t meetingsAmong(const std::uint32_t* first, const std::uint32_t* last,
                              Pairs* pairs) const;

    /// Does one of the pairs that met around the vertex being moved (mMeetingHere) no longer
    /// meet? Else no move of it leaves fewer meeting pairs: the full count is not needed.
    bool freesAPair() const;

    /// Is @a p within maxMove of where @a v started, and close enough to its source?
    bool withinReach(std::uint32_t v, const Vec3d& p);

    /// @brief Is @a p, @a moved away from where @a v started, within sourceLimit of the
    /// source of @a v's patches, or no farther than the start?
    /// @details The start's distance is asked once; a place whose distance that bounds by
    /// the triangle inequality needs no query.
    bool keepsClose(std::uint32_t v, const Vec3d& p, double moved);

    /// @brief Do the triangles [@a first, @a last), changed by a move of the points in
    /// mMovedFrom (with their positions before), still pass within sourceLimit of every
    /// voxel face centre and centroid of their patches' source that they passed within it
    /// before, or does another triangle of the patch?
    /// @details A move that keeps the point itself close to the faces (keepsClose()) may
    /// still take the triangles around it off the faces of a thin tip, as a flip across the
    /// tip does (MeetingEdgeFlips.h).
    bool keepsSourceCovered(const std::uint32_t* first, const std::uint32_t* last);

    /// mPatchesHere: the patches of the triangles around @a v, ascending.
    void collectPatchesAround(std::uint32_t v);

    /// The normal of triangle @a f, as long as twice its area.
    Vec3d faceNormal(std::uint32_t f) const;

    /// The sum of the (area-weighted) normals of the triangles around @a v.
    Vec3d vertexNormal(std::uint32_t v) const;

    /// The mean of the other corners of the triangles around @a v, pulled back to within
    /// maxMove of where @a v started.
    Vec3d towardsNeighbours(std::uint32_t v) const;

    /// The shape of the triangles around @a v.
    FanShape fanShape(std::uint32_t v) const;

    InterfaceMesh& mMesh;
    const std::vector<std::uint8_t>& mMovable;
    const SeparationSettings& mSettings;
    std::shared_ptr<State> mState;
    /// Where every point started: the caller's, or a copy of the points.
    const PointArray& mOrigin;
    const std::vector<std::uint32_t>& mPatchOf;
    const CandidateGrid& mGrid;
    /// Triangles around every point: mAround[mStart[v] .. mStart[v + 1]).
    const std::vector<std::uint32_t>& mStart;
    const std::vector<std::uint32_t>& mAround;
    std::vector<Vec3d> mBefore;
    /// The pairs meeting around the point or points being moved, before they move (set by
    /// the caller of moveTo(): meetingsAround() or meetingsAmong()).
    Pairs mMeetingHere;
    /// Per point, its start's distance to its source (State::startDistance), and
    /// keepsClose()'s patches.
    std::vector<double>& mStartDistance;
    std::vector<std::uint32_t> mPatchesHere;
    /// keepsSourceCovered()'s: the points moved and where they were; the changed triangles
    /// of one patch now and before, in voxel units; the patches of the changed triangles.
    std::vector<std::pair<std::uint32_t, Vec3d>> mMovedFrom;
    std::vector<std::uint32_t> mPatchesMoved;
    std::vector<RawPatchDistance::Corners> mNow, mThen;
};

} // namespace vdbi

#endif // VDBI_GUARDED_MOVES_HAS_BEEN_INCLUDED
