// SPDX-License-Identifier: Apache-2.0

#include <vdbi/LabelWindow.h>

#include <tbb/parallel_sort.h>

#include <algorithm>

namespace vdbi {

std::vector<openvdb::Coord>
blockOrigins(const openvdb::Int32Tree& tree, bool threaded)
{
    std::vector<const openvdb::Int32Tree::LeafNodeType*> leaves;
    leaves.reserve(tree.leafCount());
    tree.getNodes(leaves);

    std::vector<openvdb::Coord> origins;
    origins.reserve(leaves.size() * 8);
    for (const auto* leaf : leaves) {
        const openvdb::Coord o = leaf->origin();
        for (int n = 0; n < 8; ++n) {
            origins.emplace_back(o.x() + ((n & 1) ? BLOCK_DIM : 0),
                                 o.y() + ((n & 2) ? BLOCK_DIM : 0),
                                 o.z() + ((n & 4) ? BLOCK_DIM : 0));
        }
    }
    if (threaded) tbb::parallel_sort(origins.begin(), origins.end());
    else std::sort(origins.begin(), origins.end());
    origins.erase(std::unique(origins.begin(), origins.end()), origins.end());
    return origins;
}

void
LabelWindow::load(Accessor& acc, const openvdb::Coord& origin)
{
    using LeafT = openvdb::Int32Tree::LeafNodeType;
    mOrigin = origin;
    const openvdb::Coord lo = origin.offsetBy(-1);

    // The window overlaps the 3^3 leaves at offsets -8, 0, +8. Per column of three leaves
    // along z, every window row takes its last voxel from the leaf below, eight straight from
    // the middle leaf's buffer and its first from the leaf above; where no leaf is stored, the
    // tile value or background, uniform over the leaf's extent.
    for (int lx = -1; lx <= 1; ++lx) {
        for (int ly = -1; ly <= 1; ++ly) {
            const LeafT* leaf[3];
            Label fill[3];
            for (int lz = -1; lz <= 1; ++lz) {
                const openvdb::Coord leafOrigin = origin.offsetBy(
                    lx * BLOCK_DIM, ly * BLOCK_DIM, lz * BLOCK_DIM);
                leaf[lz + 1] = acc.probeConstLeaf(leafOrigin);
                fill[lz + 1] = leaf[lz + 1] ? 0 : acc.getValue(leafOrigin);
            }
            // Overlap of this column with the window, in window offsets along x and y.
            const auto first = [](int l) { return l < 0 ? 0 : (l == 0 ? 1 : BLOCK_DIM + 1); };
            const auto end = [](int l) { return l < 0 ? 1 : (l == 0 ? BLOCK_DIM + 1 : DIM); };
            for (int x = first(lx); x < end(lx); ++x) {
                for (int y = first(ly); y < end(ly); ++y) {
                    Label* dst = mLabels + index(x, y, 0);
                    // Buffer offset of (x, y, z = 0) in any leaf of the column.
                    const openvdb::Index row = LeafT::coordToOffset(lo.offsetBy(x, y, 1));
                    dst[0] = leaf[0] ? leaf[0]->buffer()[row + BLOCK_DIM - 1] : fill[0];
                    if (leaf[1]) {
                        std::copy_n(leaf[1]->buffer().data() + row, BLOCK_DIM, dst + 1);
                    } else {
                        std::fill_n(dst + 1, BLOCK_DIM, fill[1]);
                    }
                    dst[DIM - 1] = leaf[2] ? leaf[2]->buffer()[row] : fill[2];
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
    for (int n = 0; n < 27; ++n) {
        const openvdb::Coord leafOrigin = origin.offsetBy((n % 3 - 1) * BLOCK_DIM,
            ((n / 3) % 3 - 1) * BLOCK_DIM, (n / 9 - 1) * BLOCK_DIM);
        mLeaves[n] = acc.probeConstLeaf(leafOrigin);
        mTiles[n] = !mLeaves[n] && acc.isValueOn(leafOrigin);
        any = any || mLeaves[n] || mTiles[n];
    }
    if (!any) return false;
    // Window range and first leaf coordinate of the part of each neighbour leaf it
    // overlaps, per axis: the last layer of the leaf below, all 8 of the block's leaf,
    // the first layer of the leaf above.
    static constexpr int FIRST[3] = {0, 1, DIM - 1}, END[3] = {1, DIM - 1, DIM},
                         LEAF_FIRST[3] = {BLOCK_DIM - 1, 0, 0};
    std::fill(std::begin(mOn), std::end(mOn), false);
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
        mRowOn[r] = std::any_of(mOn + r * DIM, mOn + (r + 1) * DIM, [](bool on) { return on; });
    }
    return true;
}

} // namespace vdbi
