// SPDX-License-Identifier: Apache-2.0

#include <vdbi/LabelGrid.h>

#include <openvdb/tree/LeafManager.h>

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <set>

namespace vdbi {

namespace {

/// An iterator over the tile values of a tree (the root's and internal nodes'), no voxels.
openvdb::Int32Tree::ValueAllCIter
tileValues(const openvdb::Int32Tree& tree)
{
    openvdb::Int32Tree::ValueAllCIter it = tree.cbeginValueAll();
    it.setMaxDepth(openvdb::Int32Tree::ValueAllCIter::LEAF_DEPTH - 1);
    return it;
}

} // namespace

openvdb::Int32Grid::ConstPtr
voxelizedLabels(const openvdb::Int32Grid& grid)
{
    const Label background = grid.background();
    // Collect first: filling a tile changes the tree under an iterator.
    std::vector<std::pair<openvdb::CoordBBox, std::pair<Label, bool>>> tiles;
    for (auto it = tileValues(grid.tree()); it; ++it) {
        if (*it != background) tiles.push_back({it.getBoundingBox(), {*it, it.isValueOn()}});
    }
    if (tiles.empty()) return grid.copy(); // shares the tree

    openvdb::Int32Grid::Ptr copy = grid.deepCopy();
    for (const auto& t : tiles) copy->tree().denseFill(t.first, t.second.first, t.second.second);
    return copy;
}

std::vector<Label>
collectLabels(const openvdb::Int32Grid& grid, bool threaded)
{
    using LeafT = openvdb::Int32Tree::LeafNodeType;
    tbb::enumerable_thread_specific<std::set<Label>> local;
    openvdb::tree::LeafManager<const openvdb::Int32Tree> leaves(grid.tree());
    leaves.foreach([&](const LeafT& leaf, std::size_t) {
        std::set<Label>& labels = local.local();
        const Label* v = leaf.buffer().data();
        Label last = v[0];
        labels.insert(last);
        for (openvdb::Index i = 1; i < LeafT::SIZE; ++i) {
            if (v[i] != last) { last = v[i]; labels.insert(last); }
        }
    }, threaded);
    std::set<Label> all{grid.background()};
    for (auto it = tileValues(grid.tree()); it; ++it) all.insert(*it);
    for (const auto& labels : local) all.insert(labels.begin(), labels.end());
    return std::vector<Label>(all.begin(), all.end());
}

} // namespace vdbi
