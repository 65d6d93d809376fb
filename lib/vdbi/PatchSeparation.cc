// SPDX-License-Identifier: Apache-2.0

#include <vdbi/PatchSeparation.h>

#include <vdbi/CandidateGrid.h>
#include <vdbi/FanShape.h>
#include <vdbi/GuardedMoves.h>
#include <vdbi/ParallelRanges.h>
#include <vdbi/ReferenceSurface.h>
#include <vdbi/TriangleCrossing.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <utility>

namespace vdbi {

namespace {

using Vec3d = openvdb::Vec3d;

/// The 26 unit directions from a point of the integer lattice to its neighbours.
const std::array<Vec3d, 26>&
latticeDirections()
{
    static const std::array<Vec3d, 26> directions = [] {
        std::array<Vec3d, 26> result;
        std::size_t i = 0;
        for (int x = -1; x <= 1; ++x) {
            for (int y = -1; y <= 1; ++y) {
                for (int z = -1; z <= 1; ++z) {
                    if (x != 0 || y != 0 || z != 0) result[i++] = Vec3d(x, y, z).unitSafe();
                }
            }
        }
        return result;
    }();
    return directions;
}

using Pairs = TrianglePairs;

/// @brief The passes of this file: separatePatches()' rounds, and the moves of
/// pullTowardsSource() and shapeSharpFans().
class Separation : public GuardedMoves
{
public:
    Separation(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
               const SeparationSettings& settings, const PointArray* start)
        : GuardedMoves(mesh, movable, settings, start)
    {
    }
    /// A mover with its own scratch, sharing the state of @a other.
    Separation(const Separation& other) : GuardedMoves(other) {}

    /// The rounds; returns every pair of triangles meeting after them, ascending.
    /// @param known  all pairs meeting before them if the caller knows (else searched for)
    Pairs run(const Pairs* known)
    {
        const std::size_t pointCount = mMesh.points.size();
        std::vector<char> active(mMesh.triangles.size(), 0), listed(pointCount, 0);
        std::vector<int> push(pointCount, 0);
        std::vector<std::uint32_t> corners;
        Pairs meeting = known ? *known : mGrid.allMeetingPairs(meets(), mSettings.threaded);
        std::sort(meeting.begin(), meeting.end());
        // The pairs of this round's search: all at first, then those of triangles that moved.
        Pairs found = meeting;
        for (int round = 0; round < mSettings.rounds && !found.empty(); ++round) {
            corners.clear();
            for (const auto& [f, g] : found) {
                for (const std::uint32_t h : {f, g}) {
                    const int away = awayFromSharedLabel(h, h == f ? g : f);
                    for (int i = 0; i < 3; ++i) {
                        const std::uint32_t v = mMesh.triangles[h][i];
                        if (!mMovable[v]) continue;
                        if (!listed[v]) corners.push_back(v);
                        listed[v] = 1;
                        push[v] += away;
                    }
                }
            }
            std::fill(active.begin(), active.end(), 0);
            std::sort(corners.begin(), corners.end());
            bool moved = false;
            for (const std::uint32_t v : corners) {
                listed[v] = 0;
                const int direction = push[v];
                push[v] = 0;
                if (!moveCorner(v, direction)) continue;
                for (std::uint32_t i = mStart[v]; i < mStart[v + 1]; ++i) active[mAround[i]] = 1;
                moved = true;
            }
            if (!moved) break;
            found = findAgain(active, meeting);
        }
        // What no corner alone frees: the free corners of a meeting triangle move together;
        // what that leaves, with those of the meeting triangles of its patch around them.
        for (const bool widened : {false, true}) {
            moveGroups(widened, active, meeting);
        }
        return meeting;
    }

