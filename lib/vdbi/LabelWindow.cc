// SPDX-License-Identifier: Apache-2.0

#include <vdbi/LabelWindow.h>

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cstring>
#include <type_traits>

namespace vdbi {

std::vector<openvdb::Coord>
blockOrigins(const openvdb::Int32Tree& tree, bool threaded)
{
    std::vector<const openvdb::Int32Tree::LeafNodeType*> leaves;
    leaves.reserve(tree.leafCount());
    tree.getNodes(leaves);

    std::vector<openvdb::Coord> origins;
    origins.reserve(leaves.size());
    for (const auto* leaf : leaves) origins.push_back(leaf->origin());
    if (threaded) tbb::parallel_sort(origins.begin(), origins.end());
    else std::sort(origins.begin(), origins.end());
    return withPositiveNeighbours(origins);
}

std::vector<openvdb::Coord>
withPositiveNeighbours(const std::vector<openvdb::Coord>& leafOrigins)
{
    // A shift keeps the order: each of the 7 shifted copies is sorted as it is, and merging
    // them in costs far fewer comparisons than sorting 8 times as many origins.
    std::vector<openvdb::Coord> origins(leafOrigins), shifted, merged;
    shifted.reserve(leafOrigins.size());
    for (int n = 1; n < 8; ++n) {
        const openvdb::Coord step((n & 1) ? BLOCK_DIM : 0, (n & 2) ? BLOCK_DIM : 0,
                                  (n & 4) ? BLOCK_DIM : 0);
        shifted.clear();
        for (const openvdb::Coord& o : leafOrigins) shifted.push_back(o + step);
        merged.resize(origins.size() + shifted.size());
        merged.erase(std::set_union(origins.begin(), origins.end(), shifted.begin(),
                                    shifted.end(), merged.begin()), merged.end());
        origins.swap(merged);
    }
    return origins;
}

namespace {

/// Window range of the part of each neighbour leaf the window overlaps, per axis: the last
/// layer of the leaf below, all 8 of the block's leaf, the first layer of the leaf above.
constexpr int FIRST[3] = {0, 1, LabelWindow::DIM - 1}, END[3] = {1, LabelWindow::DIM - 1,
    LabelWindow::DIM};

/// @brief Probes the 27 leaves around a block through the internal node that holds the block
/// (which holds all of them for most blocks), and through @a acc only for the others.
/// @details Leaf n lies at origin + 8 (n % 3 - 1, (n / 3) % 3 - 1, n / 9 - 1). @a visit(n,
/// leaf, tileValue, tileActive) is called for each; leaf is null where none is stored, and
/// then the tile (or background) there gives the value and state. The tile is read from the
/// node's table, not through getValue(), whose path into a child leaf GCC inlines and then
/// warns about (-Wstringop-overflow) although no child is there.
template<typename AccessorT, typename Visit>
void
visitLeavesAround(AccessorT& acc, const openvdb::Coord& origin, const Visit& visit)
{
    using TreeT = std::remove_const_t<typename AccessorT::TreeType>;
    using LeafT = typename TreeT::LeafNodeType;
    using NodeT = typename TreeT::RootNodeType::ChildNodeType::ChildNodeType;
    const NodeT* node = acc.template probeConstNode<NodeT>(origin);
    const openvdb::Coord nodeMin = node ? node->origin() : origin;
    int n = 0;
    for (int lz = -1; lz <= 1; ++lz) {
        for (int ly = -1; ly <= 1; ++ly) {
            for (int lx = -1; lx <= 1; ++lx, ++n) {
                const openvdb::Coord leafOrigin =
                    origin.offsetBy(lx * BLOCK_DIM, ly * BLOCK_DIM, lz * BLOCK_DIM);
                const openvdb::Coord d = leafOrigin - nodeMin;
                if (node && unsigned(d.x()) < NodeT::DIM && unsigned(d.y()) < NodeT::DIM
                    && unsigned(d.z()) < NodeT::DIM) {
                    const LeafT* leaf = node->probeConstLeaf(leafOrigin);
                    if (leaf) {
                        visit(n, leaf, typename LeafT::ValueType(), false);
                    } else {
                        const openvdb::Index i = NodeT::coordToOffset(leafOrigin);
                        visit(n, leaf, node->getTable()[i].getValue(), node->isValueMaskOn(i));
                    }
                } else {
                    const LeafT* leaf = acc.probeConstLeaf(leafOrigin);
                    if (leaf) visit(n, leaf, typename LeafT::ValueType(), false);
                    else visit(n, leaf, acc.getValue(leafOrigin), acc.isValueOn(leafOrigin));
                }
            }
        }
    }
}

} // namespace

void
LabelWindow::load(Accessor& acc, const openvdb::Coord& origin)
{
    using LeafT = openvdb::Int32Tree::LeafNodeType;
    mOrigin = origin;

    // Per leaf around the block, its values; where no leaf is stored, 8 copies of the tile
    // value or background, which stand for every row of it (offset mask 0).
    const Label* values[27];
    openvdb::Index rowMask[27];
    Label fill[27][BLOCK_DIM];
    visitLeavesAround(acc, origin, [&](int n, const LeafT* leaf, Label tileValue, bool) {
        if (leaf) {
            values[n] = leaf->buffer().data();
            rowMask[n] = LeafT::SIZE - 1;
        } else {
            std::fill_n(fill[n], BLOCK_DIM, tileValue);
            values[n] = fill[n];
            rowMask[n] = 0;
        }
    });
    // Per column of three leaves along z, every window row takes its last voxel from the
    // leaf below, eight from the middle leaf and its first from the leaf above.
    for (int ly = 0; ly < 3; ++ly) {
        for (int lx = 0; lx < 3; ++lx) {
            const int n = lx + 3 * ly;
            const Label *below = values[n] + (BLOCK_DIM - 1), *middle = values[n + 9],
                        *above = values[n + 18];
            const openvdb::Index belowMask = rowMask[n], middleMask = rowMask[n + 9],
                                 aboveMask = rowMask[n + 18];
            for (int x = FIRST[lx]; x < END[lx]; ++x) {
                for (int y = FIRST[ly]; y < END[ly]; ++y) {
                    // Buffer offset of (x, y, z = 0) in any leaf of the column.
                    const openvdb::Index row =
                        LeafT::coordToOffset(openvdb::Coord(x - 1, y - 1, 0));
                    Label* dst = mLabels + index(x, y, 0);
                    dst[0] = below[row & belowMask];
                    // memcpy of a constant size inlines; std::copy_n here became a call to
                    // memmove per row.
                    std::memcpy(dst + 1, middle + (row & middleMask), BLOCK_DIM * sizeof(Label));
                    dst[DIM - 1] = above[row & aboveMask];
                }
            }
        }
    }
}

namespace {

/// The 8 bits of a byte as 8 bools, lowest bit first: a leaf's value mask holds a row of 8
/// voxels along z in one byte, bit z for voxel z.
struct ByteBits
{
    bool bits[256][8];
    constexpr ByteBits() : bits()
    {
        for (int b = 0; b < 256; ++b) {
            for (int z = 0; z < 8; ++z) bits[b][z] = ((b >> z) & 1) != 0;
        }
    }
};
constexpr ByteBits BYTE_BITS;

} // namespace

bool
MaskWindow::load(Accessor& acc, const openvdb::Coord& origin)
{
    using LeafT = openvdb::MaskTree::LeafNodeType;
    bool any = false;
    visitLeavesAround(acc, origin, [&](int n, const LeafT* leaf, bool, bool tileActive) {
        mLeaves[n] = leaf;
        mTiles[n] = !leaf && tileActive;
        any = any || leaf || mTiles[n];
    });
    if (!any) return false;
    // First leaf coordinate of the part of each neighbour leaf the window overlaps, per axis.
    static constexpr int LEAF_FIRST[3] = {BLOCK_DIM - 1, 0, 0};
    std::memset(mOn, 0, sizeof(mOn));
    for (int n = 0; n < 27; ++n) {
        if (!mLeaves[n] && !mTiles[n]) continue;
        const int px = n % 3, py = (n / 3) % 3, pz = n / 9;
        for (int x = FIRST[px]; x < END[px]; ++x) {
            for (int y = FIRST[py]; y < END[py]; ++y) {
                bool* row = mOn + LabelWindow::index(x, y, 0);
                if (mTiles[n]) {
                    std::fill(row + FIRST[pz], row + END[pz], true);
                    continue;
                }
                const openvdb::Index i = LeafT::coordToOffset(openvdb::Coord(
                    x - FIRST[px] + LEAF_FIRST[px], y - FIRST[py] + LEAF_FIRST[py], 0));
                const auto bits = mLeaves[n]->getValueMask().getWord<std::uint8_t>(i >> 3);
                if (pz == 1) {
                    std::copy_n(BYTE_BITS.bits[bits], BLOCK_DIM, row + 1);
                } else {
                    row[FIRST[pz]] = BYTE_BITS.bits[bits][LEAF_FIRST[pz]];
                }
            }
        }
    }
    for (int r = 0; r < DIM * DIM; ++r) {
        // A row's 10 bools as 8 + 2 bytes.
        static_assert(DIM == 10, "a window row is read as 8 + 2 bytes");
        std::uint64_t first8;
        std::uint16_t last2;
        std::memcpy(&first8, mOn + r * DIM, 8);
        std::memcpy(&last2, mOn + r * DIM + 8, 2);
        mRowOn[r] = (first8 | last2) != 0;
    }
    return true;
}

} // namespace vdbi
