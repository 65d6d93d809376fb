// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Remeshing.h>

#include <vdbi/ChordOwners.h>
#include <vdbi/FaceCentreCoverage.h>
#include <vdbi/FeatureCurves.h>
#include <vdbi/Interruption.h>
#include <vdbi/IsotropicRemeshing.h>
#include <vdbi/MeetingEdgeCollapses.h>
#include <vdbi/MeetingEdgeFlips.h>
#include <vdbi/ParallelRanges.h>
#include <vdbi/PatchBoundary.h>
#include <vdbi/PatchSeparation.h>
#include <vdbi/RawPatchDistance.h>
#include <vdbi/ReferenceSurface.h>

#include <openvdb/Exceptions.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <numeric>
#include <utility>

namespace vdbi {

namespace {

using Vec3d = openvdb::Vec3d;

/// How far, in voxels, smoothing may move a curve point and a reference surface point: enough
/// to flatten the staircase, little enough that a one-voxel rod keeps most of its section.
constexpr double CURVE_BOUND = 0.45, SURFACE_BOUND = 0.45;
/// How far, in voxels, a chord between two curve samples may pass from the smoothed curve.
/// At longer edge lengths a uniform resampling cuts tight bends (the end of a strip one voxel
/// wide), leaving voxel faces there over a voxel away from the patch and the patches there
/// crossing (frog at 4 voxels: 520 -> 225 crossing pairs, faces up to 1.59 -> 0.97 voxel
/// away). 0.5 cut the crossings on the voxel-art samples further but added samples on the
/// frog's gentle bends: 55 crossing pairs at 2 voxels instead of 31.
constexpr double CHORD_DEVIATION = 0.7;
/// Taubin iterations along the feature curves and on the reference surfaces.
constexpr int CURVE_SMOOTHING = 10, SURFACE_SMOOTHING = 10;
/// How far, in voxels, a collapse, flip or relaxation move may take the surface from a point
/// of the reference surface (measured against the fixed reference, so tips do not erode round
/// by round; frog at 2 voxels: every raw face centre within 0.98 voxel of the result).
constexpr double DEVIATION = 0.6;
/// The same for the moves that smooth sharp fans after the last round. With 0.6 (and fans
/// under 35 degrees) they took menger's raw faces up to 1.031 voxels from the result at 2
/// voxels (0.981 without them); with 0.5, 0.986.
constexpr double SMOOTHING_DEVIATION = 0.5;
/// @brief The smallest target, in voxels, the first round collapses towards before the user's
/// (RemeshSettings::finestCoarsening).
/// @details Frog at 2 voxels, one thread: the first round's collapses take 12.7 s through
/// 0.5 and 1 voxel, 15.0 s through 1 voxel only, 19.6 s straight from the staircase (0.25
/// too: 14.3 s). The smallest angle's 1st percentile rises from 18.8 to 19.7 degrees.
constexpr double FINEST_COARSENING = 0.5;
/// How far, in voxels, separatePatches() moves a vertex per round.
constexpr double SEPARATION_STEP = 0.1;

/// @brief How far, in voxels along each axis, separation may take an inner vertex from the
/// voxel faces of its patches (or no farther than it was), its splits prefer midpoints
/// within, and pullFarPoints() pulls vertices to.
/// @details The output promises one voxel. Separation pushed vertices past it (frog at 4
/// voxels: 1.162, monu16 1.191), and vertices that remeshing could not project onto the
/// reference stayed there (frog 1.030, monu16 1.046). Its moves, flips and collapses keep
/// the voxel face centres and the centroids of their halves within it too
/// (RawPatchDistance::keepsCovered()): a flip across a thin tip left a voxel face centre
/// 1.028 voxels from the frog at 4 voxels (0.957 with the bound).
constexpr double CLOSENESS_LIMIT = 0.95;
/// What the output promises, in voxels along each axis: every voxel face centre within it of
/// its remeshed patch (RemeshStatistics::farFaceCentres counts those that are not).
constexpr double PROMISED_CLOSENESS = 1.0;
/// @brief How far, in voxels, shapeSharpFans() may take a point or a face from the voxel
/// faces (or farther than it was), and how far it may move a point, in target lengths (its
/// largest step aside).
/// @details Under the test's bound of one voxel, as every step after remeshing keeps. Frog
/// at 2 voxels: 1st-percentile smallest angle 23.3 -> 26.0 degrees, edges in range 97.98 ->
/// 98.10 %; closeness unchanged (0.825 voxel vertex to faces, 0.909 face centre to mesh).
constexpr double SHAPING_LIMIT = 0.8, SHAPING_REACH = 0.3;
/// @brief The range the result is judged by, in target lengths: collapseMeetingAndShortEdges()
/// collapses the edges under SHORT_EDGE where it makes none over LONG_EDGE.
/// @details Frog at 2 voxels: edges in range 98.10 -> 99.02 %, 1st-percentile smallest angle
/// 26.0 -> 26.9 degrees (the collapses leave no sharper fan); face centres to the result
/// 0.909 -> 0.947 voxel.
constexpr double SHORT_EDGE = 0.5, LONG_EDGE = 1.5;
/// Distances to the voxel faces are exact up to this times CLOSENESS_LIMIT.
constexpr double RAW_DISTANCE_RADIUS = 1.25;
/// @brief How far, in voxels, an inner point may lie from its reference surface before the
/// last step measures its distance to the voxel faces (pullTowardsSource()).
/// @details The reference lies within SURFACE_BOUND of the faces, so a point nearer to it is
/// within about 0.75 voxel of them. Measuring only these finds all: frog at 4 voxels, the
/// same 5 points are pulled as when every inner point is measured (5311 points instead of
/// 109 488: 1.9 s less).
constexpr double OFF_REFERENCE = 0.3;

/// One cycle of separation, splits and flips (separateSplitAndFlip()).
struct SeparationCycle
{
    double maxMove;     ///< in voxels, from where a vertex started
    bool samplesMove;   ///< the inner samples of the feature curves move too
};
/// @brief The cycles: the first always, each next where pairs are left, kept only if it
/// leaves fewer.
/// @details The second lets inner vertices go a little farther. The third moves the curves'
/// inner samples too (junctions stay, a sample stays shared by all its patches): in a wedge
/// of one label at a curve, a triangle with two corners on the curve can be freed only by
/// them. Frog at 2 voxels: 32 pairs after the first, 6 after the second, 0 after the third;
/// at 4 voxels 225, 130, 92 (monu16 31 -> 24). Two cycles, the second with the samples,
/// are 0.3 s faster on the frog at 2 voxels and leave 0 pairs there too, but more at 4
/// voxels on monu16 (35) and monu1 (4 instead of 0). The farthest vertex and raw face stay
/// where they were (0.77 and 0.98 voxel at 2 voxels). The fourth lets everything go farther:
/// where a sheet of one label, one voxel thick, runs diagonally between two others, its two
/// sides smoothed at 4 voxels cross over a width the third cannot open (frog at 4 voxels with
/// the untouched voxels of the repair kept whole: 7 pairs left after three cycles, 4 after
/// the collapses; none after the fourth). It leaves today's output as it was on the frog at 2
/// and 4 voxels, monu16 at 4 and monu1 at 1, 2 and 4 (the third leaves no pair there). The
/// fifth lets points go up to a whole voxel (closeness is the separation's own guard, not
/// this bound): it frees the random smooth field 26 at 2 voxels (3 pairs after the fourth).
/// Where the fourth leaves none it does not run: the frog's output is as it was.
constexpr SeparationCycle SEPARATION_CYCLES[] = {
    {0.4, false}, {0.5, false}, {0.5, true}, {0.75, true}, {1.0, true}};

/// World size of one voxel per axis from the point keys: the smallest ratio of world to key
/// distance along triangle edges parallel to that axis of the key grid; zeros without keys.
Vec3d
voxelSizeFromKeys(const InterfaceMesh& mesh)
{
    if (mesh.pointKeys.size() != mesh.points.size() || mesh.keyScale <= 0) return Vec3d(0.0);
    const double inf = std::numeric_limits<double>::infinity();
    Vec3d best(inf, inf, inf);
    const std::size_t count = std::min<std::size_t>(mesh.triangles.size(), 4096);
    for (std::size_t t = 0; t < count; ++t) {
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t u = mesh.triangles[t][i], v = mesh.triangles[t][(i + 1) % 3];
            const VertexKey &ku = mesh.pointKeys[u], &kv = mesh.pointKeys[v];
            int axes = 0, axis = 0;
            std::int64_t delta = 0;
            for (int k = 0; k < 3; ++k) {
                if (ku[k] != kv[k]) {
                    ++axes;
                    axis = k;
                    delta = std::abs(ku[k] - kv[k]);
                }
            }
            if (axes != 1) continue;
            const double world = (mesh.points[u] - mesh.points[v]).length();
            best[axis] = std::min(best[axis], world * double(mesh.keyScale) / double(delta));
        }
    }
    const double smallest = std::min({best[0], best[1], best[2]});
    if (!std::isfinite(smallest)) return Vec3d(0.0);
    for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(best[k])) best[k] = smallest;
        // The differences of world points carry rounding (4.1 - 4.0 is not 0.1): the size to
        // 12 significant digits is the grid's own for any size written in decimal. An ulp
        // off, remeshing ties break the other way and the result is not the one the same mesh
        // gives with the grid's voxel size.
        char text[32];
        const std::to_chars_result end = std::to_chars(
            text, text + sizeof(text), best[k], std::chars_format::general, 12);
        std::from_chars(text, end.ptr, best[k]);
    }
    return best;
}