    /// pullTowardsSource() of one point; true if it moved.
    bool pullTowardsSource(std::uint32_t v)
    {
        if (!mMovable[v] || mStart[v] == mStart[v + 1]) return false;
        collectPatchesAround(v);
        const RawPatchDistance::Hit hit = mSettings.source->farthest(mMesh.points[v],
                                                                     mPatchesHere);
        if (hit.distance <= mSettings.sourceLimit) return false;
        const Vec3d normal = vertexNormal(v);
        const Vec3d here = mMesh.points[v];
        const std::size_t meetings = meetingsAround(v, &mMeetingHere);
        // The eighths within the limit, nearest to the point first; else the others, nearest
        // to the source first (the point comes closer at least).
        int firstWithin = 9;
        for (int eighths = 1; eighths <= 8; ++eighths) {
            const Vec3d next = here + (hit.point - here) * (eighths / 8.0);
            // The hit bounds the distance from there: no query while that is over the limit.
            if ((1.0 - eighths / 8.0) * hit.distance > mSettings.sourceLimit
                && mSettings.source->farthest(next, mPatchesHere).distance
                    > mSettings.sourceLimit) {
                continue;
            }
            firstWithin = std::min(firstWithin, eighths);
            if (moveTo(v, next, normal, meetings)) return true;
        }
        for (int eighths = firstWithin - 1; eighths >= 1; --eighths) {
            if (moveTo(v, here + (hit.point - here) * (eighths / 8.0), normal, meetings)) {
                return true;
            }
        }
        return false;
    }

    /// @brief pullTowardsFaceCentres() of one centre @a q (voxel units) of patch @a patch.
    /// @return whether it lies within the limit of the patch afterwards
    bool pullTowardsCentre(std::uint32_t patch, const Vec3d& q)
    {
        RawPatchDistance& source = *mSettings.source;
        const double limit = mSettings.sourceLimit;
        // The nearest triangle of the patch: within twice the limit, its box is in the cells
        // of the centre's box that wide.
        std::uint32_t nearest = 0;
        double distance = std::numeric_limits<double>::infinity();
        Vec3d weights;
        mGrid.forEachInBox(source.world(q - Vec3d(2.0 * limit)),
                           source.world(q + Vec3d(2.0 * limit)), [&](std::uint32_t g) {
            if (mPatchOf[g] != patch) return;
            const RawPatchDistance::Corners t = source.corners(mMesh.points, mMesh.triangles[g]);
            Vec3d bary;
            const Vec3d p = closestPointOnTriangle(q, t.c[0], t.c[1], t.c[2], bary);
            const double d = (p - q).length();
            if (d < distance || (d == distance && g < nearest)) {
                nearest = g;
                distance = d;
                weights = bary;
            }
        });
        if (distance <= limit) return true;
        if (!std::isfinite(distance)) return false;
        // Only the triangles around a moved corner change: the centre comes within the limit
        // of one of them, or of none. The free corners, the one nearest to the centre's
        // nearest point first, each towards the centre by eighths of the way, the nearest
        // place that brings it within the limit first.
        int order[3] = {0, 1, 2};
        std::sort(order, order + 3, [&](int a, int b) {
            return weights[a] > weights[b] || (weights[a] == weights[b] && a < b);
        });
        const Vec3d centre = source.world(q);
        for (const int k : order) {
            const std::uint32_t v = mMesh.triangles[nearest][k];
            if (!mMovable[v] || mStart[v] == mStart[v + 1]) continue;
            const Vec3d here = mMesh.points[v], normal = vertexNormal(v);
            const std::size_t meetings = meetingsAround(v, &mMeetingHere);
            for (int eighths = 1; eighths <= 8; ++eighths) {
                const Vec3d next = here + (centre - here) * (eighths / 8.0);
                mMesh.points[v] = next;
                bool covers = false;
                for (std::uint32_t i = mStart[v]; i < mStart[v + 1] && !covers; ++i) {
                    const std::uint32_t f = mAround[i];
                    covers = mPatchOf[f] == patch
                        && RawPatchDistance::isWithin(q, source.corners(mMesh.points,
                                                                        mMesh.triangles[f]),
                                                      limit);
                }
                mMesh.points[v] = here;
                if (covers && moveTo(v, next, normal, meetings)) return true;
            }
        }
        return false;
    }

