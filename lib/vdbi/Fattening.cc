// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Fattening.h>

#include <vdbi/Interruption.h>
#include <vdbi/ParallelRanges.h>

#include <tbb/parallel_invoke.h>
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

/// A neighbourhood to relabel (N_k of an element) and the element's label.
struct Claim
{
    CoordBBox box;
    Label label;
};

/// The claims of the passes, in order: a later pass overwrites what an earlier one wrote.
struct Passes
{
    std::vector<Claim> claims;         ///< pass by pass
    std::vector<std::uint32_t> ends;   ///< the end of each pass in claims

    template<typename Element>
    void add(const std::vector<Element>& elements, int s, int k)
    {
        for (const Element& e : elements) {
            claims.push_back(Claim{neighbourhood(extentOf(e), s, k), e.label});
        }
        ends.push_back(std::uint32_t(claims.size()));
    }
};

/// Keeps active only the voxels of @a leaf whose label differs from their coarse voxel's
/// (read through @a coarse).
template<typename CoarseAccessor>
void
dropUnchanged(LeafT& leaf, CoarseAccessor& coarse, int s)
{
    constexpr int DIM = int(LeafT::DIM);
    // The coarse voxels under the leaf (at most 8 per axis), read once: per fine voxel a
    // table lookup instead of a tree lookup.
    const Coord first = coarseOf(leaf.origin(), s);
    int cell[3][DIM], span[3];
    for (int a = 0; a < 3; ++a) {
        for (int t = 0; t < DIM; ++t) cell[a][t] = floorDiv(leaf.origin()[a] + t, s) - first[a];
        span[a] = cell[a][DIM - 1] + 1;
    }
    Label under[DIM * DIM * DIM];
    for (int x = 0; x < span[0]; ++x) {
        for (int y = 0; y < span[1]; ++y) {
            for (int z = 0; z < span[2]; ++z) {
                under[(x * span[1] + y) * span[2] + z] = coarse.getValue(first.offsetBy(x, y, z));
            }
        }
    }
    const Label* values = leaf.buffer().data();
    // The value mask one x slice at a time, a 64-bit word with bit 8y + z for voxel (x, y, z):
    // its active voxels by bit scans, cleared in one store (a mask iterator cost a call per
    // active voxel).
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
}

