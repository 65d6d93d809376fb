// SPDX-License-Identifier: Apache-2.0

#include <vdbi/FeatureCurves.h>

#include <vdbi/Exceptions.h>
#include <vdbi/ParallelRanges.h>
#include <vdbi/ReferenceSurface.h>

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <utility>

namespace vdbi {

namespace {

template<typename Body>
void
forEachIndex(std::size_t count, bool threaded, const Body& body)
{
    forEachRange(count, 1, threaded, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) body(i);
    });
}

/// Undirected edges of one patch that lie in exactly one of its triangles, sorted.
std::vector<std::uint64_t>
patchBoundaryEdges(const InterfaceMesh& mesh, std::size_t patchIndex, bool threaded)
{
    const InterfacePatch& patch = mesh.patches[patchIndex];
    std::vector<std::uint64_t> keys;
    keys.reserve(3 * patch.triangleCount);
    const std::size_t end = patch.firstTriangle + patch.triangleCount;
    for (std::size_t t = patch.firstTriangle; t < end; ++t) {
        const openvdb::Vec3I& tri = mesh.triangles[t];
        for (int i = 0; i < 3; ++i) {
            keys.push_back(FeatureCurves::edgeKey(tri[i], tri[(i + 1) % 3]));
        }
    }
    // In parallel too: the largest patch (a third of frog's triangles) would sort alone.
    if (threaded) tbb::parallel_sort(keys.begin(), keys.end());
    else std::sort(keys.begin(), keys.end());
    std::vector<std::uint64_t> boundary;
    for (std::size_t i = 0; i < keys.size();) {
        std::size_t j = i + 1;
        while (j < keys.size() && keys[j] == keys[i]) ++j;
        if (j - i == 1) {
            boundary.push_back(keys[i]);
        } else if (j - i > 2) {
            std::ostringstream os;
            os << "patch (" << patch.a << ", " << patch.b << "): edge (" << (keys[i] >> 32)
               << ", " << (keys[i] & 0xffffffffu) << ") lies in " << (j - i) << " triangles";
            throw TopologyError(os.str());
        }
        i = j;
    }
    return boundary;
}

/// The feature graph: feature edges with their patch sets, and the edges around every point.
struct FeatureGraph
{
    std::vector<std::uint64_t> edgeKeys;          // sorted
    std::vector<std::size_t> edgePatchStart;      // CSR into edgePatches
    std::vector<std::uint32_t> edgePatches;
    std::vector<std::uint32_t> vertices;          // point indices, sorted
    std::vector<std::size_t> vertexEdgeStart;     // CSR into vertexEdges
    std::vector<std::uint32_t> vertexEdges;       // edge indices, by ascending other end

    std::uint32_t vertexIndex(std::uint32_t point) const
    {
        return std::uint32_t(std::lower_bound(vertices.begin(), vertices.end(), point)
                             - vertices.begin());
    }
    std::uint32_t otherEnd(std::uint32_t edge, std::uint32_t point) const
    {
        const std::uint32_t u = std::uint32_t(edgeKeys[edge] >> 32);
        const std::uint32_t v = std::uint32_t(edgeKeys[edge] & 0xffffffffu);
        return u == point ? v : u;
    }
    bool samePatches(std::uint32_t e, std::uint32_t f) const
    {
        return std::equal(edgePatches.begin() + edgePatchStart[e],
                          edgePatches.begin() + edgePatchStart[e + 1],
                          edgePatches.begin() + edgePatchStart[f],
                          edgePatches.begin() + edgePatchStart[f + 1]);
    }
};