    /// shapeSharpFans() of one point; true if it moved.
    bool shapeFan(std::uint32_t v)
    {
        if (!mMovable[v] || mStart[v] == mStart[v + 1]) return false;
        const FanShape old = fanShape(v);
        if (old.sharp == 0) return false;
        Vec3d normal = vertexNormal(v);
        if (!normal.normalize()) return false;
        const Vec3d here = mMesh.points[v];
        double reach = 0.0;
        int corners = 0;
        for (std::uint32_t i = mStart[v]; i < mStart[v + 1]; ++i) {
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t w = mMesh.triangles[mAround[i]][k];
                if (w == v) continue;
                reach += (mMesh.points[w] - here).length();
                ++corners;
            }
        }
        reach /= double(corners);
        // The pattern of SharpFanSmoothing's steps aside, in the plane of the vertex normal.
        Vec3d e1 = std::abs(normal[0]) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
        e1 -= normal * e1.dot(normal);
        e1.normalize();
        const Vec3d e2 = normal.cross(e1);
        mSteps.clear();
        forEachStepAside(e1, e2, reach, [&](const Vec3d& step) {
            mMesh.points[v] = here + step;
            mSteps.push_back({fanShape(v), mMesh.points[v]});
        });
        mMesh.points[v] = here;
        std::stable_sort(mSteps.begin(), mSteps.end(),
                         [](const Step& a, const Step& b) { return a.shape < b.shape; });
        const std::size_t meetings = meetingsAround(v, &mMeetingHere);
        for (std::size_t k = 0; k < STEPS_ASIDE_TRIED && k < mSteps.size(); ++k) {
            if (!mSteps[k].shape.isBetterThan(old)) break;
            // Fewer sharp triangles at the price of a sharper one lowered the 1st percentile
            // (monu16 at 4 voxels: 5.2 -> 1.0 degrees; 5.6 with this).
            if (mSteps[k].shape.smallestCos > old.smallestCos) continue;
            if (moveTo(v, mSteps[k].place, normal, meetings)) return true;
        }
        return false;
    }

private:
    /// @brief Rounds of moveTogether() over the meeting pairs, updating @a meeting: a round
    /// looks at the pairs it found, all at first, then those of triangles that moved.
    void moveGroups(bool widened, std::vector<char>& active, Pairs& meeting)
    {
        Pairs found = meeting;
        for (int round = 0; round < mSettings.rounds && !found.empty(); ++round) {
            std::fill(active.begin(), active.end(), 0);
            if (widened) {
                mIsMeeting.assign(mMesh.triangles.size(), 0);
                for (const auto& [f, g] : meeting) mIsMeeting[f] = mIsMeeting[g] = 1;
            }
            bool moved = false;
            for (const auto& [f, g] : found) {
                if (active[f] || active[g]) continue;   // moved this round already
                for (const std::uint32_t h : {f, g}) {
                    if (!moveTogether(h, widened)) continue;
                    for (const std::uint32_t t : mGroupTriangles) active[t] = 1;
                    moved = true;
                    break;
                }
            }
            if (!moved) break;
            found = findAgain(active, meeting);
        }
    }

    /// trianglesMeet() on triangle indices, for the candidate grid.
    MeetTest meets() const
    {
        return [this](std::uint32_t f, std::uint32_t g) {
            return trianglesMeet(mMesh.points, mMesh.triangles[f], mMesh.triangles[g]);
        };
    }

