// SPDX-License-Identifier: Apache-2.0
/// @file support/SeparationChecker.h
/// @brief Independent checks of a repair with separation constraints (ALGORITHM.md §2, §6):
/// the closed sets of A and B must not touch (no shared face, edge or corner), no label may be
/// non-manifold on the fine grid, and relabelled subvoxels stay close to an input voxel of
/// their new label, except the separator layer. Also seeded constraint sets for random
/// volumes, and a dense fast path for many repairs of one tiny volume (the block sweep).
/// @details The closed sets of A and B touch exactly when some fine grid point has both among
/// its 8 fine voxels (closed cubes that meet share a corner). Manifoldness is the vertex-link
/// cycle test of RefinedChecker.h; nothing here uses the library's critical-element code.

#pragma once

#include "support/RandomVolumes.h"

#include <vdbi/RefinedLabels.h>
#include <vdbi/Types.h>

#include <openvdb/openvdb.h>

#include <cstddef>
#include <vector>

namespace vdbi_test {

/// @brief Fine points at which both labels of a constraint occur, summed over constraints.
/// @details Visits the points of checkPoints(): a coarse face, edge or point where A and B
/// meet is critical, hence subdivided, so every other point sees a stretched coarse element
/// without both.
std::size_t touchingPoints(const vdbi::RefinedLabels& labels,
                           const std::vector<vdbi::SeparationConstraint>& constraints);

/// The separator labels of @a constraints (sorted, unique).
std::vector<vdbi::Label> separators(const std::vector<vdbi::SeparationConstraint>& constraints);

/// @brief @a count distinct valid constraints for a volume drawing its labels from @a pool:
/// pairs of pool labels, separators that are no constraint's A or B (ALGORITHM.md §6), now
/// and then a separator absent from the pool. Needs count + 2 <= pool.size().
std::vector<vdbi::SeparationConstraint> randomConstraints(Rng& rng,
                                                          const std::vector<vdbi::Label>& pool,
                                                          int count);

/// What the dense check of one or more repairs found (counts add up over repairs).
struct SeparationReport
{
    std::size_t repairs = 0;
    std::size_t pointsChecked = 0;   ///< fine points whose 8 voxels are not all one label
    std::size_t nonManifold = 0;     ///< (point, label) pairs failing the vertex-link test
    std::size_t touching = 0;        ///< (point, constraint) pairs where A and B both occur
    std::size_t outsideBox = 0;      ///< relabelled subvoxels outside the checker's box
    std::size_t failingRepairs = 0;  ///< repairs with any of the three above
    std::size_t relabelled = 0;      ///< relabelled subvoxels
    /// Largest distance (coarse units, Chebyshev, closed cubes) of a subvoxel relabelled to a
    /// label that is no separator, to the nearest input voxel of that label (2 if none within
    /// 2 voxels).
    double maxDistance = 0;
    double maxSeparatorDistance = 0; ///< the same for subvoxels relabelled to a separator

    void add(const SeparationReport& other);
};

/// @brief The distances of every relabelled subvoxel of @a labels (see SeparationReport);
/// fills relabelled, maxDistance and maxSeparatorDistance. Fine tiles are not expected.
SeparationReport measureDistances(const vdbi::RefinedLabels& labels,
                                  const std::vector<vdbi::SeparationConstraint>& constraints);

/// @brief Checks many repairs of one small volume, on a dense copy of its fine labels.
/// @details The coarse labels are upsampled once. Per repair, the relabelled subvoxels are
/// written over a copy, and every fine point whose 8 voxels can differ (those of the box
/// around the non-background input voxels and the relabelled subvoxels) is tested: the
/// vertex-link cycle test for every label, and A/B touching for every constraint. Every
/// other point sees only the background. Not thread-safe: one checker per thread.
class SmallVolumeChecker
{
public:
    /// @param coarse  the input labels, every non-background voxel inside @a box
    /// @param box     coarse voxels that may be subdivided; relabelled subvoxels outside it
    ///                are counted as failures
    /// @param s       subdivision factor of the repairs to check
    /// @throw openvdb::ValueError if a non-background voxel lies outside @a box
    SmallVolumeChecker(const openvdb::Int32Grid& coarse, const openvdb::CoordBBox& box, int s);

    /// Checks one repair of the volume under @a constraints and adds the findings to @a report.
    void check(const vdbi::RefinedLabels& labels,
               const std::vector<vdbi::SeparationConstraint>& constraints,
               SeparationReport& report);

private:
    std::size_t index(const openvdb::Coord& f) const;
    /// Like measureDistances(), from the neighbour tables.
    double distanceToLabel(const openvdb::Coord& f, vdbi::Label label, double enough) const;

    int mS;
    vdbi::Label mBackground;
    openvdb::CoordBBox mBox;          ///< coarse box
    openvdb::Coord mFineOrigin;       ///< first fine voxel of the dense array (box - 1 fine voxel)
    openvdb::Coord mFineDims;
    std::vector<vdbi::Label> mUpsampled; ///< the coarse labels at every fine voxel
    std::vector<vdbi::Label> mWork;      ///< mUpsampled with one repair's changes
    std::vector<std::size_t> mChanged;   ///< indices changed in mWork
    std::vector<vdbi::Label> mColumnLabel;     ///< per voxel column of a row of points
    std::vector<unsigned char> mColumnUniform;
    openvdb::CoordBBox mStoredFine;   ///< fine voxels of the non-background input voxels
    openvdb::CoordBBox mCoarseBox;    ///< mBox grown by 2 (the distance search)
    std::vector<vdbi::Label> mCoarse; ///< labels of mCoarseBox
    std::vector<vdbi::Label> mLabels; ///< the distinct labels of mCoarse
    /// [ring - 1][(box voxel, label index)]: offsets of the neighbours with that label
    std::vector<std::vector<openvdb::Coord>> mRings[2];
};

} // namespace vdbi_test
