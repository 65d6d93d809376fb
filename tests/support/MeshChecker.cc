// SPDX-License-Identifier: Apache-2.0

#include "support/MeshChecker.h"

#include "support/RefinedChecker.h" // forEachStoredLabel

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <set>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace vdbi_test {

using openvdb::Coord;
using vdbi::Label;

namespace {

using Id = std::uint32_t;
using Tri = std::array<Id, 3>;

inline std::uint64_t
edgeKey(Id u, Id v)
{
    return (std::uint64_t(u) << 32) | v;
}

inline std::uint64_t
undirectedKey(Id u, Id v)
{
    return u < v ? edgeKey(u, v) : edgeKey(v, u);
}

struct TriHash
{
    std::size_t operator()(const Tri& t) const
    {
        std::uint64_t h = t[0];
        h = h * 0x9E3779B97F4A7C15ull ^ t[1];
        h = h * 0x9E3779B97F4A7C15ull ^ t[2];
        return std::size_t(h ^ (h >> 29));
    }
};

struct KeyHash
{
    std::size_t operator()(const vdbi::VertexKey& k) const
    {
        std::uint64_t h = std::uint64_t(k[0]);
        h = h * 0x9E3779B97F4A7C15ull ^ std::uint64_t(k[1]);
        h = h * 0x9E3779B97F4A7C15ull ^ std::uint64_t(k[2]);
        return std::size_t(h ^ (h >> 31));
    }
};

Tri
sorted(Tri t)
{
    std::sort(t.begin(), t.end());
    return t;
}

/// Fans around every vertex of a triangle set. A triangle (u, v, w) contributes the link edge
/// v-w at u (and w-u at v, u-v at w). The link of a vertex is a graph on its neighbours;
/// with every edge in at most 2 triangles its components are paths (open fans) or cycles
/// (closed fans).
struct FanCount
{
    std::size_t oneFan = 0;         ///< exactly one fan (closed or open)
    std::size_t oneClosedFan = 0;   ///< exactly one closed fan
    std::size_t severalOpenFans = 0;
    std::size_t bad = 0;            ///< a closed fan plus more, or a link node of degree > 2
};

FanCount
countFans(const std::vector<Tri>& tris)
{
    struct Entry { Id v, a, b; };
    std::vector<Entry> entries;
    entries.reserve(tris.size() * 3);
    for (const Tri& t : tris) {
        entries.push_back({t[0], t[1], t[2]});
        entries.push_back({t[1], t[2], t[0]});
        entries.push_back({t[2], t[0], t[1]});
    }
    std::sort(entries.begin(), entries.end(),
        [](const Entry& x, const Entry& y) { return x.v < y.v; });
    FanCount out;
    std::vector<Id> nodes;
    std::vector<int> parent, degree;
    std::vector<char> closedFlag;
    for (std::size_t i = 0; i < entries.size();) {
        std::size_t j = i;
        while (j < entries.size() && entries[j].v == entries[i].v) ++j;
        nodes.clear();
        for (std::size_t k = i; k < j; ++k) {
            nodes.push_back(entries[k].a);
            nodes.push_back(entries[k].b);
        }
        std::sort(nodes.begin(), nodes.end());
        nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
        parent.resize(nodes.size());
        std::iota(parent.begin(), parent.end(), 0);
        degree.assign(nodes.size(), 0);
        auto find = [&](int x) {
            while (parent[x] != x) x = parent[x] = parent[parent[x]];
            return x;
        };
        auto local = [&](Id n) {
            return int(std::lower_bound(nodes.begin(), nodes.end(), n) - nodes.begin());
        };
        for (std::size_t k = i; k < j; ++k) {
            const int a = local(entries[k].a), b = local(entries[k].b);
            ++degree[a];
            ++degree[b];
            parent[find(a)] = find(b);
        }
        // Per component: closed when every node has degree 2.
        // closedFlag[root]: 0 not a root, 1 closed so far, 2 open.
        closedFlag.assign(nodes.size(), 0);
        bool complexEdge = false;
        for (std::size_t n = 0; n < nodes.size(); ++n) {
            char& flag = closedFlag[std::size_t(find(int(n)))];
            if (flag == 0) flag = 1;
            if (degree[n] != 2) flag = 2;
            if (degree[n] > 2) complexEdge = true;
        }
        std::size_t components = 0, closedCount = 0;
        for (char flag : closedFlag) {
            components += flag != 0 ? 1 : 0;
            closedCount += flag == 1 ? 1 : 0;
        }
        if (complexEdge || (components > 1 && closedCount > 0)) {
            ++out.bad;
        } else if (components == 1) {
            ++out.oneFan;
            if (closedCount == 1) ++out.oneClosedFan;
        } else {
            ++out.severalOpenFans;
        }
        i = j;
    }
    return out;
}

void
note(MeshReport& r, const std::string& message)
{
    if (r.messages.size() < 12) r.messages.push_back(message);
}

std::int64_t
gcd64(std::int64_t a, std::int64_t b)
{
    a = a < 0 ? -a : a;
    b = b < 0 ? -b : b;
    while (b != 0) {
        const std::int64_t t = a % b;
        a = b;
        b = t;
    }
    return a;
}

} // namespace

bool
MeshReport::ok() const
{
    if (structureErrors || duplicatePoints || duplicateTrianglesGlobal || tJunctions) return false;
    for (const auto& p : patchReports) {
        if (!p.ok()) return false;
    }
    for (const auto& l : labels) {
        if (!l.second.closed()) return false;
    }
    return true;
}

std::size_t
MeshReport::sum(std::size_t PatchReport::*counter) const
{
    std::size_t n = 0;
    for (const auto& p : patchReports) n += p.*counter;
    return n;
}

std::string
MeshReport::summary() const
{
    std::ostringstream os;
    os << points << " points, " << triangles << " triangles, " << patches << " patches";
    if (structureErrors) os << "; " << structureErrors << " structure errors";
    if (duplicatePoints) os << "; " << duplicatePoints << " duplicate points";
    if (duplicateTrianglesGlobal) os << "; " << duplicateTrianglesGlobal << " duplicate triangles";
    if (tJunctions) os << "; " << tJunctions << " T-junctions";
    for (const auto& p : patchReports) {
        if (p.ok()) continue;
        os << "; patch (" << p.a << "," << p.b << "): degenerate " << p.degenerateTriangles
           << ", duplicate " << p.duplicateTriangles << ", repeated directed edges "
           << p.duplicateDirectedEdges << ", non-manifold edges " << p.nonManifoldEdges
           << ", unmatched boundary edges " << p.unmatchedBoundaryEdges << ", bad fans "
           << p.closedFanPlusMore;
    }
    for (const auto& e : labels) {
        const LabelReport& l = e.second;
        if (l.closed()) continue;
        os << "; label " << l.label << ": open edges " << l.openEdges << ", orientation errors "
           << l.orientationErrors << ", bad fans " << l.badFanVertices;
    }
    for (const auto& m : messages) os << "; " << m;
    return os.str();
}

MeshReport
checkMesh(const vdbi::InterfaceMesh& mesh, bool useKeys)
{
    MeshReport r;
    r.points = mesh.points.size();
    r.triangles = mesh.triangles.size();
    r.patches = mesh.patches.size();
    r.keyScale = mesh.keyScale;
    const bool haveKeys = !mesh.pointKeys.empty();
    if (haveKeys && mesh.pointKeys.size() != mesh.points.size()) {
        ++r.structureErrors;
        note(r, "pointKeys and points differ in size");
    }
    r.usedKeys = useKeys && haveKeys && mesh.pointKeys.size() == mesh.points.size();

    // Vertex identity.
    std::vector<Id> id(mesh.points.size());
    if (r.usedKeys) {
        std::unordered_map<vdbi::VertexKey, Id, KeyHash> first;
        first.reserve(mesh.points.size());
        for (std::size_t i = 0; i < mesh.points.size(); ++i) {
            const auto ins = first.emplace(mesh.pointKeys[i], Id(i));
            id[i] = ins.first->second;
            if (!ins.second) ++r.duplicatePoints;
        }
    } else {
        std::iota(id.begin(), id.end(), Id(0));
    }

    // Patch layout: sorted by (a, b) with a < b, contiguous, covering all triangles.
    std::size_t next = 0;
    for (std::size_t p = 0; p < mesh.patches.size(); ++p) {
        const auto& patch = mesh.patches[p];
        if (!(patch.a < patch.b) || patch.firstTriangle != next
            || (p > 0 && !(std::make_pair(mesh.patches[p - 1].a, mesh.patches[p - 1].b)
                           < std::make_pair(patch.a, patch.b)))) {
            ++r.structureErrors;
            note(r, "patch " + std::to_string(p) + " out of order or not contiguous");
        }
        next = patch.firstTriangle + patch.triangleCount;
    }
    if (next != mesh.triangles.size()) {
        ++r.structureErrors;
        note(r, "patches do not cover the triangles exactly");
    }
    std::vector<Tri> tris(mesh.triangles.size());
    std::vector<bool> used(mesh.points.size(), false);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const auto v = mesh.triangles[t][k];
            if (v >= mesh.points.size()) {
                ++r.structureErrors;
                note(r, "triangle " + std::to_string(t) + " has a bad index");
                tris[t][k] = 0;
            } else {
                tris[t][k] = id[v];
                used[v] = true;
            }
        }
    }
    r.unusedPoints = std::size_t(std::count(used.begin(), used.end(), false));
    if (r.structureErrors) return r;

    // Per patch. Edges are sorted lists of 64-bit keys (hash maps cost 10x more here).
    std::vector<Tri> allSorted;
    allSorted.reserve(tris.size());
    std::vector<std::pair<std::uint64_t, std::uint32_t>> boundary; // (edge, patch)
    for (std::size_t p = 0; p < mesh.patches.size(); ++p) {
        const auto& patch = mesh.patches[p];
        PatchReport pr;
        pr.a = patch.a;
        pr.b = patch.b;
        pr.triangles = patch.triangleCount;
        std::vector<Tri> good, seen;
        std::vector<std::uint64_t> directed, undirected;
        const std::size_t end = patch.firstTriangle + patch.triangleCount;
        for (std::size_t t = patch.firstTriangle; t < end; ++t) {
            const Tri& x = tris[t];
            if (x[0] == x[1] || x[1] == x[2] || x[0] == x[2]) {
                ++pr.degenerateTriangles;
                continue;
            }
            seen.push_back(sorted(x));
            good.push_back(x);
        }
        std::sort(seen.begin(), seen.end());
        pr.duplicateTriangles = std::size_t(seen.end() - std::unique(seen.begin(), seen.end()));
        allSorted.insert(allSorted.end(), seen.begin(), seen.end());
        if (pr.duplicateTriangles) {
            // Keep one triangle of every vertex set for the edge and fan checks.
            std::vector<Tri> kept, keys;
            for (const Tri& x : good) {
                const Tri k = sorted(x);
                if (!std::binary_search(keys.begin(), keys.end(), k)) {
                    keys.insert(std::upper_bound(keys.begin(), keys.end(), k), k);
                    kept.push_back(x);
                }
            }
            good.swap(kept);
        }
        for (const Tri& x : good) {
            if (r.usedKeys) {
                const auto& k0 = mesh.pointKeys[x[0]];
                const auto& k1 = mesh.pointKeys[x[1]];
                const auto& k2 = mesh.pointKeys[x[2]];
                const std::int64_t u[3] = {k1[0] - k0[0], k1[1] - k0[1], k1[2] - k0[2]};
                const std::int64_t v[3] = {k2[0] - k0[0], k2[1] - k0[1], k2[2] - k0[2]};
                const std::int64_t n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                                           u[0] * v[1] - u[1] * v[0]};
                const int nonZero = (n[0] != 0) + (n[1] != 0) + (n[2] != 0);
                if (nonZero == 1) {
                    pr.twiceAreaKeys += std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]);
                } else {
                    ++pr.skewTriangles;
                }
            }
            for (int k = 0; k < 3; ++k) {
                directed.push_back(edgeKey(x[k], x[(k + 1) % 3]));
                undirected.push_back(undirectedKey(x[k], x[(k + 1) % 3]));
            }
        }
        std::sort(directed.begin(), directed.end());
        for (std::size_t i = 1; i < directed.size(); ++i) {
            if (directed[i] == directed[i - 1] && (i < 2 || directed[i - 2] != directed[i])) {
                ++pr.duplicateDirectedEdges;
            }
        }
        std::sort(undirected.begin(), undirected.end());
        for (std::size_t i = 0; i < undirected.size();) {
            std::size_t j = i;
            while (j < undirected.size() && undirected[j] == undirected[i]) ++j;
            if (j - i == 1) {
                ++pr.boundaryEdges;
                boundary.emplace_back(undirected[i], std::uint32_t(p));
            } else if (j - i > 2) {
                ++pr.nonManifoldEdges;
            }
            i = j;
        }
        const FanCount fans = countFans(good);
        pr.closedFanPlusMore = fans.bad;
        pr.severalOpenFans = fans.severalOpenFans;
        r.patchReports.push_back(pr);
    }
    std::sort(allSorted.begin(), allSorted.end());
    r.duplicateTrianglesGlobal =
        std::size_t(allSorted.end() - std::unique(allSorted.begin(), allSorted.end()));
    // Across patches: a patch's boundary is made of other patches' boundaries (feature curves
    // where 3 or 4 interface faces meet).
    std::sort(boundary.begin(), boundary.end());
    for (std::size_t i = 0; i < boundary.size();) {
        std::size_t j = i;
        while (j < boundary.size() && boundary[j].first == boundary[i].first) ++j;
        if (j - i < 2) ++r.patchReports[boundary[i].second].unmatchedBoundaryEdges;
        i = j;
    }

    // Per label: the union of its patches, flipped where it is the b side, must be closed.
    std::map<Label, std::vector<Tri>> byLabel;
    for (const auto& patch : mesh.patches) {
        const std::size_t end = patch.firstTriangle + patch.triangleCount;
        for (std::size_t t = patch.firstTriangle; t < end; ++t) {
            const Tri& x = tris[t];
            byLabel[patch.a].push_back(x);
            byLabel[patch.b].push_back({x[0], x[2], x[1]});
        }
    }
    for (const auto& entry : byLabel) {
        LabelReport lr;
        lr.label = entry.first;
        const std::vector<Tri>& lt = entry.second;
        lr.triangles = lt.size();
        // (undirected edge, 1 if it runs from the smaller id) per triangle side.
        std::vector<std::uint64_t> sides;
        std::vector<Id> vertices;
        sides.reserve(lt.size() * 3);
        for (const Tri& x : lt) {
            for (int k = 0; k < 3; ++k) {
                vertices.push_back(x[k]);
                const Id u = x[k], v = x[(k + 1) % 3];
                sides.push_back((undirectedKey(u, v) << 1) | (u < v ? 1u : 0u));
            }
        }
        std::sort(vertices.begin(), vertices.end());
        vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
        std::sort(sides.begin(), sides.end());
        std::size_t edgeCount = 0;
        for (std::size_t i = 0; i < sides.size();) {
            std::size_t j = i;
            while (j < sides.size() && (sides[j] >> 1) == (sides[i] >> 1)) ++j;
            ++edgeCount;
            if (j - i != 2) {
                ++lr.openEdges;
            } else if ((sides[i] & 1) == (sides[i + 1] & 1)) {
                ++lr.orientationErrors; // both sides run the same way
            }
            i = j;
        }
        const FanCount fans = countFans(lt);
        lr.badFanVertices = vertices.size() - fans.oneClosedFan;
        lr.vertices = vertices.size();
        lr.edges = edgeCount;
        lr.euler = std::int64_t(lr.vertices) - std::int64_t(lr.edges) + std::int64_t(lr.triangles);
        // Volume by the divergence theorem: sum of det(p0, p1, p2) / 6.
        if (r.usedKeys) {
            __int128 six = 0;
            for (const Tri& x : lt) {
                const auto& a = mesh.pointKeys[x[0]];
                const auto& b = mesh.pointKeys[x[1]];
                const auto& c = mesh.pointKeys[x[2]];
                six += __int128(a[0]) * (__int128(b[1]) * c[2] - __int128(b[2]) * c[1])
                     - __int128(a[1]) * (__int128(b[0]) * c[2] - __int128(b[2]) * c[0])
                     + __int128(a[2]) * (__int128(b[0]) * c[1] - __int128(b[1]) * c[0]);
            }
            lr.sixVolumeKeys = six;
            const double k = mesh.keyScale > 0 ? mesh.keyScale : 1;
            lr.volume = double(six) / 6.0 / (k * k * k);
        } else {
            double six = 0;
            for (const Tri& x : lt) {
                const auto& a = mesh.points[x[0]];
                const auto& b = mesh.points[x[1]];
                const auto& c = mesh.points[x[2]];
                six += a.dot(b.cross(c));
            }
            lr.volume = six / 6.0;
        }
        r.labels[lr.label] = lr;
    }

    // T-junctions: a vertex strictly inside a mesh edge is a lattice point on the segment
    // between the edge's keys (exact).
    if (r.usedKeys) {
        std::vector<vdbi::VertexKey> keys(mesh.pointKeys.begin(), mesh.pointKeys.end());
        std::sort(keys.begin(), keys.end());
        std::vector<std::uint64_t> edges;
        edges.reserve(tris.size() * 3);
        for (const Tri& x : tris) {
            for (int k = 0; k < 3; ++k) edges.push_back(undirectedKey(x[k], x[(k + 1) % 3]));
        }
        std::sort(edges.begin(), edges.end());
        edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
        for (std::uint64_t e : edges) {
            const auto& a = mesh.pointKeys[e >> 32];
            const auto& b = mesh.pointKeys[e & 0xFFFFFFFFu];
            const std::int64_t d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            const std::int64_t g = gcd64(gcd64(d[0], d[1]), d[2]);
            for (std::int64_t t = 1; t < g; ++t) {
                const vdbi::VertexKey q = {a[0] + t * d[0] / g, a[1] + t * d[1] / g,
                                           a[2] + t * d[2] / g};
                if (std::binary_search(keys.begin(), keys.end(), q)) {
                    ++r.tJunctions;
                    break;
                }
            }
        }
    }
    return r;
}

