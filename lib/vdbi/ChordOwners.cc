// SPDX-License-Identifier: Apache-2.0

#include <vdbi/ChordOwners.h>

#include <vdbi/ParallelRanges.h>

#include <algorithm>
#include <tuple>
#include <utility>
#include <vector>

namespace vdbi {

namespace {

/// The third corner of a patch's triangle on an extracted feature edge.
struct EdgeSide
{
    std::uint32_t edge;   ///< index into FeatureCurves::edges
    std::uint32_t patch;
    std::uint32_t third;  ///< point index
    bool operator<(const EdgeSide& o) const
    {
        return std::tie(edge, patch) < std::tie(o.edge, o.patch);
    }
};

/// Every patch's triangle on every feature edge (one each: feature edges bound the patches
/// they are in), sorted by edge, then patch.
std::vector<EdgeSide>
edgeSides(const FeatureCurves& curves, const InterfaceMesh& mesh, bool threaded)
{
    std::vector<char> onCurve(mesh.points.size(), 0);
    for (const FeatureEdge& e : curves.edges) {
        onCurve[std::size_t(e.key >> 32)] = onCurve[std::size_t(e.key & 0xffffffffu)] = 1;
    }
    std::vector<std::vector<EdgeSide>> perPatch(mesh.patches.size());
    forEachRange(mesh.patches.size(), 1, threaded, [&](std::size_t begin, std::size_t end) {
        for (std::size_t p = begin; p < end; ++p) {
            const InterfacePatch& patch = mesh.patches[p];
            const std::size_t last = patch.firstTriangle + patch.triangleCount;
            for (std::size_t t = patch.firstTriangle; t < last; ++t) {
                const openvdb::Vec3I& tri = mesh.triangles[t];
                for (int i = 0; i < 3; ++i) {
                    const std::uint32_t a = tri[i], b = tri[(i + 1) % 3];
                    if (!onCurve[a] || !onCurve[b]) continue;
                    if (const FeatureEdge* e = curves.findEdge(a, b)) {
                        perPatch[p].push_back({std::uint32_t(e - curves.edges.data()),
                                               std::uint32_t(p), tri[(i + 2) % 3]});
                    }
                }
            }
        }
    });
    std::vector<EdgeSide> sides;
    for (const auto& s : perPatch) sides.insert(sides.end(), s.begin(), s.end());
    std::sort(sides.begin(), sides.end());
    return sides;
}

/// The unit direction from feature edge @a e into patch @a p's triangle on it, across the
/// edge; zero if the patch has none there.
openvdb::Vec3d
sideOf(const FeatureCurves& curves, const InterfaceMesh& mesh,
       const std::vector<EdgeSide>& sides, std::uint32_t e, std::uint32_t p)
{
    const auto it = std::lower_bound(sides.begin(), sides.end(), EdgeSide{e, p, 0});
    if (it == sides.end() || it->edge != e || it->patch != p) return openvdb::Vec3d(0.0);
    const std::uint64_t key = curves.edges[e].key;
    const openvdb::Vec3d& a = mesh.points[std::size_t(key >> 32)];
    const openvdb::Vec3d along = mesh.points[std::size_t(key & 0xffffffffu)] - a;
    openvdb::Vec3d across = mesh.points[it->third] - a;
    across -= along * (across.dot(along) / along.lengthSqr());
    return across.normalize() ? across : openvdb::Vec3d(0.0);
}

/// The feature edge of @a curve at arc length @a t.
std::uint32_t
edgeAt(const FeatureCurves& curves, const FeatureCurve& curve, double t)
{
    const auto above = std::upper_bound(curve.arcLength.begin(), curve.arcLength.end(), t);
    const std::size_t i =
        std::clamp<std::size_t>(std::size_t(above - curve.arcLength.begin()), 1,
                                curve.points.size() - 1) - 1;
    return std::uint32_t(curves.findEdge(curve.points[i], curve.points[i + 1])
                         - curves.edges.data());
}

/// The patches that have sample @a s, ascending.
std::pair<const std::uint32_t*, const std::uint32_t*>
patchesAt(const FeatureCurves& curves, std::uint32_t s)
{
    if (s < curves.junctions.size()) {
        const std::uint32_t* first = curves.junctionPatches.data();
        return {first + curves.junctionPatchStart[s], first + curves.junctionPatchStart[s + 1]};
    }
    const std::vector<std::uint32_t>& p = curves.curves[curves.sampleCurves[s]].patches;
    return {p.data(), p.data() + p.size()};
}

/// Where patch @a p lies seen from inner sample @a s, @a p being on its curve.
openvdb::Vec3d
sampleSide(const FeatureCurves& curves, std::uint32_t s, std::uint32_t p)
{
    const std::vector<std::uint32_t>& patches = curves.curves[curves.sampleCurves[s]].patches;
    const std::size_t j =
        std::size_t(std::lower_bound(patches.begin(), patches.end(), p) - patches.begin());
    const std::size_t inner = s - curves.junctions.size();
    return openvdb::Vec3d(curves.sampleSides[curves.sampleSideStart[inner] + j]);
}

} // namespace


void
measureCurveSides(FeatureCurves& curves, const InterfaceMesh& mesh, bool threaded)
{
    const std::vector<EdgeSide> sides = edgeSides(curves, mesh, threaded);
    const std::size_t junctionCount = curves.junctions.size();
    const std::size_t innerCount = curves.samplePoints.size() - junctionCount;
    curves.sampleSideStart.assign(innerCount + 1, 0);
    for (std::size_t i = 0; i < innerCount; ++i) {
        const std::uint32_t c = curves.sampleCurves[junctionCount + i];
        curves.sampleSideStart[i + 1] =
            curves.sampleSideStart[i] + std::uint32_t(curves.curves[c].patches.size());
    }
    curves.sampleSides.assign(curves.sampleSideStart.back(), openvdb::Vec3f(0.0f));
    forEachRange(curves.curves.size(), 1, threaded, [&](std::size_t begin, std::size_t end) {
        for (std::size_t c = begin; c < end; ++c) {
            const FeatureCurve& curve = curves.curves[c];
            for (std::size_t k = 1; k + 1 < curve.samples.size(); ++k) {
                const std::uint32_t e = edgeAt(curves, curve, curve.sampleArcLength[k]);
                const std::size_t start = curves.sampleSideStart[curve.samples[k] - junctionCount];
                for (std::size_t j = 0; j < curve.patches.size(); ++j) {
                    curves.sampleSides[start + j] =
                        openvdb::Vec3f(sideOf(curves, mesh, sides, e, curve.patches[j]));
                }
            }
        }
    });

    std::vector<std::pair<std::uint32_t, std::uint32_t>> atJunction; // (junction, patch)
    for (const FeatureCurve& curve : curves.curves) {
        for (const std::uint32_t p : curve.patches) {
            atJunction.emplace_back(curve.samples.front(), p);
            atJunction.emplace_back(curve.samples.back(), p);
        }
    }
    std::sort(atJunction.begin(), atJunction.end());
    atJunction.erase(std::unique(atJunction.begin(), atJunction.end()), atJunction.end());
    curves.junctionPatches.clear();
    curves.junctionPatchStart.assign(junctionCount + 1, 0);
    for (const auto& [j, p] : atJunction) {
        curves.junctionPatches.push_back(p);
        ++curves.junctionPatchStart[j + 1];
    }
    for (std::size_t j = 0; j < junctionCount; ++j) {
        curves.junctionPatchStart[j + 1] += curves.junctionPatchStart[j];
    }
}


std::uint32_t
chordOwner(const FeatureCurves& curves, std::uint32_t u, std::uint32_t v)
{
    const std::size_t junctionCount = curves.junctions.size();
    if (u < junctionCount && v < junctionCount) return FeatureCurves::NO_PATCH;
    openvdb::Vec3d uv = curves.samplePoints[v] - curves.samplePoints[u];
    uv.normalize();
    const auto [a, aEnd] = patchesAt(curves, u);
    const auto [b, bEnd] = patchesAt(curves, v);
    std::uint32_t best = FeatureCurves::NO_PATCH;
    double bestScore = 0.0;
    for (auto i = a, j = b; i != aEnd && j != bEnd;) {
        if (*i < *j) {
            ++i;
        } else if (*j < *i) {
            ++j;
        } else {
            double score = 0.0;
            if (u >= junctionCount) score += sampleSide(curves, u, *i).dot(uv);
            if (v >= junctionCount) score -= sampleSide(curves, v, *i).dot(uv);
            if (best == FeatureCurves::NO_PATCH || score > bestScore) {
                best = *i;
                bestScore = score;
            }
            ++i;
            ++j;
        }
    }
    return best;
}

} // namespace vdbi