    /// After a round moved the corners of the @a active triangles: their meeting pairs, found
    /// again and returned, replace theirs in @a meeting (kept ascending). Pairs without an
    /// active triangle meet as they did.
    Pairs findAgain(const std::vector<char>& active, Pairs& meeting) const
    {
        Pairs found = mGrid.meetingPairs(active, meets(), mSettings.threaded);
        meeting.erase(std::remove_if(meeting.begin(), meeting.end(), [&](const auto& pair) {
            return active[pair.first] || active[pair.second];
        }), meeting.end());
        meeting.insert(meeting.end(), found.begin(), found.end());
        std::sort(meeting.begin(), meeting.end());
        return found;
    }

    /// +1 or -1: which way along the normal of triangle @a h is away from the label its patch
    /// shares with that of @a other (the normal points from a into b); 0 for triangles of one
    /// patch, or of patches sharing no label.
    int awayFromSharedLabel(std::uint32_t h, std::uint32_t other) const
    {
        const InterfacePatch &p = mMesh.patches[mPatchOf[h]], &q = mMesh.patches[mPatchOf[other]];
        if (mPatchOf[h] == mPatchOf[other]) return 0;
        if (p.a == q.a || p.a == q.b) return 1;
        if (p.b == q.a || p.b == q.b) return -1;
        return 0;
    }


    /// @brief Moves corner @a v of meeting pairs, pushed @a direction times away from shared
    /// labels, to the first of these that leaves fewer meeting pairs around it: one step
    /// along its normal that way, the mean of its neighbours (kept within maxMove of its
    /// start), half way there. Else the step that way if it adds no meeting pair (a wedge
    /// opens over several rounds); else the nearest point along or against the normal, whole
    /// steps away and within maxMove of its start, that removes one; else the nearest such
    /// point along one of the 26 directions from a lattice point to its neighbours.
    /// @details The search along the normal finds moves that no single step makes: out of a
    /// crossing deeper than a step, which no step either way removes (frog at 2 voxels: 344
    /// meeting pairs left with one step either way, 292 with the search). Where the other
    /// triangle lies across the normal, as in a wedge near a curve, the way out is sideways:
    /// the lattice directions free such pairs (frog at 2 voxels: 202 -> 156 pairs left;
    /// monu16 at 1 voxel: 4 -> 0).
    bool moveCorner(std::uint32_t v, int direction)
    {
        const Vec3d normal = vertexNormal(v);
        const double length = normal.length();
        const Vec3d here = mMesh.points[v];
        const Vec3d step = length > 0.0 ? normal * (mSettings.step / length) : Vec3d(0.0);
        const bool pushed = direction != 0 && length > 0.0;
        const Vec3d push = direction > 0 ? here + step : here - step;
        const std::size_t meetings = meetingsAround(v, &mMeetingHere);
        if (meetings > 0) {
            const Vec3d mean = towardsNeighbours(v);
            if ((pushed && moveTo(v, push, normal, meetings - 1))
                || moveTo(v, mean, normal, meetings - 1)
                || moveTo(v, (here + mean) * 0.5, normal, meetings - 1)) {
                return true;
            }
        }
        if (pushed && moveTo(v, push, normal, meetings)) return true;
        if (meetings == 0 || !(length > 0.0)) return false;
        // A ray from v leaves the ball of radius maxMove around the start for good.
        bool along = true, against = true;
        for (double k = 1.0; along || against; k += 1.0) {
            along = along && withinReach(v, here + step * k);
            if (along && moveTo(v, here + step * k, normal, meetings - 1)) return true;
            against = against && withinReach(v, here - step * k);
            if (against && moveTo(v, here - step * k, normal, meetings - 1)) return true;
        }
        // Points within maxMove of the start are within twice that of here.
        for (double k = 1.0; k * mSettings.step <= 2.0 * mSettings.maxMove; k += 1.0) {
            for (const Vec3d& d : latticeDirections()) {
                const Vec3d next = here + d * (mSettings.step * k);
                if (withinReach(v, next) && moveTo(v, next, normal, meetings - 1)) return true;
            }
        }
        return false;
    }