bool
volumeEqualsFineVoxels(const LabelReport& label, std::int64_t fineVoxels)
{
    return label.sixVolumeKeys == __int128(fineVoxels) * 6 * 8;
}

namespace {

const Coord AXIS[3] = {Coord(1, 0, 0), Coord(0, 1, 0), Coord(0, 0, 1)};

/// Calls f(c, axis, lower, upper) once for every coarse face (c, axis) between voxel c - e_axis
/// (label lower) and voxel c (label upper) whose labels differ.
template<typename F>
void
forEachInterfaceFace(const openvdb::Int32Grid& grid, F&& f)
{
    const Label background = grid.background();
    auto acc = grid.getConstAccessor();
    forEachStoredLabel(grid, [&](const openvdb::CoordBBox& box, Label label) {
        for (auto it = box.begin(); it; ++it) {
            const Coord c = *it;
            for (int a = 0; a < 3; ++a) {
                const Label below = acc.getValue(c - AXIS[a]);
                if (below != label) f(c, a, below, label);
                // The face above belongs to the voxel above unless that one is never visited.
                const Label above = acc.getValue(c + AXIS[a]);
                if (above == background) f(c + AXIS[a], a, label, above);
            }
        }
    });
}

} // namespace

vdbi::InterfaceMesh
plainInterfaceMesh(const openvdb::Int32Grid& grid)
{
    std::map<std::pair<Label, Label>, std::vector<std::array<vdbi::VertexKey, 3>>> byPair;
    forEachInterfaceFace(grid, [&](const Coord& c, int a, Label lower, Label upper) {
        const int b = (a + 1) % 3, d = (a + 2) % 3;
        const Coord q[4] = {c, c + AXIS[b], c + AXIS[b] + AXIS[d], c + AXIS[d]};
        vdbi::VertexKey k[4];
        for (int i = 0; i < 4; ++i) k[i] = {2 * q[i].x(), 2 * q[i].y(), 2 * q[i].z()};
        // q0 q1 q2 q3 is counter-clockwise seen from +axis; the normal must point from the
        // smaller label into the larger.
        const bool up = lower < upper;
        auto& list = byPair[{std::min(lower, upper), std::max(lower, upper)}];
        if (up) {
            list.push_back({k[0], k[1], k[2]});
            list.push_back({k[0], k[2], k[3]});
        } else {
            list.push_back({k[0], k[2], k[1]});
            list.push_back({k[0], k[3], k[2]});
        }
    });
    vdbi::InterfaceMesh mesh;
    mesh.keyScale = 2;
    std::map<vdbi::VertexKey, unsigned> index;
    for (const auto& entry : byPair) {
        vdbi::InterfacePatch patch;
        patch.a = entry.first.first;
        patch.b = entry.first.second;
        patch.firstTriangle = mesh.triangles.size();
        for (const auto& t : entry.second) {
            openvdb::Vec3I tri;
            for (int k = 0; k < 3; ++k) {
                const auto ins = index.emplace(t[k], unsigned(mesh.points.size()));
                if (ins.second) {
                    mesh.pointKeys.push_back(t[k]);
                    mesh.points.emplace_back(t[k][0] / 2.0, t[k][1] / 2.0, t[k][2] / 2.0);
                }
                tri[k] = ins.first->second;
            }
            mesh.triangles.push_back(tri);
        }
        patch.triangleCount = mesh.triangles.size() - patch.firstTriangle;
        mesh.patches.push_back(patch);
    }
    return mesh;
}