FeatureGraph
buildFeatureGraph(const InterfaceMesh& mesh, bool threaded)
{
    std::vector<std::vector<std::uint64_t>> perPatch(mesh.patches.size());
    forEachIndex(mesh.patches.size(), threaded,
                 [&](std::size_t p) { perPatch[p] = patchBoundaryEdges(mesh, p, threaded); });

    // (edge key, patch) pairs are unique, so the sorted order does not depend on the sort.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> pairs;
    std::size_t total = 0;
    for (const auto& v : perPatch) total += v.size();
    pairs.reserve(total);
    for (std::size_t p = 0; p < perPatch.size(); ++p) {
        for (std::uint64_t key : perPatch[p]) pairs.emplace_back(key, std::uint32_t(p));
        std::vector<std::uint64_t>().swap(perPatch[p]);
    }
    if (threaded) tbb::parallel_sort(pairs.begin(), pairs.end());
    else std::sort(pairs.begin(), pairs.end());

    FeatureGraph g;
    g.edgePatches.reserve(pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        if (i == 0 || pairs[i].first != pairs[i - 1].first) {
            g.edgeKeys.push_back(pairs[i].first);
            g.edgePatchStart.push_back(g.edgePatches.size());
        }
        g.edgePatches.push_back(pairs[i].second);
    }
    g.edgePatchStart.push_back(g.edgePatches.size());

    g.vertices.reserve(2 * g.edgeKeys.size());
    for (std::uint64_t key : g.edgeKeys) {
        g.vertices.push_back(std::uint32_t(key >> 32));
        g.vertices.push_back(std::uint32_t(key & 0xffffffffu));
    }
    std::sort(g.vertices.begin(), g.vertices.end());
    g.vertices.erase(std::unique(g.vertices.begin(), g.vertices.end()), g.vertices.end());

    std::vector<std::size_t> count(g.vertices.size() + 1, 0);
    for (std::uint64_t key : g.edgeKeys) {
        ++count[g.vertexIndex(std::uint32_t(key >> 32)) + 1];
        ++count[g.vertexIndex(std::uint32_t(key & 0xffffffffu)) + 1];
    }
    for (std::size_t i = 1; i < count.size(); ++i) count[i] += count[i - 1];
    g.vertexEdgeStart = count;
    g.vertexEdges.resize(count.back());
    for (std::uint32_t e = 0; e < g.edgeKeys.size(); ++e) {
        g.vertexEdges[count[g.vertexIndex(std::uint32_t(g.edgeKeys[e] >> 32))]++] = e;
        g.vertexEdges[count[g.vertexIndex(std::uint32_t(g.edgeKeys[e] & 0xffffffffu))]++] = e;
    }
    for (std::size_t v = 0; v < g.vertices.size(); ++v) {
        const std::uint32_t point = g.vertices[v];
        std::sort(g.vertexEdges.begin() + g.vertexEdgeStart[v],
                  g.vertexEdges.begin() + g.vertexEdgeStart[v + 1],
                  [&](std::uint32_t e, std::uint32_t f) {
                      return g.otherEnd(e, point) < g.otherEnd(f, point);
                  });
    }
    return g;
}

/// Linear interpolation on a polyline at arc length @a t, starting the search at @a segment.
openvdb::Vec3d
pointAt(const FeatureCurve& curve, double t, std::size_t& segment)
{
    const std::size_t last = curve.points.size() - 2;
    while (segment < last && curve.arcLength[segment + 1] < t) ++segment;
    const double a = curve.arcLength[segment], b = curve.arcLength[segment + 1];
    const double w = b > a ? std::clamp((t - a) / (b - a), 0.0, 1.0) : 0.0;
    return curve.smoothed[segment] * (1.0 - w) + curve.smoothed[segment + 1] * w;
}

/// Distance from @a p to the segment [@a a, @a b].
double
distanceToSegment(const openvdb::Vec3d& p, const openvdb::Vec3d& a, const openvdb::Vec3d& b)
{
    const openvdb::Vec3d ab = b - a;
    const double len2 = ab.lengthSqr();
    const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (p - (a + ab * t)).length();
}

