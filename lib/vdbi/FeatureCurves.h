// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/FeatureCurves.h
/// @brief The feature curves of an interface mesh (where 3 or 4 interface faces meet), their
/// junctions, and one smoothed, resampled polyline per curve shared by every patch on it.

#ifndef VDBI_FEATURE_CURVES_HAS_BEEN_INCLUDED
#define VDBI_FEATURE_CURVES_HAS_BEEN_INCLUDED

#include <vdbi/InterfaceMesh.h>

#include <openvdb/Types.h>

#include <cstdint>
#include <vector>

namespace vdbi {

/// @brief A maximal chain of feature edges between two junctions.
/// @details Along a curve the set of patches that have it as boundary does not change. A
/// closed loop without a junction starts and ends at its smallest point index, which is then
/// treated as a junction (a fixed point).
struct FeatureCurve
{
    /// InterfaceMesh point indices p0..pm (m >= 1); a closed curve has p0 == pm.
    std::vector<std::uint32_t> points;
    /// Indices into InterfaceMesh::patches of the patches bounded by this curve, ascending.
    std::vector<std::uint32_t> patches;
    /// Smoothed position of every point (the two ends keep their extracted positions).
    std::vector<openvdb::Vec3d> smoothed;
    /// Arc length of every point along the smoothed polyline (0 at p0).
    std::vector<double> arcLength;
    /// Global sample index (into FeatureCurves::samplePoints) of the resampled polyline's
    /// n + 1 points; the two ends are the ids of the junctions at p0 and pm.
    std::vector<std::uint32_t> samples;
    /// Arc length of every sample along the smoothed polyline, ascending.
    std::vector<double> sampleArcLength;

    bool isClosed() const { return points.front() == points.back(); }
    double length() const { return arcLength.empty() ? 0.0 : arcLength.back(); }
};

/// One feature edge: the undirected point pair, and where it lies on its curve.
struct FeatureEdge
{
    std::uint64_t key = 0;       ///< min(u, v) << 32 | max(u, v)
    std::uint32_t curve = 0;     ///< index into FeatureCurves::curves
    std::uint32_t segment = 0;   ///< the edge joins curve.points[segment] and [segment + 1]
};

/// @brief The feature curve network of an interface mesh.
/// @details Samples are numbered junctions first (in the order of @c junctions), then the
/// inner samples of every curve, curve by curve. Every patch along a curve uses the same
/// samples, so patches keep sharing their boundary vertices exactly after remeshing.
struct FeatureCurves
{
    /// InterfaceMesh point index of every junction, ascending; junction j is sample j.
    std::vector<std::uint32_t> junctions;
    std::vector<FeatureCurve> curves;
    /// Every feature edge, sorted by key.
    std::vector<FeatureEdge> edges;
    /// Position of every sample: the junctions at their extracted positions, then the inner
    /// samples on the smoothed curves. Empty until resampleFeatureCurves().
    std::vector<openvdb::Vec3d> samplePoints;
    /// Curve of every sample: the index into @c curves of an inner sample's curve, NO_CURVE
    /// for a junction. Empty until resampleFeatureCurves().
    std::vector<std::uint32_t> sampleCurves;
    static constexpr std::uint32_t NO_CURVE = ~std::uint32_t(0);
    /// @brief Where every patch of its curve lies seen from an inner sample: the unit
    /// direction from the extracted curve there into the patch's triangle, across the curve
    /// (zero if unknown). Inner sample s's are sampleSides[sampleSideStart[s - J] + j] for
    /// the j-th patch of its curve, J the number of junctions. Empty until
    /// measureCurveSides() (ChordOwners.h).
    std::vector<openvdb::Vec3f> sampleSides;
    std::vector<std::uint32_t> sampleSideStart;
    /// The patches at every junction (of the curves that end there), ascending: those of
    /// junction j are junctionPatches[junctionPatchStart[j] .. junctionPatchStart[j + 1]).
    std::vector<std::uint32_t> junctionPatches, junctionPatchStart;
    static constexpr std::uint32_t NO_PATCH = ~std::uint32_t(0);

    static std::uint64_t edgeKey(std::uint32_t u, std::uint32_t v)
    {
        return u < v ? (std::uint64_t(u) << 32 | v) : (std::uint64_t(v) << 32 | u);
    }
    /// The feature edge between points @a u and @a v, or null if there is none.
    const FeatureEdge* findEdge(std::uint32_t u, std::uint32_t v) const;
    /// Sample id of the junction at point @a p, or -1 if @a p is no junction.
    std::int64_t junctionSample(std::uint32_t p) const;
};

/// @brief Finds the feature edges (boundary edges of some patch), the junctions (points
/// whose number of feature edges is not 2, or where the set of patches along the feature
/// edges changes) and the curves between them (ALGORITHM.md §4, §5).
/// @details The result depends only on the mesh, not on the number of threads.
/// @throw vdbi::TopologyError if a patch edge lies in more than two of its triangles
FeatureCurves findFeatureCurves(const InterfaceMesh& mesh, bool threaded = true);

/// @brief Smooths every curve along itself, its two ends fixed.
/// @details Taubin smoothing (a shrinking and an inflating Laplacian step per iteration);
/// after every step a point outside the axis-aligned ellipsoid with semi-axes
/// @a maxDisplacement (world units per axis) around its extracted position is pulled back
/// onto it, so the curve stays that close to the voxel staircase it came from. Fills
/// FeatureCurve::smoothed and arcLength.
void smoothFeatureCurves(FeatureCurves& curves, const InterfaceMesh& mesh, int iterations,
                         const openvdb::Vec3d& maxDisplacement, bool threaded = true);

/// @brief Resamples every smoothed curve once, about @a targetLength apart.
/// @details A curve of length L gets n = max(1, round(L / targetLength)) segments, uniform in
/// arc length, at least 3 for a closed curve and at least 2 when another curve joins the same
/// two junctions (so no two curves share a segment, no patch boundary is a 2-gon, and a
/// single-segment curve never coincides with an extracted edge of another curve). Where a
/// chord of those would pass farther than @a maxDeviation from the smoothed curve (a tight
/// bend cut short), the samples are placed instead where every chord stays within that
/// bound and the fewest chords are shorter than half the target or longer than 1.5 times it
/// (a cheapest path over places along the curve). Fills FeatureCurve::samples,
/// sampleArcLength and FeatureCurves::samplePoints, sampleCurves.
/// @pre smoothFeatureCurves() ran
void resampleFeatureCurves(FeatureCurves& curves, double targetLength, double maxDeviation,
                           bool threaded = true);

} // namespace vdbi

#endif // VDBI_FEATURE_CURVES_HAS_BEEN_INCLUDED
