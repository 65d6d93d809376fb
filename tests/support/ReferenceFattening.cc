// SPDX-License-Identifier: Apache-2.0

#include "support/ReferenceFattening.h"

#include <openvdb/Exceptions.h>

#include <algorithm>
#include <map>
#include <utility>

namespace vdbi_test {

using openvdb::Coord;
using openvdb::CoordBBox;
using vdbi::Label;

namespace {

const Coord AXIS[3] = {Coord(1, 0, 0), Coord(0, 1, 0), Coord(0, 0, 1)};

/// The coarse labels as a dense box; the background outside.
struct DenseCoarse
{
    CoordBBox box; // empty when every voxel is background
    Coord dims;
    std::vector<Label> labels;
    Label background = 0;

    explicit DenseCoarse(const openvdb::Int32Grid& grid)
        : background(grid.background())
    {
        std::vector<std::pair<CoordBBox, Label>> stored;
        forEachStoredLabel(grid, [&](const CoordBBox& b, Label l) {
            box.expand(b);
            stored.emplace_back(b, l);
        });
        if (box.empty()) return;
        dims = box.dim();
        labels.assign(std::size_t(dims.x()) * dims.y() * dims.z(), background);
        for (const auto& e : stored) {
            for (auto c = e.first.begin(); c; ++c) labels[index(*c)] = e.second;
        }
    }
    std::size_t index(const Coord& c) const
    {
        const Coord d = c - box.min();
        return std::size_t(d.x()) + std::size_t(dims.x()) * (d.y() + std::size_t(dims.y()) * d.z());
    }
    Label at(const Coord& c) const { return box.isInside(c) ? labels[index(c)] : background; }
};

/// Labels for which the edge from @a v along @a a is critical (0, 1 or 2 of them).
std::vector<Label>
edgeCriticalLabels(const DenseCoarse& d, const Coord& v, int a)
{
    const Coord eb = AXIS[(a + 1) % 3], ec = AXIS[(a + 2) % 3];
    // Cyclic order around the edge; the diagonals are (q0, q2) and (q1, q3).
    const Label q0 = d.at(v - eb - ec), q1 = d.at(v - ec), q2 = d.at(v), q3 = d.at(v - eb);
    std::vector<Label> out;
    if (q0 == q2 && q1 != q0 && q3 != q0) out.push_back(q0);
    if (q1 == q3 && q0 != q1 && q2 != q1) out.push_back(q1);
    return out;
}

Label
dominant(const std::vector<Label>& labels, const vdbi::LabelPriority& priority)
{
    Label best = labels.front();
    for (Label l : labels) best = priority.pick(best, l);
    return best;
}

inline Coord
scaled(const Coord& c, int s)
{
    return Coord(c.x() * s, c.y() * s, c.z() * s);
}

ReferenceCritical
findCritical(const DenseCoarse& d, const vdbi::LabelPriority& priority)
{
    ReferenceCritical out;
    if (d.box.empty()) return out;
    // Every edge and grid point with a non-background voxel around it.
    const CoordBBox points(d.box.min(), d.box.max() + Coord(1));
    std::map<std::pair<Coord, int>, std::vector<Label>> criticalEdges;
    for (auto it = points.begin(); it; ++it) {
        for (int a = 0; a < 3; ++a) {
            std::vector<Label> labels = edgeCriticalLabels(d, *it, a);
            if (labels.empty()) continue;
            vdbi::CriticalEdge e;
            e.origin = *it;
            e.axis = a;
            e.label = dominant(labels, priority);
            out.edges.push_back(e);
            criticalEdges[{*it, a}] = std::move(labels);
        }
    }
    for (auto it = points.begin(); it; ++it) {
        const Coord v = *it;
        Label block[8];
        for (int k = 0; k < 8; ++k) {
            block[k] = d.at(v + Coord((k & 1) - 1, ((k >> 1) & 1) - 1, (k >> 2) - 1));
        }
        std::vector<Label> critical;
        bool singular = false;
        // Rule 1: an end point of an edge critical for L.
        for (int a = 0; a < 3; ++a) {
            for (const Coord& origin : {v, v - AXIS[a]}) {
                const auto e = criticalEdges.find({origin, a});
                if (e != criticalEdges.end()) {
                    critical.insert(critical.end(), e->second.begin(), e->second.end());
                }
            }
        }
        // Rule 2: two antipodal voxels of L and six others, or six of L and two antipodal
        // others (block indices k and 7 - k are antipodal).
        for (int k = 0; k < 8; ++k) {
            const Label l = block[k];
            unsigned mask = 0;
            for (int j = 0; j < 8; ++j) mask |= (block[j] == l ? 1u : 0u) << j;
            if ((mask & ((1u << k) - 1u)) != 0) continue; // label seen at a smaller index
            bool antipodal = false;
            for (int j = 0; j < 4; ++j) {
                const unsigned pair = (1u << j) | (1u << (7 - j));
                antipodal = antipodal || mask == pair || mask == (0xFFu & ~pair);
            }
            if (antipodal) {
                critical.push_back(l);
                singular = true;
            }
        }
        if (critical.empty()) continue;
        vdbi::CriticalVertex cv;
        cv.point = v;
        cv.label = dominant(critical, priority);
        cv.isSingular = singular;
        out.vertices.push_back(cv);
    }
    auto edgeLess = [](const vdbi::CriticalEdge& x, const vdbi::CriticalEdge& y) {
        return x.origin != y.origin ? x.origin < y.origin : x.axis < y.axis;
    };
    std::sort(out.edges.begin(), out.edges.end(), edgeLess);
    std::sort(out.vertices.begin(), out.vertices.end(),
        [](const vdbi::CriticalVertex& x, const vdbi::CriticalVertex& y) {
            return x.point < y.point;
        });
    return out;
}

/// Dense fine labels with the per-pass claims of §3.
struct FineWork
{
    DenseFineLabels& fine;
    const vdbi::LabelPriority& priority;
    std::vector<Label> claim;
    std::vector<std::uint8_t> claimed;
    openvdb::MaskGrid::Accessor subdivided;
    int s;

