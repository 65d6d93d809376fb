// SPDX-License-Identifier: Apache-2.0

#include <vdbi/LabelGrid.h>

#include <openvdb/tree/LeafManager.h>

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <set>
#include <type_traits>

namespace vdbi {

namespace {

using RootT = openvdb::Int32Tree::RootNodeType;
using UpperT = RootT::ChildNodeType;
using LowerT = UpperT::ChildNodeType;

/// Calls op(node, slot, value) for every tile slot of every node of type NodeT.
/// @details Reads the node tables directly: a tree iterator over all values visits the
/// 32,768 + 4,096 slots of each upper and lower node through mask searches, which costs far
/// more than the labels of a small volume.
template<typename NodeT, typename Op>
void
forEachTileSlot(const openvdb::Int32Tree& tree, Op&& op)
{
    std::vector<const NodeT*> nodes;
    tree.getNodes(nodes);
    for (const NodeT* node : nodes) {
        const typename NodeT::UnionType* table = node->getTable();
        const typename NodeT::NodeMaskType& children = node->getChildMask();
        for (openvdb::Index i = 0; i < NodeT::NUM_VALUES; ++i) {
            if (!children.isOn(i)) op(*node, i, table[i].getValue());
        }
    }
}

/// Calls op(bbox, value, active) for every tile of the tree (the root's and internal nodes'),
/// no voxels, whose value is not the background.
template<typename Op>
void
forEachLabelledTile(const openvdb::Int32Tree& tree, Op&& op)
{
    const Label background = tree.background();
    for (auto it = tree.root().cbeginValueAll(); it; ++it) {
        if (*it == background) continue;
        op(openvdb::CoordBBox::createCube(it.getCoord(), UpperT::DIM), *it, it.isValueOn());
    }
    const auto internal = [&](const auto& node, openvdb::Index i, Label value) {
        if (value == background) return;
        using NodeT = std::decay_t<decltype(node)>;
        op(openvdb::CoordBBox::createCube(node.offsetToGlobalCoord(i), NodeT::ChildNodeType::DIM),
           value, node.isValueMaskOn(i));
    };
    forEachTileSlot<UpperT>(tree, internal);
    forEachTileSlot<LowerT>(tree, internal);
}

} // namespace

openvdb::Int32Grid::ConstPtr
voxelizedLabels(const openvdb::Int32Grid& grid)
{
    // Collect first: filling a tile changes the tree under an iterator.
    std::vector<std::pair<openvdb::CoordBBox, std::pair<Label, bool>>> tiles;
    forEachLabelledTile(grid.tree(), [&](const openvdb::CoordBBox& box, Label value, bool active) {
        tiles.push_back({box, {value, active}});
    });
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
    forEachLabelledTile(grid.tree(),
        [&](const openvdb::CoordBBox&, Label value, bool) { all.insert(value); });
    for (const auto& labels : local) all.insert(labels.begin(), labels.end());
    return std::vector<Label>(all.begin(), all.end());
}

} // namespace vdbi
