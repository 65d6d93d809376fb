// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Fattening.h>

#include <vdbi/Interruption.h>

#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <memory>
#include <utility>
#include <vector>

namespace vdbi {

namespace {

using openvdb::Coord;
using openvdb::CoordBBox;

/// Closed extent [lo, hi] of an element in coarse grid coordinates.
struct Extent
{
    Coord lo, hi;
};

Extent extentOf(const CriticalVertex& v) { return {v.point, v.point}; }

Extent
extentOf(const CriticalEdge& e)
{
    Coord hi = e.origin;
    hi[e.axis] += 1;
    return {e.origin, hi};
}

Extent
extentOf(const CriticalFace& f)
{
    Coord hi = f.origin.offsetBy(1);
    hi[f.axis] = f.origin[f.axis];
    return {f.origin, hi};
}

/// N_k of an element in fine voxels: [s*lo - k, s*hi + k) per axis (ALGORITHM.md §3).
CoordBBox
neighbourhood(const Extent& e, int s, int k)
{
    return CoordBBox(Coord(s * e.lo.x() - k, s * e.lo.y() - k, s * e.lo.z() - k),
                     Coord(s * e.hi.x() + k - 1, s * e.hi.y() + k - 1, s * e.hi.z() + k - 1));
}

using LeafT = openvdb::Int32Tree::LeafNodeType;

/// Writes @a label into the voxels of @a box inside @a leaf. Among the labels one pass writes
/// into a voxel (@a written: the voxels it wrote so far) the one of highest priority stays, a
/// total order, so the outcome is the same for any order of writes; a pass replaces what
/// earlier passes wrote.
void
writeByPriority(LeafT& leaf, LeafT::NodeMaskType& written, const CoordBBox& box, Label label,
                const LabelPriority& priority)
{
    const CoordBBox part(Coord::maxComponent(box.min(), leaf.origin()),
                         Coord::minComponent(box.max(), leaf.origin().offsetBy(LeafT::DIM - 1)));
    Label* values = leaf.buffer().data();
    auto& active = leaf.getValueMask();
    // A row along z is one byte of a mask, bit z for voxel z: the run [min z, max z] of a
    // row is marked written and active in one step, and where the pass has not written any
    // voxel of it yet (the common case) its label needs no comparison.
    const int zFirst = part.min().z() & int(LeafT::DIM - 1);
    const int zCount = part.max().z() - part.min().z() + 1;
    const auto run = std::uint8_t(((1u << zCount) - 1u) << zFirst);
    for (int x = part.min().x(); x <= part.max().x(); ++x) {
        for (int y = part.min().y(); y <= part.max().y(); ++y) {
            const openvdb::Index row = LeafT::coordToOffset(Coord(x, y, 0));
            std::uint8_t& writtenRow = written.template getWord<std::uint8_t>(row >> 3);
            Label* rowValues = values + row;
            if ((writtenRow & run) == 0) {
                std::fill_n(rowValues + zFirst, zCount, label);
            } else {
                for (int z = zFirst; z < zFirst + zCount; ++z) {
                    rowValues[z] = ((writtenRow >> z) & 1u) ? priority.pick(rowValues[z], label)
                                                            : label;
                }
            }
            writtenRow |= run;
            active.template getWord<std::uint8_t>(row >> 3) |= run;
        }
    }
}

/// Calls @a visit(origin) for the origin of every leaf that @a box overlaps.
template<typename Visit>
void
forEachLeafOf(const CoordBBox& box, const Visit& visit)
{
    constexpr int MASK = int(LeafT::DIM) - 1;
    const Coord lo(box.min().x() & ~MASK, box.min().y() & ~MASK, box.min().z() & ~MASK);
    for (int x = lo.x(); x <= box.max().x(); x += int(LeafT::DIM)) {
        for (int y = lo.y(); y <= box.max().y(); y += int(LeafT::DIM)) {
            for (int z = lo.z(); z <= box.max().z(); z += int(LeafT::DIM)) visit(Coord(x, y, z));
        }
    }
}

/// Relabels N_k of every element of one kind in @a fine (active voxels: the labels written),
/// over what earlier passes wrote there.
/// @details The leaves the neighbourhoods touch are made first (in parallel) and added to
/// the tree (in one thread); then every leaf takes the parts of its neighbourhoods in
/// parallel, each leaf written by one thread: no tree per thread to merge, and the result
/// does not depend on the split.
template<typename Element>
void
relabelPass(openvdb::Int32Tree& fine, const std::vector<Element>& elements, int s, int k,
            const RepairOptions& options, const char* stage)
{
    // (leaf origin, element) for every leaf a neighbourhood overlaps, by leaf.
    std::vector<std::pair<Coord, std::uint32_t>> touches;
    for (std::size_t n = 0; n < elements.size(); ++n) {
        forEachLeafOf(neighbourhood(extentOf(elements[n]), s, k), [&](const Coord& origin) {
            touches.emplace_back(origin, std::uint32_t(n));
        });
    }
    if (options.threaded) tbb::parallel_sort(touches.begin(), touches.end());
    else std::sort(touches.begin(), touches.end());

    std::vector<LeafT*> leaves;
    std::vector<std::size_t> firstTouch; // of each leaf in touches, and the end
    for (std::size_t t = 0; t < touches.size(); ++t) {
        if (t > 0 && touches[t].first == touches[t - 1].first) continue;
        leaves.push_back(fine.probeLeaf(touches[t].first));
        firstTouch.push_back(t);
    }
    firstTouch.push_back(touches.size());
    // Leaves not there yet are made in parallel (each fills 2 KiB of values, the first touch
    // of most of the tree's memory) and added in one thread (the tree's nodes are not
    // thread-safe).
    std::vector<std::unique_ptr<LeafT>> made(leaves.size());
    auto make = [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t l = range.begin(); l < range.end(); ++l) {
            if (!leaves[l]) {
                made[l] = std::make_unique<LeafT>(touches[firstTouch[l]].first,
                                                  fine.background());
            }
        }
    };
    const tbb::blocked_range<std::size_t> allLeaves(0, leaves.size(), 64);
    if (options.threaded) tbb::parallel_for(allLeaves, make);
    else make(allLeaves);
    openvdb::tree::ValueAccessor<openvdb::Int32Tree, false> acc(fine);
    for (std::size_t l = 0; l < leaves.size(); ++l) {
        if (!made[l]) continue;
        leaves[l] = made[l].get();
        acc.addLeaf(made[l].release()); // the tree owns it now
    }