/// @brief Separation, then splits of the triangles it leaves meeting with at most one free
/// corner, separation around the new points, and flips; @a left is set to the pairs still
/// meeting (all of them: a next call takes them as @a known, see separatePatches()).
/// @details Every pair still meeting after the splits has a triangle with a corner among the
/// points of the pairs separation left or the corners of the split triangles: splits keep
/// the shape, and separateAround() moves only these corners. The flips look only there.
/// Separation moves the inner points (@a inner, appended to by the splits) and the curve
/// samples @a movingSamples; splits and flips tell inner points by @a inner alone (an edge
/// between two samples may be another patch's too).
void
separateSplitAndFlip(InterfaceMesh& mesh, std::vector<std::uint8_t>& inner,
                     const std::vector<std::uint32_t>& movingSamples, PointArray& start,
                     const SeparationSettings& settings, TrianglePairs& left,
                     const TrianglePairs* known = nullptr)
{
    std::vector<std::uint8_t> moving = inner;
    for (const std::uint32_t v : movingSamples) moving[v] = 1;
    TrianglePairs meeting;
    separatePatches(mesh, moving, settings, &start, &meeting, known);
    std::vector<std::uint32_t> suspects;
    for (const auto& [f, g] : meeting) {
        for (int k = 0; k < 3; ++k) {
            suspects.push_back(mesh.triangles[f][k]);
            suspects.push_back(mesh.triangles[g][k]);
        }
    }
    const std::size_t firstNew = mesh.points.size();
    if (splitMeetingTriangles(mesh, inner, start, meeting, settings.source,
                              settings.sourceLimit) > 0) {
        moving.resize(inner.size(), 1);
        separateAround(mesh, moving, start, settings, firstNew);
    }
    for (const openvdb::Vec3I& t : mesh.triangles) {
        if (t[0] >= firstNew || t[1] >= firstNew || t[2] >= firstNew) {
            suspects.insert(suspects.end(), {t[0], t[1], t[2]});
        }
    }
    std::sort(suspects.begin(), suspects.end());
    suspects.erase(std::unique(suspects.begin(), suspects.end()), suspects.end());
    flipMeetingEdges(mesh, inner, settings.cellSize, settings.threaded, suspects, &left,
                     settings.source, settings.sourceLimit);
}