/// Does every point of the smoothed curve lie within @a maxDeviation of the chord between
/// the samples at arc lengths @a arcs around it?
bool
chordsFollow(const FeatureCurve& curve, const std::vector<double>& arcs, double maxDeviation)
{
    std::size_t segment = 0, i = 1;
    openvdb::Vec3d a = curve.smoothed.front();
    for (std::size_t k = 1; k < arcs.size(); ++k) {
        const openvdb::Vec3d b = pointAt(curve, arcs[k], segment);
        for (; i + 1 < curve.smoothed.size() && curve.arcLength[i] < arcs[k]; ++i) {
            if (distanceToSegment(curve.smoothed[i], a, b) > maxDeviation) return false;
        }
        a = b;
    }
    return true;
}

/// @brief Indices of the smoothed points that a Douglas-Peucker simplification of the curve
/// with tolerance @a maxDeviation keeps, ascending, the two ends included: its corners.
std::vector<std::size_t>
cornerPoints(const FeatureCurve& curve, double maxDeviation)
{
    const std::vector<openvdb::Vec3d>& p = curve.smoothed;
    std::vector<char> kept(p.size(), 0);
    kept.front() = kept.back() = 1;
    std::vector<std::pair<std::size_t, std::size_t>> stack{{0, p.size() - 1}};
    while (!stack.empty()) {
        const auto [first, last] = stack.back();
        stack.pop_back();
        std::size_t farthest = first;
        double worst = maxDeviation;
        for (std::size_t i = first + 1; i < last; ++i) {
            const double d = distanceToSegment(p[i], p[first], p[last]);
            if (d > worst) {
                worst = d;
                farthest = i;
            }
        }
        if (farthest == first) continue;
        kept[farthest] = 1;
        stack.push_back({first, farthest});
        stack.push_back({farthest, last});
    }
    std::vector<std::size_t> corners;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (kept[i]) corners.push_back(i);
    }
    return corners;
}

/// @brief Arc lengths of the samples of @a curve, from 0 to its length: uniform, about
/// @a targetLength apart, where the chords between them stay within @a maxDeviation of the
/// curve; else uniform between the curve's corners (cornerPoints()), so that a tight bend (the
/// end of a strip one voxel wide, the corner of a box) keeps a sample instead of being cut.
/// At least @a minSegments segments.
std::vector<double>
sampleArcLengths(const FeatureCurve& curve, double targetLength, std::size_t minSegments,
                 double maxDeviation)
{
    auto segmentsFor = [&](double length) {
        return std::size_t(std::max(1L, std::lround(length / targetLength)));
    };
    std::vector<double> arcs{0.0};
    auto appendUniform = [&](double from, double to, std::size_t n) {
        for (std::size_t k = 1; k <= n; ++k) {
            arcs.push_back(from + (to - from) * double(k) / double(n));
        }
    };
    const double length = curve.length();
    appendUniform(0.0, length, std::max(minSegments, segmentsFor(length)));
    if (chordsFollow(curve, arcs, maxDeviation)) return arcs;

    arcs.assign(1, 0.0);
    const std::vector<std::size_t> corners = cornerPoints(curve, maxDeviation);
    for (std::size_t j = 1; j < corners.size(); ++j) {
        const double from = curve.arcLength[corners[j - 1]], to = curve.arcLength[corners[j]];
        if (to > from) appendUniform(from, to, segmentsFor(to - from));
    }
    arcs.back() = length;
    // Too few segments (a short closed curve): halve the longest until there are enough.
    while (arcs.size() < minSegments + 1) {
        std::size_t longest = 1;
        for (std::size_t k = 2; k < arcs.size(); ++k) {
            if (arcs[k] - arcs[k - 1] > arcs[longest] - arcs[longest - 1]) longest = k;
        }
        arcs.insert(arcs.begin() + std::ptrdiff_t(longest),
                    0.5 * (arcs[longest - 1] + arcs[longest]));
    }
    return arcs;
}

} // namespace


