// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Remeshing.h>

#include <vdbi/FeatureCurves.h>
#include <vdbi/Interruption.h>
#include <vdbi/IsotropicRemeshing.h>
#include <vdbi/PatchBoundary.h>
#include <vdbi/PatchSeparation.h>
#include <vdbi/ReferenceSurface.h>

#include <openvdb/Exceptions.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

namespace vdbi {

namespace {

using Vec3d = openvdb::Vec3d;

/// How far, in voxels, smoothing may move a curve point and a reference surface point: enough
/// to flatten the staircase, little enough that a one-voxel rod keeps most of its section.
constexpr double CURVE_BOUND = 0.45, SURFACE_BOUND = 0.45;
/// Taubin iterations along the feature curves and on the reference surfaces.
constexpr int CURVE_SMOOTHING = 10, SURFACE_SMOOTHING = 10;
/// How far, in voxels, a collapse, flip or relaxation move may take the surface from a point
/// of the reference surface (measured against the fixed reference, so tips do not erode round
/// by round; frog at 2 voxels: every raw face centre within 0.98 voxel of the result).
constexpr double DEVIATION = 0.6;
/// How far, in voxels, separatePatches() moves a vertex per round and at most.
constexpr double SEPARATION_STEP = 0.1, SEPARATION_MOVE = 0.4;

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
    for (int k = 0; k < 3; ++k) if (!std::isfinite(best[k])) best[k] = smallest;
    return best;
}

/// Calls @a body(p) for every patch, largest first so the long ones do not start last, in
/// parallel or not.
template<typename Body>
void
forEachPatch(const InterfaceMesh& raw, bool threaded, const Body& body)
{
    const std::size_t count = raw.patches.size();
    std::vector<std::size_t> order(count);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
        return raw.patches[x].triangleCount > raw.patches[y].triangleCount;
    });
    auto run = [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) body(order[i]);
    };
    const tbb::blocked_range<std::size_t> all(0, count, 1);
    if (threaded) tbb::parallel_for(all, run, tbb::simple_partitioner());
    else run(all);
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
    settings.low2 = std::pow(0.8 * options.edgeLength, 2);
    settings.high2 = std::pow(4.0 / 3.0 * options.edgeLength, 2);
    settings.iterations = options.iterations;
    settings.deviation2 = std::pow(DEVIATION * smallestVoxel, 2);

    RemeshStatistics stats;
    auto clock = std::chrono::steady_clock::now();

    checkInterrupt(options.interrupter, "remeshing");
    FeatureCurves curves = findFeatureCurves(raw, options.threaded);
    smoothFeatureCurves(curves, raw, CURVE_SMOOTHING, voxel * CURVE_BOUND, options.threaded);
    resampleFeatureCurves(curves, settings.target, options.threaded);
    stats.curveSeconds = secondsSince(clock);
    checkInterrupt(options.interrupter, "remeshing");

    const std::size_t patchCount = raw.patches.size();
    std::vector<PatchReference> references(patchCount);
    InterruptFlag interrupt(options.interrupter);
    forEachPatch(raw, options.threaded, [&](std::size_t p) {
        if (interrupt.poll()) return;
        references[p] = buildPatchReference(raw, p, curves, SURFACE_SMOOTHING,
                                            voxel * SURFACE_BOUND);
    });
    interrupt.throwIfStopped("remeshing");
    stats.referenceSeconds = secondsSince(clock);

    std::vector<PatchResult> results(patchCount);
    forEachPatch(raw, options.threaded, [&](std::size_t p) {
        if (interrupt.poll()) return;
        RemeshingPatch patch(raw.patches[p], std::uint32_t(p), references[p], curves);
        patch.attachCurveSamples();
        // Fallback: the extracted triangles fitted to the samples, should a round go wrong.
        PatchResult fitted = patch.exportMesh();
        if (!remeshIsotropically(patch, settings, interrupt)) return;
        results[p] = patch.hasExpectedBoundary() ? patch.exportMesh() : std::move(fitted);
        references[p] = PatchReference();
    });
    interrupt.throwIfStopped("remeshing");

    InterfaceMesh out;
    const std::uint32_t sampleCount = std::uint32_t(curves.samplePoints.size());
    out.points.assign(curves.samplePoints.begin(), curves.samplePoints.end());
    std::size_t triangleCount = 0;
    for (const PatchResult& r : results) triangleCount += r.triangles.size();
    out.triangles.reserve(triangleCount);
    out.patches.reserve(patchCount);
    for (std::size_t p = 0; p < patchCount; ++p) {
        const std::uint32_t offset = std::uint32_t(out.points.size()) - sampleCount;
        PatchResult& r = results[p];
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
        std::vector<std::array<std::uint32_t, 3>>().swap(r.triangles);
    }
    out.keyScale = 0;
    stats.remeshingSeconds = secondsSince(clock);

    checkInterrupt(options.interrupter, "remeshing");
    std::vector<std::uint8_t> movable(out.points.size(), 1);
    std::fill(movable.begin(), movable.begin() + sampleCount, 0);
    SeparationSettings separation;
    separation.cellSize = options.edgeLength;
    separation.step = SEPARATION_STEP * smallestVoxel;
    separation.maxMove = SEPARATION_MOVE * smallestVoxel;
    separation.threaded = options.threaded;
    separatePatches(out, movable, separation);
    stats.separationSeconds = secondsSince(clock);
    if (statistics) *statistics = stats;
    return out;
}

} // namespace vdbi