    /// @brief Moves the free corners of triangle @a h together, by one offset, to the nearest
    /// place that leaves fewer meeting pairs around them: whole steps along or against the
    /// triangle's normal or along one of the 26 lattice directions, every corner within
    /// maxMove of its start, no triangle around them turned over. If @a widened, the free
    /// corners of the meeting triangles (mIsMeeting) of its patch around those move too.
    /// @details For pairs that no move of one corner frees: the other corner holds the
    /// triangle in place, or drags a neighbour through another triangle (in a wedge of one
    /// label at a curve, where the patch is a strip of slivers along it). Widened: where the
    /// strip's slivers lie across the curve, a move of some of their corners turns a sliver
    /// between them over; all of them moving keeps the slivers as they are (frog at one
    /// voxel: a wedge of 4 crossing pairs freed).
    bool moveTogether(std::uint32_t h, bool widened)
    {
        mGroup.clear();
        for (int i = 0; i < 3; ++i) {
            if (mMovable[mMesh.triangles[h][i]]) mGroup.push_back(mMesh.triangles[h][i]);
        }
        const std::size_t own = widened ? mGroup.size() : 0;
        for (std::size_t k = 0; k < own; ++k) {
            const std::uint32_t v = mGroup[k];
            for (std::uint32_t i = mStart[v]; i < mStart[v + 1]; ++i) {
                const std::uint32_t f = mAround[i];
                if (!mIsMeeting[f] || mPatchOf[f] != mPatchOf[h]) continue;
                for (int j = 0; j < 3; ++j) {
                    const std::uint32_t w = mMesh.triangles[f][j];
                    if (mMovable[w] && std::find(mGroup.begin(), mGroup.end(), w) == mGroup.end()) {
                        mGroup.push_back(w);
                    }
                }
            }
        }
        if (mGroup.size() < 2) return false;
        mGroupTriangles.clear();
        for (const std::uint32_t v : mGroup) {
            mGroupTriangles.insert(mGroupTriangles.end(), mAround.begin() + mStart[v],
                                   mAround.begin() + mStart[v + 1]);
        }
        std::sort(mGroupTriangles.begin(), mGroupTriangles.end());
        mGroupTriangles.erase(std::unique(mGroupTriangles.begin(), mGroupTriangles.end()),
                              mGroupTriangles.end());
        const std::uint32_t *first = mGroupTriangles.data(),
                            *last = first + mGroupTriangles.size();
        const std::size_t meetings = meetingsAmong(first, last, &mMeetingHere);
        if (meetings == 0) return false;
        mBefore.clear();
        for (const std::uint32_t f : mGroupTriangles) mBefore.push_back(faceNormal(f));
        mGroupPoints.clear();
        for (const std::uint32_t v : mGroup) mGroupPoints.push_back(mMesh.points[v]);
        const Vec3d normal = faceNormal(h);
        const double length = normal.length();
        auto tryOffset = [&](const Vec3d& offset) {
            for (std::size_t i = 0; i < mGroup.size(); ++i) {
                if (!withinReach(mGroup[i], mGroupPoints[i] + offset)) return false;
            }
            for (std::size_t i = 0; i < mGroup.size(); ++i) {
                mMesh.points[mGroup[i]] = mGroupPoints[i] + offset;
            }
            bool turned = false;
            for (std::size_t i = 0; i < mGroupTriangles.size() && !turned; ++i) {
                turned = !(faceNormal(mGroupTriangles[i]).dot(mBefore[i]) > 0.0);
            }
            mMovedFrom.clear();
            for (std::size_t i = 0; i < mGroup.size(); ++i) {
                mMovedFrom.emplace_back(mGroup[i], mGroupPoints[i]);
            }
            if (!turned && freesAPair() && meetingsAmong(first, last, nullptr) < meetings
                && keepsSourceCovered(mGroupTriangles.data(),
                                      mGroupTriangles.data() + mGroupTriangles.size())) {
                return true;
            }
            for (std::size_t i = 0; i < mGroup.size(); ++i) mMesh.points[mGroup[i]] = mGroupPoints[i];
            return false;
        };
        for (double k = 1.0; k * mSettings.step <= 2.0 * mSettings.maxMove; k += 1.0) {
            const double distance = mSettings.step * k;
            if (length > 0.0 && (tryOffset(normal * (distance / length))
                                 || tryOffset(normal * (-distance / length)))) {
                return true;
            }
            for (const Vec3d& d : latticeDirections()) {
                if (tryOffset(d * distance)) return true;
            }
        }
        return false;
    }

