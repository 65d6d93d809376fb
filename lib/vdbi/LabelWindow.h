// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/LabelWindow.h
/// @brief The unit of work of the leaf passes: an 8^3 block of grid points or voxels, with the
/// labels of the voxels around it copied into a small dense window.
/// @details Every element (voxel, face, edge, grid point) is owned by one block: the one that
/// holds its min corner. The blocks to visit are the leaves of the tree and their neighbours in
/// the positive directions, whose elements touch the background just past a leaf's max faces.
/// So the passes cost O(leaves), never O(bounding box).

#ifndef VDBI_LABEL_WINDOW_HAS_BEEN_INCLUDED
#define VDBI_LABEL_WINDOW_HAS_BEEN_INCLUDED

#include <vdbi/Types.h>

#include <openvdb/openvdb.h>

#include <vector>

namespace vdbi {

/// Edge length of a block: the leaf size of Int32Tree.
constexpr int BLOCK_DIM = 8;

/// @brief Origins of the blocks to visit, sorted: the origins of the leaves of @a tree and of
/// their neighbours at +8 along any combination of axes.
/// @param tree  a tree whose tiles hold only the background (see voxelizedLabels())
std::vector<openvdb::Coord> blockOrigins(const openvdb::Int32Tree& tree, bool threaded);

/// @brief The block origins @a leafOrigins (sorted, distinct) and those of their neighbours
/// at +8 along any combination of axes, sorted and distinct.
std::vector<openvdb::Coord> withPositiveNeighbours(const std::vector<openvdb::Coord>& leafOrigins);

/// @brief The labels of voxels [origin - 1, origin + BLOCK_DIM] (10^3), read leaf by leaf.
class LabelWindow
{
public:
    static constexpr int DIM = BLOCK_DIM + 2;

    /// Unregistered read accessor: the trees are not modified while the passes run.
    using Accessor = openvdb::tree::ValueAccessor<const openvdb::Int32Tree, false>;

    /// Copies the window of the block at @a origin through @a acc (one per thread).
    void load(Accessor& acc, const openvdb::Coord& origin);

    /// Label of the voxel at offset (x, y, z) from origin - 1, each in [0, DIM).
    Label at(int x, int y, int z) const { return mLabels[(x * DIM + y) * DIM + z]; }
    const Label* data() const { return mLabels; }
    const openvdb::Coord& origin() const { return mOrigin; }

    /// @brief True when the @a count rows of voxels starting at flat indices @a rows hold one
    /// label over z in [0, DIM - 1): the voxels that the grid points or faces of one row of
    /// the block read. Lets the passes skip the rows that hold nothing to do.
    bool isUniform(const int* rows, int count) const
    {
        const Label label = mLabels[rows[0]];
        bool uniform = true;
        for (int r = 0; r < count; ++r) {
            const Label* row = mLabels + rows[r];
            for (int z = 0; z < DIM - 1; ++z) uniform &= row[z] == label;
        }
        return uniform;
    }

    /// Offsets in the flat array for a step along x, y, z.
    static constexpr int STRIDE[3] = {DIM * DIM, DIM, 1};
    /// Flat index of the voxel at offset (x, y, z) from origin - 1.
    static constexpr int index(int x, int y, int z) { return (x * DIM + y) * DIM + z; }

private:
    Label mLabels[DIM * DIM * DIM];
    openvdb::Coord mOrigin;
};

/// @brief Which voxels of a block's window (LabelWindow) are subdivided, read from the
/// subdivision mask of the repair.
class MaskWindow
{
public:
    using Accessor = openvdb::tree::ValueAccessor<const openvdb::MaskTree, false>;

    /// Returns false (and loads nothing) when no subdivided voxel is near the block.
    bool load(Accessor& acc, const openvdb::Coord& origin);
    /// Whether the voxel at flat index @a flat (LabelWindow::index()) is subdivided.
    bool at(int flat) const { return mOn[flat]; }
    /// Whether a voxel of the 3 x 3 rows (along z) around row (x, y) is subdivided: the
    /// voxels that the faces of row (x, y) and their edges touch.
    bool anyOnNear(int x, int y) const
    {
        const bool* r = mRowOn + (x - 1) * DIM + (y - 1);
        return r[0] || r[1] || r[2] || r[DIM] || r[DIM + 1] || r[DIM + 2] || r[2 * DIM]
            || r[2 * DIM + 1] || r[2 * DIM + 2];
    }
    /// Whether a voxel of the rows of LabelWindow::isUniform() is subdivided.
    bool anyOn(const int* rows, int count) const
    {
        bool any = false;
        for (int r = 0; r < count; ++r) {
            for (int z = 0; z < DIM - 1; ++z) any |= mOn[rows[r] + z];
        }
        return any;
    }

private:
    static constexpr int DIM = LabelWindow::DIM;
    const openvdb::MaskTree::LeafNodeType* mLeaves[27];
    bool mTiles[27];
    bool mOn[DIM * DIM * DIM];
    bool mRowOn[DIM * DIM]; ///< per row (x, y): whether a voxel of it is on
};

} // namespace vdbi

#endif // VDBI_LABEL_WINDOW_HAS_BEEN_INCLUDED
