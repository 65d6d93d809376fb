// SPDX-License-Identifier: Apache-2.0

#include <vdbi/CriticalElements.h>

#include <vdbi/Interruption.h>
#include <vdbi/LabelWindow.h>
#include <vdbi/ParallelRanges.h>

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>

namespace vdbi {

namespace {

// The 2x2x2 block of a grid point v holds the voxels v - 1 + (dx, dy, dz); bit n of a mask is
// the voxel with dx = n & 1, dy = (n >> 1) & 1, dz = (n >> 2) & 1. Its antipode is 7 - n.

/// The four voxels of the block's face with bit @a axis equal to @a side, in cyclic order.
constexpr std::array<int, 4>
faceCycle(int axis, int side)
{
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    const int base = side << axis;
    return {base, base | (1 << b), base | (1 << b) | (1 << c), base | (1 << c)};
}

bool
isDiagonal(unsigned mask, const std::array<int, 4>& cycle)
{
    const unsigned q = ((mask >> cycle[0]) & 1u) | (((mask >> cycle[1]) & 1u) << 1)
        | (((mask >> cycle[2]) & 1u) << 2) | (((mask >> cycle[3]) & 1u) << 3);
    return q == 0b0101u || q == 0b1010u;
}

bool
isAntipodalPair(unsigned mask)
{
    for (int n = 0; n < 4; ++n) {
        if (mask == ((1u << n) | (1u << (7 - n)))) return true;
    }
    return false;
}

/// Per 8-bit mask of one label in a block: is the point critical for it, and by which rule.
struct VertexRule
{
    bool critical = false;
    bool singular = false;
};

struct VertexRuleTable
{
    std::array<VertexRule, 256> rules;
    VertexRuleTable()
    {
        for (unsigned m = 0; m < 256; ++m) {
            VertexRule r;
            for (int axis = 0; axis < 3; ++axis) {
                for (int side = 0; side < 2; ++side) {
                    if (isDiagonal(m, faceCycle(axis, side))) r.critical = true;
                }
            }
            r.singular = isAntipodalPair(m) || isAntipodalPair(~m & 0xffu);
            r.critical = r.critical || r.singular;
            rules[m] = r;
        }
    }
};

const VertexRuleTable&
vertexRules()
{
    static const VertexRuleTable table;
    return table;
}

/// Keeps the label of highest priority among the candidates offered.
class DominantLabel
{
public:
    explicit DominantLabel(const LabelPriority& p): mPriority(&p) {}
    void offer(Label l)
    {
        mLabel = mFound ? mPriority->pick(mLabel, l) : l;
        mFound = true;
    }
    bool found() const { return mFound; }
    Label label() const { return mLabel; }

private:
    const LabelPriority* mPriority;
    Label mLabel = 0;
    bool mFound = false;
};

/// Offers the separator of every constraint whose two labels both occur in @a labels.
void
offerSeparators(const std::vector<SeparationConstraint>& constraints, const Label* labels,
                int count, DominantLabel& dominant)
{
    for (const SeparationConstraint& c : constraints) {
        bool hasA = false, hasB = false;
        for (int i = 0; i < count; ++i) {
            hasA = hasA || labels[i] == c.a;
            hasB = hasB || labels[i] == c.b;
        }
        if (hasA && hasB) dominant.offer(c.separator);
    }
}

struct BlockResult
{
    std::vector<CriticalFace> faces;
    std::vector<CriticalEdge> edges;
    std::vector<CriticalVertex> vertices;
};

/// All critical elements owned by the block at the window's origin.
void
scanBlock(const LabelWindow& w, const RepairOptions& options, BlockResult& out)
{
    const VertexRuleTable& table = vertexRules();
    const bool constrained = !options.constraints.empty();
    const openvdb::Coord& o = w.origin();
    const Label* data = w.data();
    int offsets[8];
    for (int n = 0; n < 8; ++n) {
        offsets[n] = LabelWindow::index(n & 1, (n >> 1) & 1, (n >> 2) & 1);
    }
    const std::array<int, 4> cycles[3] = {faceCycle(0, 1), faceCycle(1, 1), faceCycle(2, 1)};

    for (int i = 0; i < BLOCK_DIM; ++i) {
        for (int j = 0; j < BLOCK_DIM; ++j) {
            // The 2x2x2 blocks of the points (i, j, 0 .. 7) lie in these four rows.
            const int rows[4] = {LabelWindow::index(i, j, 0), LabelWindow::index(i + 1, j, 0),
                LabelWindow::index(i, j + 1, 0), LabelWindow::index(i + 1, j + 1, 0)};
            if (w.isUniform(rows, 4) && !constrained) continue;
            // Per point of the row, the corners labelled like corner 0: all eight points at
            // once (the compiler vectorizes along k).
            const Label* row = data + LabelWindow::index(i, j, 0);
            unsigned firstMasks[BLOCK_DIM] = {};
            for (int n = 0; n < 8; ++n) {
                for (int k = 0; k < BLOCK_DIM; ++k) {
                    firstMasks[k] |= unsigned(row[offsets[n] + k] == row[k]) << n;
                }
            }
            for (int k = 0; k < BLOCK_DIM; ++k) {
                const unsigned firstMask = firstMasks[k];
                if (firstMask == 0xFFu) continue;
                const Label* corner = row + k;
                Label l[8];
                for (int n = 0; n < 8; ++n) l[n] = corner[offsets[n]];
                if (!constrained && !table.rules[firstMask].critical) {
                    // With two labels, a face of the block is diagonal for one when it is
                    // for the other, and the table's rule for one mask covers both: the
                    // point and its edges are not critical. Most points hold two labels.
                    const Label second =
                        l[openvdb::util::FindLowestOn(openvdb::Index32(~firstMask))];
                    bool two = true;
                    for (int n = 0; n < 8; ++n) two = two && (l[n] == l[0] || l[n] == second);
                    if (two) continue;
                }
                const openvdb::Coord v = o.offsetBy(i, j, k);

                // Faces (v, axis) between voxels v - e_axis (bit 7 - 2^axis) and v (bit 7).
                if (constrained) {
                    for (int axis = 0; axis < 3; ++axis) {
                        const Label pair[2] = {l[7 & ~(1 << axis)], l[7]};
                        if (pair[0] == pair[1]) continue;
                        DominantLabel d(options.priority);
                        offerSeparators(options.constraints, pair, 2, d);
                        if (d.found()) out.faces.push_back({v, axis, d.label()});
                    }
                }

                // Edges (v, axis): their four voxels are the block's face with bit axis = 1.
                for (int axis = 0; axis < 3; ++axis) {
                    const std::array<int, 4>& cyc = cycles[axis];
                    const Label r[4] = {l[cyc[0]], l[cyc[1]], l[cyc[2]], l[cyc[3]]};
                    DominantLabel d(options.priority);
                    if (constrained) offerSeparators(options.constraints, r, 4, d);
                    if (!d.found()) {
                        if (r[0] == r[2] && r[1] != r[0] && r[3] != r[0]) d.offer(r[0]);
                        if (r[1] == r[3] && r[0] != r[1] && r[2] != r[1]) d.offer(r[1]);
                    }
                    if (d.found()) out.edges.push_back({v, axis, d.label()});
                }

                // The point itself: every distinct label of the block, by its mask.
                DominantLabel d(options.priority);
                bool singular = false;
                // Bits of the corners whose label has no mask yet; the lowest is the first
                // corner of its label. Most blocks hold two labels: two rounds.
                for (unsigned remaining = 0xFFu; remaining != 0; ) {
                    int n = 0;
                    while (!((remaining >> n) & 1u)) ++n;
                    unsigned mask = 0;
                    for (int p = n; p < 8; ++p) mask |= unsigned(l[p] == l[n]) << p;
                    remaining &= ~mask;
                    const VertexRule& rule = table.rules[mask];
                    if (rule.critical) d.offer(l[n]);
                    singular = singular || rule.singular;
                }
                if (constrained) {
                    DominantLabel c(options.priority);
                    offerSeparators(options.constraints, l, 8, c);
                    if (c.found()) d = c;
                }
                if (d.found()) out.vertices.push_back({v, d.label(), singular});
            }
        }
    }
}

template<typename T>
void
concatenate(std::vector<BlockResult>& blocks, std::vector<T> BlockResult::*member,
            std::vector<T>& out)
{
    std::size_t n = 0;
    for (const BlockResult& b : blocks) n += (b.*member).size();
    out.reserve(n);
    for (BlockResult& b : blocks) {
        out.insert(out.end(), (b.*member).begin(), (b.*member).end());
        std::vector<T>().swap(b.*member);
    }
}

} // namespace

std::size_t
CriticalElements::singularVertexCount() const
{
    return std::size_t(std::count_if(vertices.begin(), vertices.end(),
        [](const CriticalVertex& v) { return v.isSingular; }));
}

CriticalElements
findCriticalElements(const openvdb::Int32Grid& grid, const RepairOptions& options)
{
    checkInterrupt(options.interrupter, "critical elements");
    const std::vector<openvdb::Coord> origins = blockOrigins(grid.tree(), options.threaded);
    std::vector<BlockResult> results(origins.size());
    InterruptFlag interrupt(options.interrupter);

    forEachRange(origins.size(), 16, options.threaded, [&](std::size_t begin, std::size_t end) {
        if (interrupt.poll()) return;
        LabelWindow::Accessor acc(grid.tree());
        LabelWindow window;
        for (std::size_t b = begin; b < end; ++b) {
            window.load(acc, origins[b]);
            scanBlock(window, options, results[b]);
        }
    });
    interrupt.throwIfStopped("critical elements");

    // Blocks are sorted and each block emits in (x, y, z) order of its points, which is not
    // the global coordinate order: sort, so that callers see one canonical list.
    CriticalElements elements;
    concatenate(results, &BlockResult::faces, elements.faces);
    concatenate(results, &BlockResult::edges, elements.edges);
    concatenate(results, &BlockResult::vertices, elements.vertices);
    auto byPlace = [](const auto& a, const auto& b) {
        return a.origin < b.origin || (a.origin == b.origin && a.axis < b.axis);
    };
    auto sort = [&options](auto& list, const auto& less) {
        if (options.threaded) tbb::parallel_sort(list.begin(), list.end(), less);
        else std::sort(list.begin(), list.end(), less);
    };
    sort(elements.faces, byPlace);
    sort(elements.edges, byPlace);
    sort(elements.vertices,
        [](const CriticalVertex& a, const CriticalVertex& b) { return a.point < b.point; });
    return elements;
}

} // namespace vdbi