std::map<std::pair<Label, Label>, std::size_t>
interfaceFacesPerPair(const openvdb::Int32Grid& grid)
{
    std::map<std::pair<Label, Label>, std::size_t> out;
    forEachInterfaceFace(grid, [&](const Coord&, int, Label lower, Label upper) {
        ++out[{std::min(lower, upper), std::max(lower, upper)}];
    });
    return out;
}

std::string
compareWithPlainFaces(const vdbi::InterfaceMesh& mesh, const openvdb::Int32Grid& grid)
{
    if (mesh.pointKeys.size() != mesh.points.size() || mesh.keyScale <= 0) return "no keys";
    const std::int64_t K = mesh.keyScale;
    // Expected: face (corner, axis) -> (a, b, sign of the normal along the axis).
    struct Expect { Label a, b; int sign; int found = 0; std::set<vdbi::VertexKey> corners; };
    std::map<std::pair<Coord, int>, Expect> faces;
    forEachInterfaceFace(grid, [&](const Coord& c, int axis, Label lower, Label upper) {
        Expect e;
        e.a = std::min(lower, upper);
        e.b = std::max(lower, upper);
        e.sign = lower < upper ? 1 : -1;
        faces[{c, axis}] = e;
    });
    std::ostringstream os;
    for (const auto& patch : mesh.patches) {
        const std::size_t end = patch.firstTriangle + patch.triangleCount;
        for (std::size_t t = patch.firstTriangle; t < end; ++t) {
            vdbi::VertexKey k[3];
            for (int i = 0; i < 3; ++i) k[i] = mesh.pointKeys[mesh.triangles[t][i]];
            int axis = -1;
            for (int a = 0; a < 3; ++a) {
                if (k[0][a] == k[1][a] && k[1][a] == k[2][a]) axis = a;
            }
            if (axis < 0 || k[0][axis] % K != 0) {
                os << "triangle " << t << " is not in a coarse face plane";
                return os.str();
            }
            std::int64_t lo[3], hi[3];
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min({k[0][a], k[1][a], k[2][a]});
                hi[a] = std::max({k[0][a], k[1][a], k[2][a]});
            }
            const int b = (axis + 1) % 3, d = (axis + 2) % 3;
            if (hi[b] - lo[b] != K || hi[d] - lo[d] != K || lo[b] % K != 0 || lo[d] % K != 0) {
                os << "triangle " << t << " is not half of a coarse face";
                return os.str();
            }
            // Twice the signed area along the axis: +-K^2 for half a face.
            const std::int64_t u0 = k[1][b] - k[0][b], u1 = k[1][d] - k[0][d];
            const std::int64_t v0 = k[2][b] - k[0][b], v1 = k[2][d] - k[0][d];
            const std::int64_t twiceArea = u0 * v1 - u1 * v0;
            if (twiceArea != K * K && twiceArea != -K * K) {
                os << "triangle " << t << " does not cover half of its face";
                return os.str();
            }
            Coord corner;
            corner[axis] = openvdb::Int32(k[0][axis] / K);
            corner[b] = openvdb::Int32(lo[b] / K);
            corner[d] = openvdb::Int32(lo[d] / K);
            const auto it = faces.find({corner, axis});
            if (it == faces.end()) {
                os << "triangle " << t << " on a face between equal labels";
                return os.str();
            }
            Expect& e = it->second;
            if (e.a != patch.a || e.b != patch.b || (twiceArea > 0 ? 1 : -1) != e.sign) {
                os << "triangle " << t << " in patch (" << patch.a << "," << patch.b
                   << ") should be in (" << e.a << "," << e.b << ") with sign " << e.sign;
                return os.str();
            }
            ++e.found;
            for (int i = 0; i < 3; ++i) e.corners.insert(k[i]);
        }
    }
    for (const auto& f : faces) {
        if (f.second.found != 2 || f.second.corners.size() != 4) {
            os << "face at (" << f.first.first.x() << "," << f.first.first.y() << ","
               << f.first.first.z() << ") axis " << f.first.second << " covered by "
               << f.second.found << " triangles";
            return os.str();
        }
    }
    return "";
}

