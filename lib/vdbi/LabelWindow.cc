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

    // The window overlaps the 3^3 leaves at offsets -8, 0, +8; copy each overlap directly
    // from the leaf buffer, or fill it with the tile value where no leaf is stored.
    for (int lx = -1; lx <= 1; ++lx) {
        for (int ly = -1; ly <= 1; ++ly) {
            for (int lz = -1; lz <= 1; ++lz) {
                const openvdb::Coord leafOrigin = origin.offsetBy(
                    lx * BLOCK_DIM, ly * BLOCK_DIM, lz * BLOCK_DIM);
                // Overlap of this leaf with the window, in window offsets.
                int b[3], e[3];
                const int l[3] = {lx, ly, lz};
                for (int a = 0; a < 3; ++a) {
                    b[a] = l[a] < 0 ? 0 : (l[a] == 0 ? 1 : BLOCK_DIM + 1);
                    e[a] = l[a] < 0 ? 1 : (l[a] == 0 ? BLOCK_DIM + 1 : DIM);
                }
                const LeafT* leaf = acc.probeConstLeaf(leafOrigin);
                // No leaf: a tile or the background, uniform over the leaf's extent.
                const Label fill = leaf ? 0 : acc.getValue(leafOrigin);
                for (int x = b[0]; x < e[0]; ++x) {
                    for (int y = b[1]; y < e[1]; ++y) {
                        Label* dst = mLabels + index(x, y, 0);
                        if (!leaf) {
                            for (int z = b[2]; z < e[2]; ++z) dst[z] = fill;
                            continue;
                        }
                        const Label* src = leaf->buffer().data()
                            + LeafT::coordToOffset(lo.offsetBy(x, y, b[2]));
                        for (int z = b[2]; z < e[2]; ++z) dst[z] = src[z - b[2]];
                    }
                }
            }
        }
    }
}

} // namespace vdbi