    InterruptFlag interrupt(options.interrupter);
    auto relabel = [&](const tbb::blocked_range<std::size_t>& range) {
        if (interrupt.poll()) return;
        for (std::size_t l = range.begin(); l < range.end(); ++l) {
            LeafT::NodeMaskType written; // by this pass
            for (std::size_t t = firstTouch[l]; t < firstTouch[l + 1]; ++t) {
                const Element& e = elements[touches[t].second];
                writeByPriority(*leaves[l], written, neighbourhood(extentOf(e), s, k), e.label,
                                options.priority);
            }
        }
    };
    if (options.threaded) tbb::parallel_for(allLeaves, relabel);
    else relabel(allLeaves);
    interrupt.throwIfStopped(stage);
}

/// Marks the coarse voxels whose closed cubes touch an element: [lo - 1, hi] per axis.
template<typename Element>
void
markTouchedVoxels(const std::vector<Element>& elements, openvdb::MaskTree& mask)
{
    openvdb::tree::ValueAccessor<openvdb::MaskTree, false> acc(mask);
    for (const Element& e : elements) {
        const Extent x = extentOf(e);
        const CoordBBox box(x.lo.offsetBy(-1), x.hi);
        for (auto it = box.begin(); it; ++it) acc.setValueOn(*it);
    }
}

/// Keeps active only the fine voxels whose label differs from their coarse voxel's.
void
dropUnchanged(openvdb::Int32Tree& fine, const openvdb::Int32Tree& coarse, int s, bool threaded)
{
    constexpr int DIM = int(LeafT::DIM);
    openvdb::tree::LeafManager<openvdb::Int32Tree> leaves(fine);
    leaves.foreach([&](LeafT& leaf, std::size_t) {
        // The coarse voxels under the leaf (at most 8 per axis), read once: per fine voxel a
        // table lookup instead of a tree lookup.
        const Coord first = coarseOf(leaf.origin(), s);
        int cell[3][DIM], span[3];
        for (int a = 0; a < 3; ++a) {
            for (int t = 0; t < DIM; ++t) {
                cell[a][t] = floorDiv(leaf.origin()[a] + t, s) - first[a];
            }
            span[a] = cell[a][DIM - 1] + 1;
        }
        openvdb::tree::ValueAccessor<const openvdb::Int32Tree, false> acc(coarse);
        Label under[DIM * DIM * DIM];
        for (int x = 0; x < span[0]; ++x) {
            for (int y = 0; y < span[1]; ++y) {
                for (int z = 0; z < span[2]; ++z) {
                    under[(x * span[1] + y) * span[2] + z] = acc.getValue(first.offsetBy(x, y, z));
                }
            }
        }
        const Label* values = leaf.buffer().data();
        // The value mask one x slice at a time, a 64-bit word with bit 8y + z for voxel
        // (x, y, z): its active voxels by bit scans, cleared in one store (a mask iterator
        // cost a call per active voxel).
        for (int x = 0; x < DIM; ++x) {
            std::uint64_t& slice = leaf.getValueMask().template getWord<std::uint64_t>(x);
            std::uint64_t changed = slice;
            for (std::uint64_t bits = slice; bits != 0; bits &= bits - 1) {
                const int yz = int(openvdb::util::FindLowestOn(bits));
                const Label c = under[(cell[0][x] * span[1] + cell[1][yz >> 3]) * span[2]
                                      + cell[2][yz & (DIM - 1)]];
                if (values[x * DIM * DIM + yz] == c) changed &= ~(std::uint64_t(1) << yz);
            }
            slice = changed;
        }
    }, threaded);
    openvdb::tools::pruneInactive(fine, threaded);
}

} // namespace