/// @brief Runs the passes into @a fine (active voxels: the labels that differ from the
/// coarse ones in @a coarse), one leaf at a time.
/// @details The leaves the claims touch are listed and sorted. Then each leaf, in parallel,
/// is made, takes all passes' claims on it in pass order and drops what equals the coarse
/// label, while its values are in cache: every leaf is written by one thread, so no tree per
/// thread to merge, and the result does not depend on the split.
void
runPasses(openvdb::Int32Tree& fine, const openvdb::Int32Tree& coarse, const Passes& passes,
          int s, const RepairOptions& options)
{
    constexpr int DIM = int(LeafT::DIM);
    // (leaf origin, claim) for every leaf a claim overlaps, by leaf then claim: per claim,
    // its leaves are counted, then written at their offsets.
    const std::vector<Claim>& claims = passes.claims;
    auto leafOf = [](const Coord& c) { return c & ~(DIM - 1); };
    std::vector<std::size_t> firstOf(claims.size() + 1, 0);
    forEachRange(claims.size(), 256, options.threaded, [&](std::size_t begin, std::size_t end) {
        for (std::size_t n = begin; n < end; ++n) {
            const Coord lo = leafOf(claims[n].box.min()), hi = leafOf(claims[n].box.max());
            firstOf[n + 1] = std::size_t((hi.x() - lo.x()) / DIM + 1)
                * std::size_t((hi.y() - lo.y()) / DIM + 1)
                * std::size_t((hi.z() - lo.z()) / DIM + 1);
        }
    });
    for (std::size_t n = 0; n < claims.size(); ++n) firstOf[n + 1] += firstOf[n];
    std::vector<std::pair<Coord, std::uint32_t>> touches(firstOf.back());
    forEachRange(claims.size(), 256, options.threaded, [&](std::size_t begin, std::size_t end) {
        for (std::size_t n = begin; n < end; ++n) {
            const CoordBBox& box = claims[n].box;
            const Coord lo = leafOf(box.min());
            std::size_t t = firstOf[n];
            for (int x = lo.x(); x <= box.max().x(); x += DIM) {
                for (int y = lo.y(); y <= box.max().y(); y += DIM) {
                    for (int z = lo.z(); z <= box.max().z(); z += DIM) {
                        touches[t++] = {Coord(x, y, z), std::uint32_t(n)};
                    }
                }
            }
        }
    });
    if (options.threaded) tbb::parallel_sort(touches.begin(), touches.end());
    else std::sort(touches.begin(), touches.end());
    std::vector<std::size_t> firstTouch; // of each leaf in touches, and the end
    for (std::size_t t = 0; t < touches.size(); ++t) {
        if (t == 0 || touches[t].first != touches[t - 1].first) firstTouch.push_back(t);
    }
    firstTouch.push_back(touches.size());
    const std::size_t leafCount = firstTouch.size() - 1;

    // Every leaf is new (the tree starts empty). The thread that writes a leaf makes it (the
    // first touch of its memory) and keeps it only if a voxel stays active; the leaves kept
    // are added in one thread (the tree's nodes are not thread-safe), so no prune is needed.
    std::vector<std::unique_ptr<LeafT>> made(leafCount);
    InterruptFlag interrupt(options.interrupter);
    forEachRange(leafCount, 64, options.threaded, [&](std::size_t begin, std::size_t end) {
        if (interrupt.poll()) return;
        openvdb::tree::ValueAccessor<const openvdb::Int32Tree, false> coarseAcc(coarse);
        for (std::size_t l = begin; l < end; ++l) {
            auto leaf = std::make_unique<LeafT>(touches[firstTouch[l]].first, fine.background());
            LeafT::NodeMaskType written; // by the current pass
            std::size_t pass = 0;
            for (std::size_t t = firstTouch[l]; t < firstTouch[l + 1]; ++t) {
                const std::uint32_t n = touches[t].second;
                while (n >= passes.ends[pass]) { // the next pass (some may be empty)
                    ++pass;
                    written.setOff();
                }
                writeByPriority(*leaf, written, claims[n].box, claims[n].label,
                                options.priority);
            }
            dropUnchanged(*leaf, coarseAcc, s);
            if (!leaf->isEmpty()) made[l] = std::move(leaf);
        }
    });
    interrupt.throwIfStopped("fattening");
    openvdb::tree::ValueAccessor<openvdb::Int32Tree, false> acc(fine);
    for (std::unique_ptr<LeafT>& leaf : made) {
        if (leaf) acc.addLeaf(leaf.release()); // the tree owns it now
    }
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
    Passes passes;
    if (constrained) {
        passes.add(elements.faces, s, 1);
        passes.add(elements.edges, s, 2);
    } else {
        passes.add(elements.edges, s, 1);
    }
    passes.add(elements.vertices, s, constrained ? 3 : 2);
    auto fine = std::make_shared<openvdb::Int32Tree>(background);
    auto mask = std::make_shared<openvdb::MaskTree>(false);
    auto markSubdivided = [&] {
        markTouchedVoxels(elements.faces, *mask);
        markTouchedVoxels(elements.edges, *mask);
        markTouchedVoxels(elements.vertices, *mask);
    };
    auto relabel = [&] { runPasses(*fine, grid->tree(), passes, s, options); };
    if (options.threaded) {
        // The mask is marked in one thread, beside the passes: they leave a thread idle
        // while they add their leaves.
        tbb::parallel_invoke(relabel, markSubdivided);
    } else {
        relabel();
        markSubdivided();
    }

    result.fine = openvdb::Int32Grid::create(fine);
    result.fine->setName("fine_labels");
    result.fine->setGridClass(openvdb::GRID_UNKNOWN);
    // Fine voxel f has its centre at coarse index (f + 0.5) / s - 0.5.
    openvdb::math::Transform::Ptr xform = grid->transform().copy();
    xform->preTranslate(openvdb::Vec3d(0.5 / s - 0.5));
    xform->preScale(1.0 / s);
    result.fine->setTransform(xform);

    result.subdivided = openvdb::MaskGrid::create(mask);
    result.subdivided->setName("subdivided");
    result.subdivided->setTransform(grid->transform().copy());
    return result;
}

} // namespace vdbi
