// SPDX-License-Identifier: Apache-2.0

#include <vdbi/FeatureCurves.h>

#include <vdbi/Exceptions.h>
#include <vdbi/ParallelRanges.h>
#include <vdbi/RadixSort.h>
#include <vdbi/ReferenceSurface.h>

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
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
    sortByPackedKey<2, 32>(keys, [](std::uint64_t key) { return key; }, threaded);
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

/// @brief Arc lengths of samples of @a curve, from 0 to its length, at least @a minSegments
/// segments, every point of the curve within @a maxDeviation of the chord over it: those whose
/// chords are the fewest out of [0.5, 1.5] x @a targetLength, then the nearest to it.
/// @details The cheapest path over candidate places along the curve (every smoothed point,
/// and places an eighth of the target apart at most between them). A chord costs
/// (log of its length over the target)^2, plus OUT_OF_RANGE out of the range, plus
/// (its largest deviation over @a maxDeviation)^2: a chord that cuts a bend makes the
/// triangles along it sharper (frog at 2 voxels: 1st-percentile smallest angle 23.2 degrees
/// without that term, 23.3 with it).
std::vector<double>
bestArcLengths(const FeatureCurve& curve, double targetLength, std::size_t minSegments,
               double maxDeviation)
{
    constexpr double OUT_OF_RANGE = 4.0, CANDIDATE_STEP = 0.125;
    // No chord spans more arc than this many targets: farther, they stray from the bound.
    constexpr double LONGEST_ARC = 3.0;
    const std::vector<openvdb::Vec3d>& p = curve.smoothed;
    const std::size_t np = p.size();
    // Candidates: arc length, position, and the first smoothed point after them.
    std::vector<double> arc;
    std::vector<openvdb::Vec3d> at;
    std::vector<std::size_t> nextPoint;
    const double step = CANDIDATE_STEP * targetLength;
    for (std::size_t i = 0; i + 1 < np; ++i) {
        const double a = curve.arcLength[i], b = curve.arcLength[i + 1];
        const std::size_t parts = std::max<std::size_t>(1, std::size_t(std::ceil((b - a) / step)));
        for (std::size_t j = 0; j < parts; ++j) {
            if (j > 0 && !(b > a)) break;
            const double w = double(j) / double(parts);
            arc.push_back(a + (b - a) * w);
            at.push_back(p[i] * (1.0 - w) + p[i + 1] * w);
            nextPoint.push_back(j == 0 ? i : i + 1);
        }
    }
    arc.push_back(curve.length());
    at.push_back(p.back());
    nextPoint.push_back(np - 1);
    const std::size_t nc = arc.size();

    // cost[c * levels + s]: the cheapest samples up to candidate c with min(s, minSegments)
    // segments; from[...] the candidate and level before.
    const std::size_t levels = minSegments + 1;
    constexpr double NONE = std::numeric_limits<double>::infinity();
    std::vector<double> cost(nc * levels, NONE);
    std::vector<std::uint32_t> from(nc * levels, 0);
    cost[0] = 0.0;
    const double inverseTarget = 1.0 / targetLength;
    for (std::size_t c = 0; c + 1 < nc; ++c) {
        bool reached = false;
        for (std::size_t s = 0; s < levels; ++s) reached = reached || cost[c * levels + s] < NONE;
        if (!reached) continue;
        for (std::size_t d = c + 1; d < nc; ++d) {
            if (d > c + 1 && arc[d] - arc[c] > LONGEST_ARC * targetLength) break;
            // The smoothed points strictly between the two candidates.
            double deviation = 0.0;
            for (std::size_t i = nextPoint[c]; i < nextPoint[d] && deviation <= maxDeviation; ++i) {
                if (curve.arcLength[i] <= arc[c]) continue;
                deviation = std::max(deviation, distanceToSegment(p[i], at[c], at[d]));
            }
            if (deviation > maxDeviation) break;
            const double t = (at[d] - at[c]).length() * inverseTarget;
            const double logT = t > 0.0 ? std::log(t) : -1e3;
            const double bend = deviation / maxDeviation;
            const double chord =
                logT * logT + ((t < 0.5 || t > 1.5) ? OUT_OF_RANGE : 0.0) + bend * bend;
            for (std::size_t s = 0; s < levels; ++s) {
                const double here = cost[c * levels + s];
                if (!(here < NONE)) continue;
                const std::size_t to = d * levels + std::min(s + 1, minSegments);
                if (here + chord < cost[to]) {
                    cost[to] = here + chord;
                    from[to] = std::uint32_t(c * levels + s);
                }
            }
        }
    }
    // The cheapest end with enough segments, else with the most (split below).
    std::size_t end = (nc - 1) * levels + minSegments;
    while (!(cost[end] < NONE)) --end;
    std::vector<double> arcs;
    for (std::size_t k = end;; k = from[k]) {
        arcs.push_back(arc[k / levels]);
        if (k == 0) break;
    }
    std::reverse(arcs.begin(), arcs.end());
    arcs.back() = curve.length();
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

/// @brief Arc lengths of the samples of @a curve, from 0 to its length: uniform, about
/// @a targetLength apart (at least @a minSegments segments), where the chords between them
/// stay within @a maxDeviation of the curve; else bestArcLengths().
/// @details Where uniform chords cut a tight bend (the end of a strip one voxel wide, the
/// corner of a box), the samples used to be uniform between the curve's corners, and the
/// pieces between corners came out as short as they were: on the frog at 2 voxels, 1 062 of
/// the curves' segments were under half the target by arc length, 2 206 by chord; 1 984 by
/// chord now. bestArcLengths() for every curve would leave 1 187 (edges in range 98.16 %
/// instead of 97.98 %), but it also replaces the short chords of hairpins that uniform samples
/// follow, and the patches inside them get sharper triangles (1st-percentile smallest angle
/// 22.9 degrees instead of 23.3).
std::vector<double>
sampleArcLengths(const FeatureCurve& curve, double targetLength, std::size_t minSegments,
                 double maxDeviation)
{
    auto segmentsFor = [&](double length) {
        return std::size_t(std::max(1L, std::lround(length / targetLength)));
    };
    const double length = curve.length();
    const std::size_t n = std::max(minSegments, segmentsFor(length));
    std::vector<double> arcs;
    for (std::size_t k = 0; k <= n; ++k) arcs.push_back(length * double(k) / double(n));
    arcs.back() = length;
    if (chordsFollow(curve, arcs, maxDeviation)) return arcs;
    return bestArcLengths(curve, targetLength, minSegments, maxDeviation);
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