    std::size_t index(const Coord& f) const
    {
        const Coord d = f - fine.origin;
        return std::size_t(d.x())
            + std::size_t(fine.dims.x()) * (d.y() + std::size_t(fine.dims.y()) * d.z());
    }
    void beginPass()
    {
        claim.assign(fine.labels.size(), 0);
        claimed.assign(fine.labels.size(), 0);
    }
    /// Element of label @a l claims the fine voxels [lo, hi) (half-open per axis).
    void claimBox(const Coord& lo, const Coord& hi, Label l)
    {
        for (int z = lo.z(); z < hi.z(); ++z) {
            for (int y = lo.y(); y < hi.y(); ++y) {
                for (int x = lo.x(); x < hi.x(); ++x) {
                    const std::size_t i = index(Coord(x, y, z));
                    claim[i] = claimed[i] ? priority.pick(claim[i], l) : l;
                    claimed[i] = 1;
                }
            }
        }
        // The coarse voxels of the box are subdivided (only adds voxels when k > s).
        const CoordBBox coarse(vdbi::coarseOf(lo, s), vdbi::coarseOf(hi - Coord(1), s));
        for (auto c = coarse.begin(); c; ++c) subdivided.setValueOn(*c);
    }
    void endPass()
    {
        for (std::size_t i = 0; i < claim.size(); ++i) {
            if (claimed[i]) fine.labels[i] = claim[i];
        }
    }
};

} // namespace

std::size_t
ReferenceCritical::singularVertexCount() const
{
    return std::size_t(std::count_if(vertices.begin(), vertices.end(),
        [](const vdbi::CriticalVertex& v) { return v.isSingular; }));
}

ReferenceCritical
referenceCriticalElements(const openvdb::Int32Grid& grid, const vdbi::LabelPriority& priority)
{
    return findCritical(DenseCoarse(grid), priority);
}

openvdb::MaskGrid::Ptr
ReferenceRefined::checkPoints() const
{
    return vdbi_test::checkPoints(*coarse, *subdivided, s);
}

ManifoldReport
ReferenceRefined::check(const CheckOptions& options) const
{
    return checkManifold(fine, *checkPoints(), options);
}

DistanceReport
ReferenceRefined::distance(double bound) const
{
    return checkDistance([this](const Coord& f) { return fine(f); }, *coarse, *subdivided, s,
                         bound);
}

ReferenceRefined
referenceFattening(const openvdb::Int32Grid& grid, const ReferenceParams& params)
{
    const int s = params.s;
    if (s < 1 || params.edgeK < 0 || params.vertexK < 0) {
        OPENVDB_THROW(openvdb::ValueError, "referenceFattening: s = " << s << ", edge N"
            << params.edgeK << ", vertex N" << params.vertexK);
    }
    const DenseCoarse d(grid);
    ReferenceRefined r;
    r.s = s;
    r.coarse = grid.copy(); // shares the tree
    r.subdivided = openvdb::MaskGrid::create(false);
    r.elements = findCritical(d, params.priority);
    r.fine.outside = d.background;
    if (d.box.empty()) return r;

    // Fine box: the coarse box grown by 2 voxels (critical points lie on its closure, their
    // blocks reach one voxel out, and neighbourhoods up to N_s stay inside).
    const Coord lo = d.box.min() - Coord(2), hi = d.box.max() + Coord(3);
    r.fine.origin = scaled(lo, s);
    r.fine.dims = scaled(hi - lo, s);
    r.fine.labels.resize(std::size_t(r.fine.dims.x()) * r.fine.dims.y() * r.fine.dims.z());
    FineWork work{r.fine, params.priority, {}, {}, r.subdivided->getAccessor(), s};
    // Each coarse voxel fills its s^3 subvoxels.
    auto forEachCoarse = [&](auto&& f) {
        for (auto c = CoordBBox(lo, hi - Coord(1)).begin(); c; ++c) {
            const Label label = d.at(*c);
            const Coord base = scaled(*c, s);
            for (int z = 0; z < s; ++z) {
                for (int y = 0; y < s; ++y) {
                    const std::size_t row = work.index(base + Coord(0, y, z));
                    for (int x = 0; x < s; ++x) f(row + std::size_t(x), label);
                }
            }
        }
    };
    forEachCoarse([&](std::size_t i, Label label) { r.fine.labels[i] = label; });

    auto& sub = work.subdivided;
    // Every voxel whose closed cube touches a critical element is subdivided.
    for (const auto& e : r.elements.edges) {
        Coord a = e.origin - Coord(1), b = e.origin;
        a[e.axis] = e.origin[e.axis] - 1;
        b[e.axis] = e.origin[e.axis] + 1;
        for (auto c = CoordBBox(a, b).begin(); c; ++c) sub.setValueOn(*c);
    }
    for (const auto& v : r.elements.vertices) {
        for (auto c = CoordBBox(v.point - Coord(1), v.point).begin(); c; ++c) sub.setValueOn(*c);
    }

    // (1) Critical edges: N_k = [s v_a - k, s v_a + s + k) along the edge, [s v - k, s v + k)
    // across it.
    work.beginPass();
    for (const auto& e : r.elements.edges) {
        const int k = params.edgeK;
        if (k == 0) break;
        Coord elo = scaled(e.origin, s) - Coord(k), ehi = scaled(e.origin, s) + Coord(k);
        ehi[e.axis] = s * e.origin[e.axis] + s + k;
        work.claimBox(elo, ehi, e.label);
    }
    work.endPass();
    // (2) Critical vertices: N_k = [s v - k, s v + k)^3, overwriting the edge pass.
    work.beginPass();
    for (const auto& v : r.elements.vertices) {
        const int k = params.vertexK;
        if (k == 0) break;
        work.claimBox(scaled(v.point, s) - Coord(k), scaled(v.point, s) + Coord(k), v.label);
    }
    work.endPass();

    forEachCoarse([&](std::size_t i, Label label) {
        if (r.fine.labels[i] != label) ++r.relabelled;
    });
    return r;
}

} // namespace vdbi_test
