// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Fattening.h>

#include <vdbi/Interruption.h>

#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>

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

/// Keeps, per voxel, the label of highest priority written there. The choice is a total
/// order, so the outcome is the same for any order of writes and any split among threads.
class PriorityWriter
{
public:
    PriorityWriter(openvdb::Int32Tree& tree, const LabelPriority& priority)
        : mAcc(tree), mPriority(&priority) {}

    /// Writes @a label into every voxel of @a box, leaf by leaf through the leaf buffers.
    void write(const CoordBBox& box, Label label)
    {
        using LeafT = openvdb::Int32Tree::LeafNodeType;
        constexpr int MASK = int(LeafT::DIM) - 1;
        const Coord& lo = box.min();
        const Coord& hi = box.max();
        for (int x0 = lo.x(); x0 <= hi.x(); x0 = (x0 & ~MASK) + int(LeafT::DIM)) {
            for (int y0 = lo.y(); y0 <= hi.y(); y0 = (y0 & ~MASK) + int(LeafT::DIM)) {
                for (int z0 = lo.z(); z0 <= hi.z(); z0 = (z0 & ~MASK) + int(LeafT::DIM)) {
                    // The part of the box inside the leaf that holds (x0, y0, z0).
                    const Coord first(x0, y0, z0);
                    const Coord last(std::min(hi.x(), x0 | MASK), std::min(hi.y(), y0 | MASK),
                                     std::min(hi.z(), z0 | MASK));
                    LeafT* leaf = mAcc.touchLeaf(first);
                    Label* values = leaf->buffer().data();
                    auto& active = leaf->getValueMask();
                    for (int x = first.x(); x <= last.x(); ++x) {
                        for (int y = first.y(); y <= last.y(); ++y) {
                            openvdb::Index i = LeafT::coordToOffset(Coord(x, y, first.z()));
                            for (int z = first.z(); z <= last.z(); ++z, ++i) {
                                values[i] = active.isOn(i) ? mPriority->pick(values[i], label)
                                                           : label;
                                active.setOn(i);
                            }
                        }
                    }
                }
            }
        }
    }

private:
    openvdb::tree::ValueAccessor<openvdb::Int32Tree, false> mAcc;
    const LabelPriority* mPriority;
};

/// Moves the leaves of @a from into @a into; where @a into has a leaf already, @a combine
/// (old value, new value) gives each voxel that both hold. Leaves @a from empty. Only adding
/// leaves changes the tree: that is serial, combining the overlapping leaves is not.
template<typename Combine>
void
mergeLeaves(openvdb::Int32Tree& into, openvdb::Int32Tree& from, const Combine& combine,
            bool threaded)
{
    using LeafT = openvdb::Int32Tree::LeafNodeType;
    std::vector<LeafT*> leaves;
    from.stealNodes(leaves);
    std::vector<std::pair<LeafT*, LeafT*>> overlaps; // (leaf of into, leaf of from)
    openvdb::tree::ValueAccessor<openvdb::Int32Tree, false> acc(into);
    for (LeafT* leaf : leaves) {
        if (LeafT* target = acc.probeLeaf(leaf->origin())) overlaps.emplace_back(target, leaf);
        else acc.addLeaf(leaf);
    }
    auto merge = [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t n = range.begin(); n < range.end(); ++n) {
            LeafT& target = *overlaps[n].first;
            const LeafT* leaf = overlaps[n].second;
            Label* to = target.buffer().data();
            const Label* values = leaf->buffer().data();
            for (auto it = leaf->getValueMask().beginOn(); it; ++it) {
                const openvdb::Index i = it.pos();
                to[i] = target.isValueOn(i) ? combine(to[i], values[i]) : values[i];
                target.getValueMask().setOn(i);
            }
            delete leaf;
        }
    };
    const tbb::blocked_range<std::size_t> all(0, overlaps.size(), 16);
    if (threaded) tbb::parallel_for(all, merge);
    else merge(all);
}

/// Merges @a from into @a into by priority; leaves @a from empty.
void
mergeByPriority(openvdb::Int32Tree& into, openvdb::Int32Tree& from, const LabelPriority& p,
                bool threaded)
{
    mergeLeaves(into, from, [&p](Label a, Label b) { return p.pick(a, b); }, threaded);
}

/// Relabels N_k of every element of one kind; returns the labels written (active voxels).
template<typename Element>
openvdb::Int32Tree::Ptr
relabelPass(const std::vector<Element>& elements, int s, int k, const RepairOptions& options,
            Label background, const char* stage)
{
    tbb::enumerable_thread_specific<openvdb::Int32Tree::Ptr> local(
        [background] { return std::make_shared<openvdb::Int32Tree>(background); });
    InterruptFlag interrupt(options.interrupter);

    auto relabel = [&](const tbb::blocked_range<std::size_t>& range) {
        if (interrupt.poll()) return;
        PriorityWriter writer(*local.local(), options.priority);
        for (std::size_t n = range.begin(); n < range.end(); ++n) {
            writer.write(neighbourhood(extentOf(elements[n]), s, k), elements[n].label);
        }
    };
    const tbb::blocked_range<std::size_t> all(0, elements.size(), 64);
    if (options.threaded) tbb::parallel_for(all, relabel);
    else relabel(all);
    interrupt.throwIfStopped(stage);

    auto result = std::make_shared<openvdb::Int32Tree>(background);
    for (auto& tree : local) {
        mergeByPriority(*result, *tree, options.priority, options.threaded);
    }
    return result;
}

/// Later passes overwrite earlier ones; leaves @a from empty.
void
overwrite(openvdb::Int32Tree& into, openvdb::Int32Tree& from, bool threaded)
{
    mergeLeaves(into, from, [](Label, Label later) { return later; }, threaded);
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
    using LeafT = openvdb::Int32Tree::LeafNodeType;
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
        auto& active = leaf.getValueMask();
        const Label* values = leaf.buffer().data();
        for (auto it = active.beginOn(); it; ++it) {
            const Coord xyz = LeafT::offsetToLocalCoord(it.pos());
            const Label c = under[(cell[0][xyz.x()] * span[1] + cell[1][xyz.y()]) * span[2]
                                  + cell[2][xyz.z()]];
            if (values[it.pos()] == c) active.setOff(it.pos());
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
    openvdb::Int32Tree::Ptr fine;
    if (constrained) {
        fine = relabelPass(elements.faces, s, 1, options, background, "fattening faces");
        overwrite(*fine, *relabelPass(elements.edges, s, 2, options, background,
            "fattening edges"), options.threaded);
    } else {
        fine = relabelPass(elements.edges, s, 1, options, background, "fattening edges");
    }
    overwrite(*fine, *relabelPass(elements.vertices, s, constrained ? 3 : 2, options,
        background, "fattening vertices"), options.threaded);
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
