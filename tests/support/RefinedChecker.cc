// SPDX-License-Identifier: Apache-2.0

#include "support/RefinedChecker.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <sstream>

namespace vdbi_test {

using openvdb::Coord;
using openvdb::CoordBBox;
using vdbi::Label;

namespace {

inline Coord
scaled(const Coord& c, int s)
{
    return Coord(c.x() * s, c.y() * s, c.z() * s);
}

/// The link graph of one label at one point (see the file comment of the header). Node
/// 2 * axis + (positive ? 1 : 0) is the fine grid edge leaving p along that direction.
struct LinkGraph
{
    std::array<int, 6> degree{};
    std::vector<std::pair<int, int>> edges;
};

LinkGraph
linkGraph(std::uint8_t mask)
{
    LinkGraph g;
    for (int i = 0; i < 8; ++i) {
        for (int a = 0; a < 3; ++a) {
            if ((i >> a) & 1) continue;
            const int j = i | (1 << a);
            if (((mask >> i) & 1) == ((mask >> j) & 1)) continue;
            // The face between block voxels i and j has normal a and p as a corner; it spans
            // the other two axes on the side of the two voxels.
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            const int nb = 2 * b + ((i >> b) & 1), nc = 2 * c + ((i >> c) & 1);
            g.edges.emplace_back(nb, nc);
            ++g.degree[nb];
            ++g.degree[nc];
        }
    }
    return g;
}

bool
isSingleCycle(const LinkGraph& g)
{
    int used = 0, first = -1;
    for (int n = 0; n < 6; ++n) {
        if (g.degree[n] == 0) continue;
        if (g.degree[n] != 2) return false;
        ++used;
        if (first < 0) first = n;
    }
    if (used == 0) return true;
    // All degrees are 2, so the graph is a union of cycles: one cycle iff connected.
    std::array<bool, 6> seen{};
    std::vector<int> stack = {first};
    seen[first] = true;
    int reached = 0;
    while (!stack.empty()) {
        const int n = stack.back();
        stack.pop_back();
        ++reached;
        for (const auto& e : g.edges) {
            const int m = e.first == n ? e.second : (e.second == n ? e.first : -1);
            if (m >= 0 && !seen[m]) {
                seen[m] = true;
                stack.push_back(m);
            }
        }
    }
    return reached == used;
}

struct MaskTables
{
    std::array<bool, 256> manifold{};
    std::array<int, 256> euler4{};
};

const MaskTables&
maskTables()
{
    static const MaskTables tables = [] {
        MaskTables t;
        for (int m = 0; m < 256; ++m) {
            const LinkGraph g = linkGraph(std::uint8_t(m));
            t.manifold[m] = isSingleCycle(g);
            int nodes = 0;
            for (int d : g.degree) nodes += d > 0 ? 1 : 0;
            t.euler4[m] = (g.edges.empty() ? 0 : 4) - 2 * nodes + int(g.edges.size());
        }
        return t;
    }();
    return tables;
}

bool
failureLess(const ManifoldFailure& a, const ManifoldFailure& b)
{
    if (a.point != b.point) return a.point < b.point;
    return a.label < b.label;
}

/// Partial results of one task, merged in a fixed way (the kept failures are the smallest
/// by (point, label), so the report does not depend on the thread count).
struct Accum
{
    std::size_t maxFailures = 16;
    bool euler = true;
    std::size_t points = 0;
    std::size_t failureCount = 0;
    std::vector<ManifoldFailure> failures;
    std::map<Label, std::int64_t> eulerTimes4;

    void trim()
    {
        std::sort(failures.begin(), failures.end(), failureLess);
        if (failures.size() > maxFailures) failures.resize(maxFailures);
    }
    void addFailure(const Coord& p, Label l, std::uint8_t mask)
    {
        ++failureCount;
        failures.push_back({p, l, mask});
        if (failures.size() > 4 * maxFailures + 16) trim();
    }
    void join(const Accum& o)
    {
        points += o.points;
        failureCount += o.failureCount;
        failures.insert(failures.end(), o.failures.begin(), o.failures.end());
        trim();
        for (const auto& e : o.eulerTimes4) eulerTimes4[e.first] += e.second;
    }