    /// shapeFan()'s places tried, with the fan's shape there.
    struct Step
    {
        FanShape shape;
        Vec3d place;
    };
    std::vector<Step> mSteps;
    /// moveTogether()'s corners, where they were, and the triangles around them.
    std::vector<std::uint32_t> mGroup, mGroupTriangles;
    std::vector<Vec3d> mGroupPoints;
    /// Per triangle: in a meeting pair (set at the start of every widened round).
    std::vector<char> mIsMeeting;
};

} // namespace


std::size_t
pullTowardsSource(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                  const SeparationSettings& settings, const std::vector<std::uint32_t>& points)
{
    // Most points are close enough: the state, with a grid over the whole mesh, is built only
    // if one is not.
    const std::vector<std::uint32_t> patchOf = trianglePatches(mesh);
    std::vector<std::uint32_t> first, around, patches, far;
    trianglesAroundPoints(mesh, first, around);
    for (const std::uint32_t v : points) {
        if (!movable[v]) continue;
        patchesAround(v, first, around, patchOf, patches);
        if (settings.source->farthest(mesh.points[v], patches).distance > settings.sourceLimit) {
            far.push_back(v);
        }
    }
    if (far.empty()) return 0;
    Separation separation(mesh, movable, settings, nullptr);
    std::size_t moved = 0;
    for (const std::uint32_t v : far) moved += separation.pullTowardsSource(v);
    return moved;
}


std::size_t
pullTowardsFaceCentres(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                       const SeparationSettings& settings, const std::vector<FaceCentre>& centres)
{
    if (centres.empty()) return 0;
    Separation separation(mesh, movable, settings, nullptr);
    std::size_t far = 0;
    for (const FaceCentre& c : centres) {
        far += !separation.pullTowardsCentre(c.patch, settings.source->scaled(c.point));
    }
    return far;
}


std::size_t
shapeSharpFans(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
               const SeparationSettings& settings, const std::vector<std::uint32_t>& points)
{
    Separation separation(mesh, movable, settings, nullptr);
    const Separation::IndependentBlocks blocks = separation.independentBlocks(points);
    separation.buildSourceCells(blocks.points);
    auto shapeBlocks = [&](std::size_t begin, std::size_t end) {
        Separation mover(separation);
        std::size_t moved = 0;
        for (std::size_t b = begin; b < end; ++b) {
            for (std::size_t i = blocks.blockStart[b]; i < blocks.blockStart[b + 1]; ++i) {
                moved += mover.shapeFan(blocks.points[i]);
            }
        }
        return moved;
    };
    std::atomic<std::size_t> moved{0};
    for (int colour = 0; colour < 8; ++colour) {
        const std::size_t first = blocks.colourStart[colour];
        forEachRange(blocks.colourStart[colour + 1] - first, 1, settings.threaded,
                     [&](std::size_t begin, std::size_t end) {
            moved += shapeBlocks(first + begin, first + end);
        });
    }
    return moved;
}


std::size_t
separatePatches(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
                const SeparationSettings& settings, const PointArray* start,
                TrianglePairs* meeting, const TrianglePairs* known)
{
    Pairs left = Separation(mesh, movable, settings, start).run(known);
    const std::size_t count = left.size();
    if (meeting) meeting->swap(left);
    return count;
}