/// The settings of the pulls towards the voxel faces: within CLOSENESS_LIMIT of them.
SeparationSettings
pullSettings(RawPatchDistance& rawDistance, const RemeshOptions& options, const Vec3d& voxel)
{
    SeparationSettings pull;
    pull.cellSize = options.edgeLength;
    // A pull goes at most the radius of rawDistance, in voxels.
    pull.maxMove =
        RAW_DISTANCE_RADIUS * CLOSENESS_LIMIT * std::max({voxel[0], voxel[1], voxel[2]});
    pull.threaded = options.threaded;
    pull.source = &rawDistance;
    pull.sourceLimit = CLOSENESS_LIMIT;
    pull.sourceUnit = std::min({voxel[0], voxel[1], voxel[2]});
    return pull;
}

/// pullTowardsSource() of the inner points @a far that lie over CLOSENESS_LIMIT voxels from
/// their raw patch.
void
pullFarPoints(InterfaceMesh& mesh, const std::vector<std::uint8_t>& inner,
              const std::vector<std::uint32_t>& far, RawPatchDistance& rawDistance,
              const RemeshOptions& options, const Vec3d& voxel)
{
    pullTowardsSource(mesh, inner, pullSettings(rawDistance, options, voxel), far);
}

/// pullTowardsFaceCentres() of the voxel face centres over CLOSENESS_LIMIT voxels from
/// their patch. After the moves that may take the surface from centres over their own
/// bounds (shapeSharpFans() guards only those within SHAPING_LIMIT); the collapses after it
/// keep every centre within CLOSENESS_LIMIT there.
void
pullToFarFaceCentres(InterfaceMesh& mesh, std::vector<std::uint8_t> inner,
                     const RawFaceCentres& rawCentres, RawPatchDistance& rawDistance,
                     const RemeshOptions& options, const Vec3d& voxel)
{
    const std::vector<FaceCentre> far =
        findFarFaceCentres(rawCentres, mesh, voxel, CLOSENESS_LIMIT, options.threaded);
    if (far.empty()) return;
    // The points a last separation cycle split and did not keep are gone from the mesh.
    inner.resize(mesh.points.size());
    pullTowardsFaceCentres(mesh, inner, pullSettings(rawDistance, options, voxel), far);
}