const FeatureEdge*
FeatureCurves::findEdge(std::uint32_t u, std::uint32_t v) const
{
    const std::uint64_t key = edgeKey(u, v);
    auto it = std::lower_bound(edges.begin(), edges.end(), key,
        [](const FeatureEdge& e, std::uint64_t k) { return e.key < k; });
    return (it != edges.end() && it->key == key) ? &*it : nullptr;
}


std::int64_t
FeatureCurves::junctionSample(std::uint32_t p) const
{
    auto it = std::lower_bound(junctions.begin(), junctions.end(), p);
    return (it != junctions.end() && *it == p) ? std::int64_t(it - junctions.begin()) : -1;
}


FeatureCurves
findFeatureCurves(const InterfaceMesh& mesh, bool threaded)
{
    const FeatureGraph g = buildFeatureGraph(mesh, threaded);
    const std::size_t nv = g.vertices.size();

    std::vector<char> isJunction(nv, 0);
    for (std::size_t v = 0; v < nv; ++v) {
        const std::size_t begin = g.vertexEdgeStart[v], end = g.vertexEdgeStart[v + 1];
        isJunction[v] = (end - begin != 2)
            || !g.samePatches(g.vertexEdges[begin], g.vertexEdges[begin + 1]);
    }

    FeatureCurves result;
    result.edges.resize(g.edgeKeys.size());
    std::vector<char> visited(g.edgeKeys.size(), 0);

    // Walks from vertex v along edge e until a junction (or back to v on a closed loop).
    auto trace = [&](std::uint32_t v, std::uint32_t e) {
        FeatureCurve curve;
        curve.patches.assign(g.edgePatches.begin() + g.edgePatchStart[e],
                             g.edgePatches.begin() + g.edgePatchStart[e + 1]);
        std::uint32_t point = g.vertices[v];
        curve.points.push_back(point);
        const std::uint32_t curveIndex = std::uint32_t(result.curves.size());
        while (true) {
            visited[e] = 1;
            result.edges[e] = FeatureEdge{g.edgeKeys[e], curveIndex,
                                          std::uint32_t(curve.points.size() - 1)};
            point = g.otherEnd(e, point);
            curve.points.push_back(point);
            const std::uint32_t w = g.vertexIndex(point);
            if (isJunction[w]) break;
            // Not a junction: exactly two feature edges, continue on the other one.
            const std::uint32_t e0 = g.vertexEdges[g.vertexEdgeStart[w]];
            const std::uint32_t e1 = g.vertexEdges[g.vertexEdgeStart[w] + 1];
            e = (e0 == e) ? e1 : e0;
        }
        result.curves.push_back(std::move(curve));
    };

    for (std::uint32_t v = 0; v < nv; ++v) {
        if (!isJunction[v]) continue;
        for (std::size_t i = g.vertexEdgeStart[v]; i < g.vertexEdgeStart[v + 1]; ++i) {
            if (!visited[g.vertexEdges[i]]) trace(v, g.vertexEdges[i]);
        }
    }
    // Closed loops without a junction: start at the smallest point (the first one met in
    // ascending order), walk towards its smaller neighbour; the start becomes a junction.
    for (std::uint32_t v = 0; v < nv; ++v) {
        const std::uint32_t e = g.vertexEdges[g.vertexEdgeStart[v]];
        if (visited[e]) continue;
        isJunction[v] = 1;
        trace(v, e);
    }

    for (std::uint32_t v = 0; v < nv; ++v) {
        if (isJunction[v]) result.junctions.push_back(g.vertices[v]);
    }
    return result;
}