std::size_t
splitMeetingTriangles(InterfaceMesh& mesh, std::vector<std::uint8_t>& movable,
                      PointArray& start, const TrianglePairs& pairs, RawPatchDistance* source,
                      double sourceLimit)
{
    // The meeting triangles with at most one free corner.
    std::vector<std::uint32_t> meeting;
    for (const auto& [f, g] : pairs) {
        for (const std::uint32_t h : {f, g}) {
            const openvdb::Vec3I& t = mesh.triangles[h];
            if (int(movable[t[0]]) + movable[t[1]] + movable[t[2]] <= 1) meeting.push_back(h);
        }
    }
    if (meeting.empty()) return 0;
    std::sort(meeting.begin(), meeting.end());
    meeting.erase(std::unique(meeting.begin(), meeting.end()), meeting.end());

    const std::size_t triangleCount = mesh.triangles.size();
    const std::vector<std::uint32_t> patchOf = trianglePatches(mesh);
    std::vector<std::uint32_t> first, around;
    trianglesAroundPoints(mesh, first, around);
    // The triangle across an inner edge; a feature curve segment stays as it is.
    auto across = [&](std::uint32_t f, std::uint32_t u, std::uint32_t v) {
        return triangleAcross(mesh, first, around, patchOf, f, u, v);
    };

    // Every meeting triangle not changed yet in this call splits its longest inner edge whose
    // other triangle is unchanged too, at the midpoint: (a, b, c) and (b, a, d) become
    // (a, m, c), (m, b, c), (b, m, d), (m, a, d).
    std::vector<char> changed(triangleCount, 0);
    mesh.points.reserve(mesh.points.size() + meeting.size());
    start.reserve(start.size() + meeting.size());
    std::vector<std::vector<openvdb::Vec3I>> added(mesh.patches.size());
    std::size_t splits = 0;
    for (const std::uint32_t f : meeting) {
        if (changed[f]) continue;
        const openvdb::Vec3I t = mesh.triangles[f];
        int best = -1;
        std::int64_t bestOther = -1;
        double bestLength = 0.0;
        bool bestNear = false;
        const std::vector<std::uint32_t> patches{patchOf[f]};
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t a = t[i], b = t[(i + 1) % 3];
            const double length = (mesh.points[a] - mesh.points[b]).lengthSqr();
            const std::int64_t g = across(f, a, b);
            if (g < 0 || changed[g]) continue;
            bool near = true;
            if (source) {
                const Vec3d midpoint = (mesh.points[a] + mesh.points[b]) * 0.5;
                near = source->farthest(midpoint, patches).distance <= sourceLimit;
            }
            if (bestNear && !near) continue;
            if (near == bestNear && length <= bestLength) continue;
            best = i;
            bestOther = g;
            bestLength = length;
            bestNear = near;
        }
        if (best < 0) continue;
        const std::uint32_t g = std::uint32_t(bestOther);
        const std::uint32_t a = t[best], b = t[(best + 1) % 3], c = t[(best + 2) % 3];
        const openvdb::Vec3I& u = mesh.triangles[g];
        const std::uint32_t d =
            u[0] != a && u[0] != b ? u[0] : u[1] != a && u[1] != b ? u[1] : u[2];
        const std::uint32_t m = std::uint32_t(mesh.points.size());
        mesh.points.push_back((mesh.points[a] + mesh.points[b]) * 0.5);
        start.push_back((start[a] + start[b]) * 0.5);
        movable.push_back(1);
        mesh.triangles[f] = openvdb::Vec3I(a, m, c);
        mesh.triangles[g] = openvdb::Vec3I(b, m, d);
        added[patchOf[f]].emplace_back(m, b, c);
        added[patchOf[f]].emplace_back(m, a, d);
        changed[f] = changed[g] = 1;
        ++splits;
    }
    // Each patch's new triangles after its others, so the patches stay consecutive.
    TriangleArray triangles;
    triangles.reserve(triangleCount + 2 * splits);
    for (std::size_t p = 0; p < mesh.patches.size(); ++p) {
        InterfacePatch& patch = mesh.patches[p];
        const auto begin = mesh.triangles.begin() + patch.firstTriangle;
        patch.firstTriangle = triangles.size();
        triangles.insert(triangles.end(), begin, begin + patch.triangleCount);
        triangles.insert(triangles.end(), added[p].begin(), added[p].end());
        patch.triangleCount += added[p].size();
    }
    mesh.triangles.swap(triangles);
    return splits;
}


