// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/LabelGrid.h
/// @brief Small facts about an input label grid, shared by the stages.

#ifndef VDBI_LABEL_GRID_HAS_BEEN_INCLUDED
#define VDBI_LABEL_GRID_HAS_BEEN_INCLUDED

#include <vdbi/Types.h>

#include <openvdb/openvdb.h>

#include <vector>

namespace vdbi {

/// @brief The grid itself (sharing its tree) when it holds no tile of a non-background value,
/// else a deep copy in which such tiles are replaced by voxels. The stages read leaf voxels.
openvdb::Int32Grid::ConstPtr voxelizedLabels(const openvdb::Int32Grid& grid);

/// The distinct labels of the grid, the background included, in increasing order.
std::vector<Label> collectLabels(const openvdb::Int32Grid& grid, bool threaded = true);

} // namespace vdbi

#endif // VDBI_LABEL_GRID_HAS_BEEN_INCLUDED
