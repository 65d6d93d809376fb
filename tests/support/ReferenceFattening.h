// SPDX-License-Identifier: Apache-2.0
/// @file support/ReferenceFattening.h
/// @brief A small, dense, obviously correct reference of the repair (ALGORITHM.md §2-§3),
/// with the subdivision and the neighbourhoods as parameters, so that the checker can be shown
/// to fail on settings that must fail and the library can be compared voxel by voxel.
/// @details Single-threaded, dense over the bounding box, no sparse trees in the work: slow and
/// simple on purpose. It finds the critical elements itself by the pattern rules of §2 (it does
/// not call the library) and relabels with the rules of §3; inside one pass a subvoxel claimed
/// by several elements goes to the label of highest priority.

#pragma once

#include "support/RefinedChecker.h"

#include <vdbi/CriticalElements.h>
#include <vdbi/Types.h>

#include <openvdb/openvdb.h>

#include <vector>

namespace vdbi_test {

/// Parameters of the reference repair.
struct ReferenceParams
{
    int s = 5;       ///< subdivision factor
    int edgeK = 1;   ///< critical edges relabel N_edgeK (0: edges are not fattened)
    int vertexK = 2; ///< critical vertices relabel N_vertexK (0: vertices are not fattened)
    vdbi::LabelPriority priority;
};

/// Critical elements found by the reference, sorted like the library's lists.
struct ReferenceCritical
{
    std::vector<vdbi::CriticalEdge> edges;
    std::vector<vdbi::CriticalVertex> vertices;

    std::size_t singularVertexCount() const;
    bool empty() const { return edges.empty() && vertices.empty(); }
};

/// @brief Critical edges and vertices of @a grid by the pattern rules of ALGORITHM.md §2, with
/// dominant labels chosen by @a priority. Voxels are read by value, active or not.
ReferenceCritical referenceCriticalElements(const openvdb::Int32Grid& grid,
                                            const vdbi::LabelPriority& priority = {});

/// The result of the reference repair.
struct ReferenceRefined
{
    int s = 1;
    openvdb::Int32Grid::ConstPtr coarse;  ///< the input
    /// Coarse voxels whose closed cube touches a critical element (plus, for neighbourhoods
    /// larger than s, any coarse voxel holding a relabelled subvoxel).
    openvdb::MaskGrid::Ptr subdivided;
    /// Fine labels over the input's bounding box grown by 2 coarse voxels; the background
    /// outside.
    DenseFineLabels fine;
    ReferenceCritical elements;
    std::size_t relabelled = 0; ///< fine voxels whose label differs from their coarse voxel's

    vdbi::Label operator()(const openvdb::Coord& f) const { return fine(f); }
    /// The points the manifold checker must visit (see checkPoints()).
    openvdb::MaskGrid::Ptr checkPoints() const;
    /// Runs the manifold checker on this result.
    ManifoldReport check(const CheckOptions& options = CheckOptions()) const;
    /// Runs the distance check on this result.
    DistanceReport distance(double bound = 0.4) const;
};

/// @brief The reference repair of @a grid (its background is the label outside).
/// @throw openvdb::ValueError for s < 1 or negative neighbourhoods
ReferenceRefined referenceFattening(const openvdb::Int32Grid& grid,
                                    const ReferenceParams& params = ReferenceParams());

} // namespace vdbi_test