    void checkBlock(const Coord& p, const Label* l)
    {
        ++points;
        bool uniform = true;
        for (int i = 1; i < 8; ++i) uniform = uniform && l[i] == l[0];
        if (uniform) return;
        const MaskTables& t = maskTables();
        unsigned done = 0;
        for (int i = 0; i < 8; ++i) {
            if ((done >> i) & 1) continue;
            std::uint8_t mask = 0;
            for (int j = i; j < 8; ++j) {
                if (l[j] == l[i]) mask = std::uint8_t(mask | (1u << j));
            }
            done |= mask;
            if (!t.manifold[mask]) addFailure(p, l[i], mask);
            if (euler && t.euler4[mask] != 0) eulerTimes4[l[i]] += t.euler4[mask];
        }
    }
};

/// Checks the active points of one mask leaf; @a src(f) is the label of fine voxel f.
template<typename Source>
void
checkLeaf(const openvdb::MaskTree::LeafNodeType& leaf, Source& src, Accum& acc)
{
    const Coord o = leaf.origin();
    Label block[8];
    if (leaf.onVoxelCount() * 8 > 729) {
        // Dense enough: read the 9^3 fine voxels around the leaf once.
        std::array<Label, 729> buf;
        for (int z = 0; z < 9; ++z) {
            for (int y = 0; y < 9; ++y) {
                for (int x = 0; x < 9; ++x) {
                    buf[x + 9 * (y + 9 * z)] = src(o + Coord(x - 1, y - 1, z - 1));
                }
            }
        }
        for (auto it = leaf.cbeginValueOn(); it; ++it) {
            const Coord p = it.getCoord();
            const Coord d = p - o; // block voxel p - 1 + e sits at buf[d + e]
            for (int k = 0; k < 8; ++k) {
                block[k] = buf[(d.x() + (k & 1)) + 9 * ((d.y() + ((k >> 1) & 1))
                    + 9 * (d.z() + (k >> 2)))];
            }
            acc.checkBlock(p, block);
        }
    } else {
        for (auto it = leaf.cbeginValueOn(); it; ++it) {
            const Coord p = it.getCoord();
            for (int k = 0; k < 8; ++k) {
                block[k] = src(p + Coord((k & 1) - 1, ((k >> 1) & 1) - 1, (k >> 2) - 1));
            }
            acc.checkBlock(p, block);
        }
    }
}

/// Points in active tiles of @a points (callers may pass masks with tiles).
template<typename Source>
void
checkTiles(const openvdb::MaskGrid& points, Source& src, Accum& acc)
{
    Label block[8];
    auto it = points.tree().cbeginValueOn();
    it.setMaxDepth(openvdb::MaskTree::RootNodeType::LEVEL - 1); // stop above the leaves
    for (; it; ++it) {
        if (!it.isTileValue()) continue;
        const CoordBBox box = it.getBoundingBox();
        for (auto c = box.begin(); c; ++c) {
            const Coord p = *c;
            for (int k = 0; k < 8; ++k) {
                block[k] = src(p + Coord((k & 1) - 1, ((k >> 1) & 1) - 1, (k >> 2) - 1));
            }
            acc.checkBlock(p, block);
        }
    }
}

ManifoldReport
toReport(Accum& acc)
{
    acc.trim();
    ManifoldReport r;
    r.pointsChecked = acc.points;
    r.failureCount = acc.failureCount;
    r.failures = acc.failures;
    r.eulerTimes4 = acc.eulerTimes4;
    return r;
}

template<typename Source>
ManifoldReport
checkSerial(Source& src, const openvdb::MaskGrid& points, const CheckOptions& options)
{
    Accum acc;
    acc.maxFailures = options.maxFailures;
    acc.euler = options.computeEuler;
    for (auto leaf = points.tree().cbeginLeaf(); leaf; ++leaf) checkLeaf(*leaf, src, acc);
    checkTiles(points, src, acc);
    return toReport(acc);
}

/// Calls @a f(c) for every active voxel of @a grid, tiles expanded.
template<typename GridT, typename F>
void
forEachActiveVoxel(const GridT& grid, F&& f)
{
    for (auto it = grid.tree().cbeginValueOn(); it; ++it) {
        if (it.isVoxelValue()) {
            f(it.getCoord(), *it);
        } else {
            const CoordBBox box = it.getBoundingBox();
            for (auto c = box.begin(); c; ++c) f(*c, *it);
        }
    }
}

/// The fine label of @a labels without null grids (an unchanged volume may come without).
struct SafeRefined
{
    vdbi::RefinedLabels r;
    explicit SafeRefined(const vdbi::RefinedLabels& in): r(in)
    {
        if (!r.fine) r.fine = openvdb::Int32Grid::create(r.coarse->background());
        if (!r.subdivided) r.subdivided = openvdb::MaskGrid::create(false);
        if (r.subdivision < 1) r.subdivision = 1;
    }
};

double
setDistance(const Coord& f, const Coord& c, int s)
{
    int gap = 0;
    for (int a = 0; a < 3; ++a) {
        gap = std::max({gap, s * c[a] - (f[a] + 1), f[a] - (s * c[a] + s)});
    }
    return double(gap) / s;
}

double
farDistance(const Coord& f, const Coord& c, int s)
{
    int gap = 0;
    for (int a = 0; a < 3; ++a) {
        gap = std::max({gap, s * c[a] - f[a], (f[a] + 1) - (s * c[a] + s)});
    }
    return double(gap) / s;
}

/// Measures one relabelled fine voxel against the coarse voxels of its new label.
template<typename CoarseAcc>
void
measure(const Coord& f, Label label, CoarseAcc& coarse, int s, double bound, DistanceReport& r)
{
    const Coord home = vdbi::coarseOf(f, s);
    ++r.relabelled;
    double best = 2.0, bestFar = 2.0;
    for (int radius = 1; radius <= 2 && best >= 2.0; ++radius) {
        for (int z = -radius; z <= radius; ++z) {
            for (int y = -radius; y <= radius; ++y) {
                for (int x = -radius; x <= radius; ++x) {
                    const Coord c = home + Coord(x, y, z);
                    if (coarse.getValue(c) != label) continue;
                    best = std::min(best, setDistance(f, c, s));
                    bestFar = std::min(bestFar, farDistance(f, c, s));
                }
            }
        }
    }
    r.maxDistance = std::max(r.maxDistance, best);
    r.maxFarDistance = std::max(r.maxFarDistance, bestFar);
    if (best > bound + 1e-12) {
        ++r.beyondBound;
        if (r.examples.size() < 16) r.examples.push_back(f);
    }
}

} // namespace

bool
isManifoldMask(std::uint8_t mask)
{
    return maskTables().manifold[mask];
}

int
boundaryEulerTimes4(std::uint8_t mask)
{
    return maskTables().euler4[mask];
}

std::int64_t
ManifoldReport::euler(Label label) const
{
    const auto it = eulerTimes4.find(label);
    return it == eulerTimes4.end() ? 0 : it->second / 4;
}

std::string
ManifoldReport::summary() const
{
    std::ostringstream os;
    os << pointsChecked << " points, " << failureCount << " failures";
    if (fineOutsideSubdivided) os << ", " << fineOutsideSubdivided << " fine voxels outside";
    for (const auto& f : failures) {
        os << "; (" << f.point.x() << "," << f.point.y() << "," << f.point.z() << ") label "
           << f.label << " mask " << int(f.mask);
    }
    return os.str();
}

void
forEachStoredLabel(const openvdb::Int32Grid& grid,
                   const std::function<void(const CoordBBox&, Label)>& f)
{
    const Label background = grid.background();
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
        for (auto it = leaf->cbeginValueAll(); it; ++it) {
            if (*it != background) f(CoordBBox(it.getCoord(), it.getCoord()), *it);
        }
    }
    auto it = grid.tree().cbeginValueOn();
    it.setMaxDepth(openvdb::Int32Tree::RootNodeType::LEVEL - 1); // tiles only
    for (; it; ++it) {
        if (it.isTileValue() && *it != background) f(it.getBoundingBox(), *it);
    }
}