std::size_t
separateAround(InterfaceMesh& mesh, const std::vector<std::uint8_t>& movable,
               const PointArray& start, const SeparationSettings& settings,
               std::size_t firstPoint)
{
    // Free: the points from firstPoint on and the movable corners of their triangles.
    std::vector<std::uint8_t> free(mesh.points.size(), 0);
    for (const openvdb::Vec3I& t : mesh.triangles) {
        if (t[0] < firstPoint && t[1] < firstPoint && t[2] < firstPoint) continue;
        for (int k = 0; k < 3; ++k) free[t[k]] = movable[t[k]];
    }
    // A free point moves at most 2 maxMove from where it is now, so a triangle its own ones
    // can meet overlaps their boxes widened by that: such a triangle shares a grid cell with
    // one of those widened boxes.
    const double inverse = 1.0 / settings.cellSize, margin = 2.0 * settings.maxMove;
    auto forEachCell = [&](std::size_t f, double widen, const auto& body) {
        openvdb::Vec3i a, b;
        triangleCells(mesh, f, widen, inverse, a, b);
        for (int x = a[0]; x <= b[0]; ++x) {
            for (int y = a[1]; y <= b[1]; ++y) {
                for (int z = a[2]; z <= b[2]; ++z) body(cellKey(openvdb::Vec3i(x, y, z)));
            }
        }
    };
    std::vector<std::uint64_t> cells;
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        const openvdb::Vec3I& t = mesh.triangles[f];
        if (!free[t[0]] && !free[t[1]] && !free[t[2]]) continue;
        forEachCell(f, margin, [&](std::uint64_t key) { cells.push_back(key); });
    }
    if (cells.empty()) return 0;
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    // One bit per hashed cell key, set for those cells: most triangles are far from all of
    // them and take a bit test per cell instead of a binary search.
    constexpr int HASH_BITS = 22;
    std::vector<std::uint64_t> hashed(std::size_t(1) << (HASH_BITS - 6), 0);
    auto hashOf = [](std::uint64_t key) {
        return (key * 0x9E3779B97F4A7C15ull) >> (64 - HASH_BITS);
    };
    for (const std::uint64_t key : cells) {
        const std::uint64_t h = hashOf(key);
        hashed[h >> 6] |= std::uint64_t(1) << (h & 63);
    }

    // Those triangles, patch by patch, and all points: separation there moves free points
    // only, so no triangle left out can come to meet one that moves.
    InterfaceMesh region;
    for (const InterfacePatch& patch : mesh.patches) {
        InterfacePatch part = patch;
        part.firstTriangle = region.triangles.size();
        for (std::size_t f = patch.firstTriangle; f < patch.firstTriangle + patch.triangleCount;
             ++f) {
            bool near = false;
            forEachCell(f, 0.0, [&](std::uint64_t key) {
                const std::uint64_t h = hashOf(key);
                near = near || ((hashed[h >> 6] >> (h & 63) & 1)
                                && std::binary_search(cells.begin(), cells.end(), key));
            });
            if (near) region.triangles.push_back(mesh.triangles[f]);
        }
        // Empty ones too: patch indices stay those of the mesh (settings.source takes them).
        part.triangleCount = region.triangles.size() - part.firstTriangle;
        region.patches.push_back(part);
    }
    region.points.swap(mesh.points);
    const std::size_t left = separatePatches(region, free, settings, &start);
    mesh.points.swap(region.points);
    return left;
}

} // namespace vdbi