/// shapeSharpFans() of every inner point, after separation: the fans that remeshing left
/// sharp next to a tight part of a patch boundary (where a patch alone cannot see the others),
/// and those whose moves the reference surface's guards refused, within SHAPING_LIMIT of the
/// voxel faces. The corners of the pairs still meeting (@a left) stay, so that those pairs
/// are as collapseMeetingEdges() expects them.
void
shapeFansAcrossPatches(InterfaceMesh& mesh, std::vector<std::uint8_t> inner,
                       const TrianglePairs& left, RawPatchDistance& rawDistance,
                       const RemeshOptions& options, double smallestVoxel)
{
    // The points a last separation cycle split and did not keep are gone from the mesh.
    inner.resize(mesh.points.size());
    for (const auto& [f, g] : left) {
        for (int k = 0; k < 3; ++k) inner[mesh.triangles[f][k]] = inner[mesh.triangles[g][k]] = 0;
    }
    SeparationSettings shaping;
    shaping.cellSize = options.edgeLength;
    shaping.maxMove = SHAPING_REACH * options.edgeLength;
    shaping.threaded = options.threaded;
    shaping.source = &rawDistance;
    shaping.sourceLimit = SHAPING_LIMIT;
    shaping.sourceUnit = smallestVoxel;
    std::vector<std::uint32_t> points;
    for (std::uint32_t v = 0; v < std::uint32_t(inner.size()); ++v) {
        if (inner[v]) points.push_back(v);
    }
    shapeSharpFans(mesh, inner, shaping, points);
}