openvdb::MaskGrid::Ptr
checkPoints(const openvdb::Int32Grid& coarse, const openvdb::MaskGrid& subdivided, int s)
{
    openvdb::MaskGrid::Ptr points = openvdb::MaskGrid::create(false);
    auto pacc = points->getAccessor();
    forEachActiveVoxel(subdivided, [&](const Coord& c, bool) {
        const Coord base = scaled(c, s);
        for (int z = 0; z <= s; ++z) {
            for (int y = 0; y <= s; ++y) {
                for (int x = 0; x <= s; ++x) pacc.setValueOn(base + Coord(x, y, z));
            }
        }
    });

    // Coarse grid points of the non-background voxels (active or not: a voxel's label is its
    // value), deduplicated on a coarse mask first.
    openvdb::MaskGrid::Ptr corners = openvdb::MaskGrid::create(false);
    auto cacc = corners->getAccessor();
    forEachStoredLabel(coarse, [&](const CoordBBox& box, Label) {
        for (auto c = box.begin(); c; ++c) {
            for (int k = 0; k < 8; ++k) {
                cacc.setValueOn(*c + Coord(k & 1, (k >> 1) & 1, k >> 2));
            }
        }
    });
    for (auto it = corners->tree().cbeginValueOn(); it; ++it) {
        const Coord p = scaled(it.getCoord(), s);
        pacc.setValueOn(p);
        pacc.setValueOn(p + Coord(1, 0, 0));
        pacc.setValueOn(p + Coord(0, 1, 0));
        pacc.setValueOn(p + Coord(0, 0, 1));
    }
    return points;
}

