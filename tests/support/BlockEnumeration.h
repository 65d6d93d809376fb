// SPDX-License-Identifier: Apache-2.0
/// @file support/BlockEnumeration.h
/// @brief Exhaustive small inputs: every labelling of a 2x2x2 block and every 2x2x3 volume
/// with labels 0..2, each padded with background 0 and reduced by the symmetries of the box.
/// @details The repair (ALGORITHM.md §2-§3) only compares labels (equality, and order for the
/// dominant label) and is symmetric under the symmetries of the grid, so one representative
/// per class stands for all of its labellings. Whether a label is the background 0 matters
/// (the padding around the block is 0), so the classes with and without a background block
/// are distinct.

#pragma once

#include <vdbi/Types.h>

#include <openvdb/openvdb.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace vdbi_test {

/// Labels of a 2x2x2 block at the origin, voxel (x,y,z) at index x + 2y + 4z.
using BlockLabels = std::array<vdbi::Label, 8>;

/// Labels of a 2x2x3 box at the origin, voxel (x,y,z) at index x + 2y + 4z (z = 0..2).
using Box223Labels = std::array<vdbi::Label, 12>;

/// @brief One class of 2x2x2 block labellings.
struct BlockClass
{
    /// The representative: its order ranks (minimal over the 48 symmetries), as labels 1..k,
    /// or 0..k-1 when the smallest block is the background 0.
    BlockLabels labels;
    bool hasBackground = false;
    /// Labellings in the class: ordered set partitions equivalent under the symmetries.
    std::size_t orbitSize = 0;
};

/// @brief One class of 2x2x3 volumes with labels 0..2.
struct Box223Class
{
    Box223Labels labels; ///< the representative: minimal code over the 16 symmetries
    std::size_t orbitSize = 0;
};

/// @brief The 48 symmetries of the cube as permutations of the block indices:
/// symmetry s maps voxel i to voxel cubeSymmetries()[s][i]. Entry 0 is the identity.
const std::vector<std::array<int, 8>>& cubeSymmetries();

/// @brief The 16 symmetries of the 2x2x3 box (swap x and y, flip x, y, z) as permutations of
/// its 12 voxel indices. Entry 0 is the identity.
const std::vector<std::array<int, 12>>& box223Symmetries();

/// @brief Every ordered set partition of the 8 voxels (as rank vectors: surjections onto
/// 0..k-1): the ordered Bell (Fubini) number of 8, 545,835.
std::vector<std::array<std::uint8_t, 8>> orderedSetPartitions8();

/// @brief The canonical form of a rank vector: the minimum of its 48 images, compared
/// lexicographically from voxel 0.
std::array<std::uint8_t, 8> canonicalBlock(const std::array<std::uint8_t, 8>& ranks);

/// @brief All classes of 2x2x2 labellings (cached after the first call): every ordered set
/// partition, with and without the background, under the 48 symmetries. ALGORITHM.md §6
/// counts 23,982 classes of 2 x 545,835 = 1,091,670 labellings.
const std::vector<BlockClass>& blockClasses();

/// @brief All classes of the 3^12 = 531,441 volumes of 2x2x3 voxels with labels 0..2
/// (cached after the first call), under the 16 symmetries of the box.
const std::vector<Box223Class>& box223Classes();

/// A grid (background 0) holding @a labels at voxels [0,1]^3.
openvdb::Int32Grid::Ptr blockGrid(const BlockLabels& labels);

/// A grid (background 0) holding @a labels at voxels [0,1] x [0,1] x [0,2].
openvdb::Int32Grid::Ptr box223Grid(const Box223Labels& labels);

/// Calls @a f with every 2x2x2 class, with its index into blockClasses().
void forEachBlockClass(const std::function<void(std::size_t, const BlockClass&)>& f);

/// Calls @a f with every 2x2x3 class, with its index into box223Classes().
void forEachBox223Class(const std::function<void(std::size_t, const Box223Class&)>& f);

} // namespace vdbi_test