void
smoothFeatureCurves(FeatureCurves& curves, const InterfaceMesh& mesh, int iterations,
                    const openvdb::Vec3d& maxDisplacement, bool threaded)
{
    // Taubin's lambda/mu pair: the second step undoes the shrinking of the first.
    constexpr double LAMBDA = 0.5, MU = -0.53;
    forEachIndex(curves.curves.size(), threaded, [&](std::size_t c) {
        FeatureCurve& curve = curves.curves[c];
        const std::size_t n = curve.points.size();
        std::vector<openvdb::Vec3d> original(n), previous(n);
        for (std::size_t i = 0; i < n; ++i) original[i] = mesh.points[curve.points[i]];
        curve.smoothed = original;
        auto step = [&](double factor) {
            previous = curve.smoothed;
            for (std::size_t i = 1; i + 1 < n; ++i) {
                const openvdb::Vec3d mid = (previous[i - 1] + previous[i + 1]) * 0.5;
                curve.smoothed[i] = clampDisplacement(previous[i] + (mid - previous[i]) * factor,
                                                      original[i], maxDisplacement);
            }
        };
        for (int it = 0; it < iterations; ++it) {
            step(LAMBDA);
            step(MU);
        }
        curve.arcLength.assign(n, 0.0);
        for (std::size_t i = 1; i < n; ++i) {
            curve.arcLength[i] = curve.arcLength[i - 1]
                + (curve.smoothed[i] - curve.smoothed[i - 1]).length();
        }
    });
}


void
resampleFeatureCurves(FeatureCurves& curves, double targetLength, double maxDeviation,
                      bool threaded)
{
    const std::size_t nc = curves.curves.size();
    // Curves that join the same two junctions: none of them may be a single segment, or two
    // curves (or a curve and an extracted edge) would share it.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> curvesWithEnds;
    auto endsOf = [](const FeatureCurve& curve) {
        const std::uint32_t u = curve.points.front(), v = curve.points.back();
        return std::make_pair(std::min(u, v), std::max(u, v));
    };
    for (const FeatureCurve& curve : curves.curves) ++curvesWithEnds[endsOf(curve)];
    forEachIndex(nc, threaded, [&](std::size_t c) {
        FeatureCurve& curve = curves.curves[c];
        const std::size_t minSegments =
            curve.isClosed() ? 3 : curvesWithEnds.at(endsOf(curve)) > 1 ? 2 : 1;
        curve.sampleArcLength = sampleArcLengths(curve, targetLength, minSegments, maxDeviation);
    });

    std::vector<std::uint32_t> firstInner(nc + 1);
    firstInner[0] = std::uint32_t(curves.junctions.size());
    for (std::size_t c = 0; c < nc; ++c) {
        firstInner[c + 1] =
            firstInner[c] + std::uint32_t(curves.curves[c].sampleArcLength.size()) - 2;
    }
    curves.samplePoints.resize(firstInner[nc]);
    curves.sampleCurves.assign(firstInner[nc], FeatureCurves::NO_CURVE);

    forEachIndex(nc, threaded, [&](std::size_t c) {
        FeatureCurve& curve = curves.curves[c];
        const std::size_t n = curve.sampleArcLength.size() - 1;
        curve.samples.resize(n + 1);
        curve.samples[0] = std::uint32_t(curves.junctionSample(curve.points.front()));
        curve.samples[n] = std::uint32_t(curves.junctionSample(curve.points.back()));
        std::size_t segment = 0;
        for (std::size_t k = 1; k < n; ++k) {
            curve.samples[k] = firstInner[c] + std::uint32_t(k) - 1;
            curves.sampleCurves[curve.samples[k]] = std::uint32_t(c);
            curves.samplePoints[curve.samples[k]] =
                pointAt(curve, curve.sampleArcLength[k], segment);
        }
    });
    // Junctions keep their extracted positions (the ends of every smoothed curve).
    for (const FeatureCurve& curve : curves.curves) {
        curves.samplePoints[curve.samples.front()] = curve.smoothed.front();
        curves.samplePoints[curve.samples.back()] = curve.smoothed.back();
    }
}

} // namespace vdbi