double
secondsSince(std::chrono::steady_clock::time_point& start)
{
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - start).count();
    start = now;
    return s;
}

} // namespace


InterfaceMesh
remeshPatches(const InterfaceMesh& raw, const RemeshOptions& options,
              RemeshStatistics* statistics)
{
    if (!std::isfinite(options.edgeLength) || options.edgeLength <= 0.0) {
        OPENVDB_THROW(openvdb::ValueError, "remeshing: the edge length must be a finite "
            "number > 0, not " << options.edgeLength);
    }
    if (options.iterations < 0) {
        OPENVDB_THROW(openvdb::ValueError, "remeshing: iterations must be >= 0, not "
            << options.iterations);
    }
    Vec3d voxel = options.voxelSize;
    if (!(voxel[0] > 0.0 && voxel[1] > 0.0 && voxel[2] > 0.0)) voxel = voxelSizeFromKeys(raw);
    if (!(voxel[0] > 0.0 && voxel[1] > 0.0 && voxel[2] > 0.0)) voxel = Vec3d(options.edgeLength);
    const double smallestVoxel = std::min({voxel[0], voxel[1], voxel[2]});

    RemeshSettings settings;
    settings.target = options.edgeLength;
    settings.high2 = std::pow(4.0 / 3.0 * options.edgeLength, 2);
    settings.iterations = options.iterations;
    settings.deviation2 = std::pow(DEVIATION * smallestVoxel, 2);
    settings.smoothingDeviation2 = std::pow(SMOOTHING_DEVIATION * smallestVoxel, 2);
    settings.finestCoarsening = FINEST_COARSENING * smallestVoxel;

    RemeshStatistics stats;
    auto clock = std::chrono::steady_clock::now();

    checkInterrupt(options.interrupter, "remeshing");
    FeatureCurves curves = findFeatureCurves(raw, options.threaded);
    smoothFeatureCurves(curves, raw, CURVE_SMOOTHING, voxel * CURVE_BOUND, options.threaded);
    resampleFeatureCurves(curves, settings.target, CHORD_DEVIATION * smallestVoxel,
                          options.threaded);
    measureCurveSides(curves, raw, options.threaded);
    stats.curveSeconds = secondsSince(clock);
    checkInterrupt(options.interrupter, "remeshing");

    // A patch is remeshed right after its reference surface is built, in one parallel pass:
    // no thread waits at the end of the references for the largest patch's.
    const std::size_t patchCount = raw.patches.size();
    std::vector<PatchResult> results(patchCount);
    std::vector<double> referenceTimes(patchCount, 0.0), remeshingTimes(patchCount, 0.0);
    std::vector<RemeshStepSeconds> stepTimes(patchCount);
    InterruptFlag interrupt(options.interrupter);
    // Separation after this asks about nearly every raw patch (frog at 2 voxels: 90 of 96),
    // one at a time, and twice for the face centres of all. Their cells are sorted and their
    // centres found here, each patch's a piece after the patches (a triangle takes about a
    // hundredth of the time it is remeshed in) that fills a gap the last patches leave: in
    // separation, the cells took 0.3 s in one thread, and the centres were found twice.
    RawPatchDistance rawDistance(raw, voxel, RAW_DISTANCE_RADIUS * CLOSENESS_LIMIT);
    RawFaceCentres rawCentres(patchCount);
    std::vector<std::size_t> pieces = patchSizes(raw);
    for (std::size_t p = 0; p < patchCount; ++p) pieces.push_back(pieces[p] / 100);
    forEachLargestFirst(pieces, options.threaded, [&](std::size_t piece) {
        if (interrupt.poll()) return;
        if (piece >= patchCount) {
            const std::size_t p = piece - patchCount;
            rawDistance.buildCells({std::uint32_t(p)});
            rawCentres[p] = rawFaceCentresOf(raw, p, voxel);
            return;
        }
        const std::size_t p = piece;
        auto patchClock = std::chrono::steady_clock::now();
        const PatchReference reference = buildPatchReference(raw, p, curves, SURFACE_SMOOTHING,
                                                             voxel * SURFACE_BOUND);
        referenceTimes[p] = secondsSince(patchClock);
        if (interrupt.poll()) return;
        RemeshingPatch patch(raw.patches[p], std::uint32_t(p), reference, curves);
        patch.attachCurveSamples();
        if (!remeshIsotropically(patch, settings, interrupt, &stepTimes[p])) return;
        if (patch.hasExpectedBoundary()) {
            results[p] = patch.exportMesh(true);
        } else {
            // Fallback, should a round go wrong: the extracted triangles fitted to the
            // samples, made again rather than kept through the rounds (the largest patch's
            // copy is tens of MB). Its inner points are the extracted ones: at the voxel faces.
            RemeshingPatch fitted(raw.patches[p], std::uint32_t(p), reference, curves);
            fitted.attachCurveSamples();
            results[p] = fitted.exportMesh();
        }
        remeshingTimes[p] = secondsSince(patchClock);
    });
    interrupt.throwIfStopped("remeshing");
    // The pass's wall time, shared between references and rounds as their summed times are.
    const double passSeconds = secondsSince(clock);
    const double referenceSum =
        std::accumulate(referenceTimes.begin(), referenceTimes.end(), 0.0);
    const double patchSum =
        referenceSum + std::accumulate(remeshingTimes.begin(), remeshingTimes.end(), 0.0);
    stats.referenceSeconds = patchSum > 0.0 ? passSeconds * referenceSum / patchSum : 0.0;
    const double roundSeconds = passSeconds - stats.referenceSeconds;
    for (const RemeshStepSeconds& steps : stepTimes) stats.roundSteps += steps;

    InterfaceMesh out;
    const std::uint32_t sampleCount = std::uint32_t(curves.samplePoints.size());
    out.points.assign(curves.samplePoints.begin(), curves.samplePoints.end());
    std::size_t triangleCount = 0;
    for (const PatchResult& r : results) triangleCount += r.triangles.size();
    out.triangles.reserve(triangleCount);
    out.patches.reserve(patchCount);
    // Inner points off their reference surface, that may lie far from the voxel faces.
    std::vector<std::uint32_t> offReference;
    for (std::size_t p = 0; p < patchCount; ++p) {
        const std::uint32_t offset = std::uint32_t(out.points.size()) - sampleCount;
        PatchResult& r = results[p];
        for (std::size_t i = 0; i < r.referenceDistances.size(); ++i) {
            if (r.referenceDistances[i] > OFF_REFERENCE * smallestVoxel) {
                offReference.push_back(std::uint32_t(out.points.size() + i));
            }
        }
        out.points.insert(out.points.end(), r.innerPoints.begin(), r.innerPoints.end());
        InterfacePatch patch;
        patch.a = raw.patches[p].a;
        patch.b = raw.patches[p].b;
        patch.firstTriangle = out.triangles.size();
        patch.triangleCount = r.triangles.size();
        for (const auto& t : r.triangles) {
            openvdb::Vec3I tri;
            for (int k = 0; k < 3; ++k) tri[k] = t[k] < sampleCount ? t[k] : t[k] + offset;
            out.triangles.push_back(tri);
        }
        out.patches.push_back(patch);
        std::vector<Vec3d>().swap(r.innerPoints);
        std::vector<double>().swap(r.referenceDistances);
        std::vector<std::array<std::uint32_t, 3>>().swap(r.triangles);
    }
    out.keyScale = 0;
    stats.remeshingSeconds = roundSeconds + secondsSince(clock);

    checkInterrupt(options.interrupter, "remeshing");
    std::vector<std::uint8_t> inner(out.points.size(), 1);
    std::fill(inner.begin(), inner.begin() + sampleCount, 0);
    std::vector<std::uint32_t> innerSamples;
    for (std::uint32_t i = 0; i < sampleCount; ++i) {
        if (curves.sampleCurves[i] != FeatureCurves::NO_CURVE) innerSamples.push_back(i);
    }
    const std::size_t remeshedCount = out.points.size();
    auto separationClock = clock;   // the parts of separation, lap by lap
    PointArray start = out.points;
    TrianglePairs left;
    for (std::size_t c = 0; c < std::size(SEPARATION_CYCLES); ++c) {
        if (c > 0 && left.empty()) break;
        const SeparationCycle& cycle = SEPARATION_CYCLES[c];
        SeparationSettings separation;
        separation.cellSize = options.edgeLength;
        separation.step = SEPARATION_STEP * smallestVoxel;
        separation.maxMove = cycle.maxMove * smallestVoxel;
        separation.threaded = options.threaded;
        separation.source = &rawDistance;
        separation.sourceLimit = CLOSENESS_LIMIT;
        separation.sourceUnit = smallestVoxel;
        const std::vector<std::uint32_t> noSamples;
        const std::vector<std::uint32_t>& samples = cycle.samplesMove ? innerSamples : noSamples;
        if (c == 0) {
            separateSplitAndFlip(out, inner, samples, start, separation, left);
            continue;
        }
        // A cycle whose result was not kept appended its split points: they go.
        inner.resize(out.points.size());
        start.resize(out.points.size());
        InterfaceMesh again = out;
        TrianglePairs leftAgain;
        separateSplitAndFlip(again, inner, samples, start, separation, leftAgain, &left);
        if (leftAgain.size() < left.size()) {
            out = std::move(again);
            left.swap(leftAgain);
        }
    }
    stats.separationCycleSeconds = secondsSince(separationClock);
    // Those and the midpoints that separation's splits made.
    std::vector<std::uint32_t> far = offReference;
    for (std::size_t v = remeshedCount; v < out.points.size(); ++v) {
        far.push_back(std::uint32_t(v));
    }
    pullFarPoints(out, inner, far, rawDistance, options, voxel);
    stats.pullSeconds = secondsSince(separationClock);
    shapeFansAcrossPatches(out, inner, left, rawDistance, options, smallestVoxel);
    stats.fanShapingSeconds = secondsSince(separationClock);
    pullToFarFaceCentres(out, inner, rawCentres, rawDistance, options, voxel);
    stats.pullSeconds += secondsSince(separationClock);
    // Knots that no move or flip frees: collapse free corners; then short edges, every patch
    // in sight (last: it renumbers points).
    ShortEdgeCollapseSettings shortEdges;
    shortEdges.shortLength = SHORT_EDGE * options.edgeLength;
    shortEdges.longLength = LONG_EDGE * options.edgeLength;
    shortEdges.cellSize = options.edgeLength;
    shortEdges.threaded = options.threaded;
    shortEdges.mayJoinFixed = [&curves](std::uint32_t patch, std::uint32_t a, std::uint32_t b) {
        return chordOwner(curves, a, b) == patch;
    };
    shortEdges.source = &rawDistance;
    shortEdges.sourceLimit = CLOSENESS_LIMIT;
    collapseMeetingAndShortEdges(out, inner, shortEdges, left);
    stats.finalCollapseSeconds = secondsSince(separationClock);
    // Searched afresh rather than carried through the steps above: the counts tell the
    // user whether the output keeps its promises, so they must not rest on those steps' own.
    stats.meetingPairs =
        findMeetingPairs(out, options.edgeLength, options.threaded).size();
    stats.farFaceCentres =
        findFarFaceCentres(rawCentres, out, voxel, PROMISED_CLOSENESS, options.threaded).size();
    stats.checkSeconds = secondsSince(separationClock);
    stats.separationSeconds = secondsSince(clock);
    if (statistics) *statistics = stats;
    return out;
}

} // namespace vdbi