ManifoldReport
checkManifold(const vdbi::RefinedLabels& labels, const CheckOptions& options)
{
    const SafeRefined safe(labels);
    const vdbi::RefinedLabels& r = safe.r;
    const int s = r.subdivision;

    // Subdivided voxels, plus the coarse voxels of any active fine voxel (which should all be
    // subdivided: count the others and visit their closures too).
    openvdb::MaskGrid::Ptr stray = openvdb::MaskGrid::create(false);
    std::size_t outside = 0;
    {
        auto macc = r.subdivided->getConstAccessor();
        auto sacc = stray->getAccessor();
        forEachActiveVoxel(*r.fine, [&](const Coord& f, Label) {
            const Coord c = vdbi::coarseOf(f, s);
            if (!macc.isValueOn(c)) {
                ++outside;
                sacc.setValueOn(c);
            }
        });
    }
    openvdb::MaskGrid::Ptr points = checkPoints(*r.coarse, *r.subdivided, s);
    if (outside > 0) {
        openvdb::MaskGrid::Ptr more = checkPoints(*r.coarse, *stray, s);
        points->tree().topologyUnion(more->tree());
    }

    std::vector<const openvdb::MaskTree::LeafNodeType*> leaves;
    points->tree().getNodes(leaves);
    Accum init;
    init.maxFailures = options.maxFailures;
    init.euler = options.computeEuler;
    auto body = [&](const tbb::blocked_range<std::size_t>& range, Accum acc) {
        vdbi::RefinedLabels::Accessor a(r);
        auto src = [&a](const Coord& f) { return a.fineLabel(f); };
        for (std::size_t i = range.begin(); i != range.end(); ++i) checkLeaf(*leaves[i], src, acc);
        return acc;
    };
    Accum acc;
    if (options.threaded) {
        acc = tbb::parallel_reduce(tbb::blocked_range<std::size_t>(0, leaves.size(), 16), init,
            body, [](Accum a, const Accum& b) { a.join(b); return a; });
    } else {
        acc = body(tbb::blocked_range<std::size_t>(0, leaves.size()), init);
    }
    vdbi::RefinedLabels::Accessor a(r);
    auto src = [&a](const Coord& f) { return a.fineLabel(f); };
    checkTiles(*points, src, acc);
    ManifoldReport report = toReport(acc);
    report.fineOutsideSubdivided = outside;
    return report;
}

ManifoldReport
checkManifold(const FineLabelFn& fineLabel, const openvdb::MaskGrid& points,
              const CheckOptions& options)
{
    return checkSerial(fineLabel, points, options);
}

ManifoldReport
checkManifold(const DenseFineLabels& fineLabels, const openvdb::MaskGrid& points,
              const CheckOptions& options)
{
    return checkSerial(fineLabels, points, options);
}

DistanceReport
checkDistance(const vdbi::RefinedLabels& labels, double bound)
{
    const SafeRefined safe(labels);
    const vdbi::RefinedLabels& r = safe.r;
    DistanceReport report;
    auto coarse = r.coarse->getConstAccessor();
    forEachActiveVoxel(*r.fine, [&](const Coord& f, Label label) {
        if (label == coarse.getValue(vdbi::coarseOf(f, r.subdivision))) return;
        measure(f, label, coarse, r.subdivision, bound, report);
    });
    return report;
}

DistanceReport
checkDistance(const FineLabelFn& fineLabel, const openvdb::Int32Grid& coarseGrid,
              const openvdb::MaskGrid& subdivided, int s, double bound)
{
    DistanceReport report;
    auto coarse = coarseGrid.getConstAccessor();
    forEachActiveVoxel(subdivided, [&](const Coord& c, bool) {
        const Label home = coarse.getValue(c);
        for (int z = 0; z < s; ++z) {
            for (int y = 0; y < s; ++y) {
                for (int x = 0; x < s; ++x) {
                    const Coord f = scaled(c, s) + Coord(x, y, z);
                    const Label label = fineLabel(f);
                    if (label != home) measure(f, label, coarse, s, bound, report);
                }
            }
        }
    });
    return report;
}

std::map<Label, std::int64_t>
refinedVolumes(const vdbi::RefinedLabels& labels)
{
    const SafeRefined safe(labels);
    const vdbi::RefinedLabels& r = safe.r;
    const std::int64_t s = r.subdivision, s3 = s * s * s;
    const Label background = r.coarse->background();
    std::map<Label, std::int64_t> volume;
    forEachStoredLabel(*r.coarse, [&](const CoordBBox& box, Label label) {
        volume[label] += std::int64_t(box.volume()) * s3;
    });
    auto coarse = r.coarse->getConstAccessor();
    forEachActiveVoxel(*r.fine, [&](const Coord& f, Label label) {
        const Label old = coarse.getValue(vdbi::coarseOf(f, r.subdivision));
        if (old == label) return;
        --volume[old];
        ++volume[label];
    });
    volume.erase(background);
    for (auto it = volume.begin(); it != volume.end();) {
        it = it->second == 0 ? volume.erase(it) : std::next(it);
    }
    return volume;
}

} // namespace vdbi_test