std::int64_t
voxelSetEuler(const openvdb::Int32Grid& grid, Label label)
{
    // Cells of the closure on the doubled grid: cell 2c + d, d in {0,1,2}^3, has as many odd
    // coordinates as dimensions.
    std::unordered_set<std::uint64_t> cells;
    auto pack = [](std::int64_t x, std::int64_t y, std::int64_t z) {
        const std::int64_t o = 1 << 20;
        return (std::uint64_t(x + o) << 42) | (std::uint64_t(y + o) << 21) | std::uint64_t(z + o);
    };
    std::int64_t euler = 0;
    forEachStoredLabel(grid, [&](const openvdb::CoordBBox& box, Label l) {
        if (l != label) return;
        for (auto it = box.begin(); it; ++it) {
            const Coord c = *it;
            for (int dz = 0; dz < 3; ++dz) {
                for (int dy = 0; dy < 3; ++dy) {
                    for (int dx = 0; dx < 3; ++dx) {
                        const std::uint64_t cell = pack(2 * c.x() + dx, 2 * c.y() + dy,
                                                        2 * c.z() + dz);
                        if (!cells.insert(cell).second) continue;
                        const int dim = (dx & 1) + (dy & 1) + (dz & 1);
                        euler += (dim % 2 == 0) ? 1 : -1;
                    }
                }
            }
        }
    });
    return euler;
}