int
subdivisionFactor(const RepairOptions& options)
{
    return options.constraints.empty() ? 5 : 7;
}

RefinedLabels
fattenCriticalElements(const openvdb::Int32Grid::ConstPtr& grid,
                       const CriticalElements& elements, const RepairOptions& options)
{
    const int s = subdivisionFactor(options);
    const Label background = grid->background();
    const bool constrained = !options.constraints.empty();

    RefinedLabels result;
    result.coarse = grid;
    result.subdivision = s;

    // Edges N1 then vertices N2; with constraints faces N1, edges N2, vertices N3.
    auto fine = std::make_shared<openvdb::Int32Tree>(background);
    if (constrained) {
        relabelPass(*fine, elements.faces, s, 1, options, "fattening faces");
        relabelPass(*fine, elements.edges, s, 2, options, "fattening edges");
    } else {
        relabelPass(*fine, elements.edges, s, 1, options, "fattening edges");
    }
    relabelPass(*fine, elements.vertices, s, constrained ? 3 : 2, options, "fattening vertices");
    dropUnchanged(*fine, grid->tree(), s, options.threaded);

    result.fine = openvdb::Int32Grid::create(fine);
    result.fine->setName("fine_labels");
    result.fine->setGridClass(openvdb::GRID_UNKNOWN);
    // Fine voxel f has its centre at coarse index (f + 0.5) / s - 0.5.
    openvdb::math::Transform::Ptr xform = grid->transform().copy();
    xform->preTranslate(openvdb::Vec3d(0.5 / s - 0.5));
    xform->preScale(1.0 / s);
    result.fine->setTransform(xform);

    auto mask = std::make_shared<openvdb::MaskTree>(false);
    markTouchedVoxels(elements.faces, *mask);
    markTouchedVoxels(elements.edges, *mask);
    markTouchedVoxels(elements.vertices, *mask);
    result.subdivided = openvdb::MaskGrid::create(mask);
    result.subdivided->setName("subdivided");
    result.subdivided->setTransform(grid->transform().copy());
    return result;
}

} // namespace vdbi
