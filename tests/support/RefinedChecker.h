// SPDX-License-Identifier: Apache-2.0
/// @file support/RefinedChecker.h
/// @brief The independent manifold checker on the fine grid, and a distance check, for the
/// output of the repair (ALGORITHM.md §3) or any other fine label function.
/// @details Nothing here uses the library's critical-element code. The test at a fine grid
/// point p is the definition itself: for every label L, the faces of the boundary of V_L that
/// contain p, seen from p, must form one cycle (the link of p in the surface is a circle).
/// Take the 2x2x2 block of fine voxels around p (p-1..p). Each of its 12 inner faces
/// contains p; it lies in the boundary of V_L when exactly one of its two voxels is L. Such a
/// face spans two of the 6 axis directions at p (the grid edges leaving p), so it is an edge
/// of a graph on those 6 nodes. p is manifold for L iff the graph is empty or exactly one
/// cycle: every node has degree 0 or 2 and the used nodes are connected.

#pragma once

#include <vdbi/RefinedLabels.h>
#include <vdbi/Types.h>

#include <openvdb/openvdb.h>

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace vdbi_test {

/// The label of fine voxel f.
using FineLabelFn = std::function<vdbi::Label(const openvdb::Coord&)>;

/// @brief The fine labels of a dense box, and a constant label outside it.
struct DenseFineLabels
{
    openvdb::Coord origin;          ///< first fine voxel of the box
    openvdb::Coord dims;            ///< box size per axis
    std::vector<vdbi::Label> labels; ///< x fastest
    vdbi::Label outside = 0;        ///< the label of every fine voxel outside the box

    vdbi::Label operator()(const openvdb::Coord& f) const
    {
        const openvdb::Coord d = f - origin;
        if (d.x() < 0 || d.y() < 0 || d.z() < 0 || d.x() >= dims.x() || d.y() >= dims.y()
            || d.z() >= dims.z()) {
            return outside;
        }
        return labels[std::size_t(d.x())
            + std::size_t(dims.x()) * (std::size_t(d.y()) + std::size_t(dims.y()) * d.z())];
    }
};

/// @brief Manifoldness of one label at one point, from its block mask.
/// @param mask  bit d (d = dx + 2dy + 4dz) set when fine voxel p - 1 + (dx,dy,dz) is L
/// @details Evaluated by the cycle test of the file comment (not by the §2 pattern rules).
bool isManifoldMask(std::uint8_t mask);

/// @brief 4 x the contribution of point p to the Euler characteristic of the boundary
/// surface of V_L: 4 [p on the surface] - 2 (surface edges at p) + (surface faces at p).
/// @details Every cell of the surface has 2^k corners, so summing cell / 2^k over the
/// corners gives V - E + F. Points in the interior of a voxel or a flat face contribute 0,
/// and so do points inside a straight edge: only the visited points matter.
int boundaryEulerTimes4(std::uint8_t mask);

/// One (point, label) at which the boundary of the label's set is not a 2-manifold.
struct ManifoldFailure
{
    openvdb::Coord point;    ///< fine grid point
    vdbi::Label label = 0;
    std::uint8_t mask = 0;   ///< the label's block mask at the point (see isManifoldMask)
};

/// What the manifold checker found.
struct ManifoldReport
{
    std::size_t pointsChecked = 0;
    std::size_t failureCount = 0;             ///< failing (point, label) pairs
    std::vector<ManifoldFailure> failures;    ///< the first few, by (point, label)
    /// RefinedLabels only: active fine voxels outside the subdivided coarse voxels (they
    /// would break the choice of points; they are checked all the same).
    std::size_t fineOutsideSubdivided = 0;
    /// 4 x Euler characteristic of the boundary surface of every label's fine set.
    std::map<vdbi::Label, std::int64_t> eulerTimes4;

    bool ok() const { return failureCount == 0 && fineOutsideSubdivided == 0; }
    /// Euler characteristic of the boundary of V_label (0 if the label never occurs).
    std::int64_t euler(vdbi::Label label) const;
    /// "N points, M failures: (x,y,z) label L, ..."
    std::string summary() const;
};

/// @brief Calls @a f(bbox, label) for every stored value of @a grid that is not the
/// background: every leaf voxel (active or not: a voxel's label is its value) and every active
/// tile. Inactive tiles are taken as background (scanning them costs a pass over every
/// internal-node slot; the library's inputs and all test grids have none).
void forEachStoredLabel(const openvdb::Int32Grid& grid,
                        const std::function<void(const openvdb::CoordBBox&, vdbi::Label)>& f);

/// @brief The fine grid points that must be visited to decide manifoldness everywhere.
/// @details (1) every fine point in the closure of a subdivided coarse voxel c (s*c .. s*c+s
/// per axis); (2) for the rest, every coarse grid point v of a coarse voxel whose label is not
/// the background, as fine point s*v, and one interior fine point s*v + e_axis of each coarse
/// edge leaving such a v.
/// Why that is enough: a fine point p that is not in the closure of any subdivided voxel sees
/// only fine voxels of non-subdivided coarse voxels, whose fine labels are their coarse labels.
/// Its block is then the block of the coarse element p lies in, stretched: inside a coarse
/// voxel it is uniform; inside a coarse face it is two uniform halves, whose boundary at p is
/// one 4-cycle (or empty); inside a coarse edge it is the edge's 4 voxels, the same at every
/// interior point of that edge, so one interior point decides them all; at a coarse grid point
/// it is that point's coarse block. Faces and voxel interiors can never be non-manifold, and
/// coarse elements whose voxels are all background are uniform.
/// @param coarse      the coarse labels (its background is the label of everything unstored)
/// @param subdivided  the subdivided coarse voxels
/// @param s           the subdivision factor (1: the fine grid is the coarse grid)
openvdb::MaskGrid::Ptr checkPoints(const openvdb::Int32Grid& coarse,
                                   const openvdb::MaskGrid& subdivided, int s);

/// Options of the checkers.
struct CheckOptions
{
    bool threaded = true;        ///< only for RefinedLabels (a FineLabelFn may not be thread-safe)
    std::size_t maxFailures = 16; ///< failures kept in the report
    bool computeEuler = true;
};

/// @brief Checks @a labels at every point of checkPoints(), its coarse grid and its
/// subdivided voxels together with the coarse voxels of all active fine voxels.
ManifoldReport checkManifold(const vdbi::RefinedLabels& labels,
                             const CheckOptions& options = CheckOptions());

/// @brief Checks an arbitrary fine label function at @a points (serially).
ManifoldReport checkManifold(const FineLabelFn& fineLabel, const openvdb::MaskGrid& points,
                             const CheckOptions& options = CheckOptions());

/// @brief Checks dense fine labels at @a points (serially; faster than a FineLabelFn).
ManifoldReport checkManifold(const DenseFineLabels& fineLabels,
                             const openvdb::MaskGrid& points,
                             const CheckOptions& options = CheckOptions());

/// What the distance check found.
struct DistanceReport
{
    std::size_t relabelled = 0;     ///< fine voxels whose label differs from their coarse voxel's
    /// Max over them of the Chebyshev distance, in coarse voxels, between the closed fine cube
    /// and the nearest closed coarse input voxel of its new label (2 coarse voxels when there is
    /// none within 2).
    double maxDistance = 0;
    /// The same with the farthest point of the fine cube: the largest distance of any point of
    /// a relabelled subvoxel to the nearest single input voxel of its new label.
    double maxFarDistance = 0;
    std::size_t beyondBound = 0;    ///< relabelled voxels with a distance above the bound
    std::vector<openvdb::Coord> examples; ///< the first few of those (fine voxels)

    bool ok() const { return beyondBound == 0; }
};

/// @brief Every relabelled subvoxel must lie within @a bound (coarse units, Chebyshev,
/// closed fine cube to closed coarse cube) of a coarse input voxel of its new label
/// (ALGORITHM.md §3: 2/5 without constraints).
DistanceReport checkDistance(const vdbi::RefinedLabels& labels, double bound = 0.4);

/// @brief The same for a fine label function: examines every fine voxel of the subdivided
/// coarse voxels; @a coarse gives the input labels.
DistanceReport checkDistance(const FineLabelFn& fineLabel, const openvdb::Int32Grid& coarse,
                             const openvdb::MaskGrid& subdivided, int s, double bound = 0.4);

/// @brief Volume of every non-background label of @a labels, in fine voxels (s^3 per coarse
/// voxel): the volume that a closed surface around the label must enclose.
std::map<vdbi::Label, std::int64_t> refinedVolumes(const vdbi::RefinedLabels& labels);

} // namespace vdbi_test
