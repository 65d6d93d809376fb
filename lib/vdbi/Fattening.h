// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/Fattening.h
/// @brief Subdivides the voxels around critical elements and relabels small neighbourhoods
/// of them, so that no label has a critical element left on the fine grid.

#ifndef VDBI_FATTENING_HAS_BEEN_INCLUDED
#define VDBI_FATTENING_HAS_BEEN_INCLUDED

#include <vdbi/CriticalElements.h>
#include <vdbi/RefinedLabels.h>
#include <vdbi/Types.h>

namespace vdbi {

/// The subdivision factor s for these options: 7 with constraints, else 5.
int subdivisionFactor(const RepairOptions& options);

/// @brief Fattening (Bischoff & Kobbelt 2006; ALGORITHM.md §3).
/// @details Every coarse voxel whose closed cube touches a critical element is split into s^3
/// subvoxels. Without constraints (s = 5), the N1 neighbourhood of each critical edge and then
/// the N2 neighbourhood of each critical vertex is relabelled to the element's dominant label;
/// with constraints (s = 7), faces N1, then edges N2, then vertices N3. A later pass overwrites
/// an earlier one; inside one pass a subvoxel claimed by several elements goes to the label of
/// highest priority, so the result does not depend on order or thread count.
/// @param grid      the coarse labels, without tiles (tiles voxelized: see LabelGrid.h)
/// @param elements  found by findCriticalElements() on @a grid with the same @a options
/// @throw vdbi::Interrupted if the interrupter asks to stop
RefinedLabels fattenCriticalElements(const openvdb::Int32Grid::ConstPtr& grid,
                                     const CriticalElements& elements,
                                     const RepairOptions& options = RepairOptions());

} // namespace vdbi

#endif // VDBI_FATTENING_HAS_BEEN_INCLUDED