std::string
compareMeshes(const vdbi::InterfaceMesh& a, const vdbi::InterfaceMesh& b)
{
    if (a.points.size() != b.points.size()) return "point counts differ";
    if (a.triangles.size() != b.triangles.size()) return "triangle counts differ";
    if (a.patches.size() != b.patches.size()) return "patch counts differ";
    if (a.pointKeys.size() != b.pointKeys.size()) return "key counts differ";
    if (a.keyScale != b.keyScale) return "key scales differ";
    if (!a.points.empty()
        && std::memcmp(a.points.data(), b.points.data(), a.points.size() * sizeof(a.points[0]))) {
        return "points differ";
    }
    for (std::size_t i = 0; i < a.triangles.size(); ++i) {
        if (a.triangles[i] != b.triangles[i]) return "triangle " + std::to_string(i) + " differs";
    }
    for (std::size_t i = 0; i < a.patches.size(); ++i) {
        const auto &p = a.patches[i], &q = b.patches[i];
        if (p.a != q.a || p.b != q.b || p.firstTriangle != q.firstTriangle
            || p.triangleCount != q.triangleCount) {
            return "patch " + std::to_string(i) + " differs";
        }
    }
    if (a.pointKeys != b.pointKeys) return "keys differ";
    return "";
}

} // namespace vdbi_test
