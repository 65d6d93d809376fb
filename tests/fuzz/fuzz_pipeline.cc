// SPDX-License-Identifier: Apache-2.0
/// @file fuzz/fuzz_pipeline.cc
/// @brief Fuzz target: vdbi::extractInterfaces on small label volumes decoded from the bytes,
/// with the guarantees checked by a compact checker of its own.
/// @details Input layout (bytes past the end read as 0):
///
/// | byte  | meaning                                                                      |
/// |-------|------------------------------------------------------------------------------|
/// | 0..2  | nx, ny, nz = 1 + byte % 6                                                    |
/// | 3     | bits 0-1: 2..5 labels; bits 2-3: palette (small, mixed sign, extremes, ...)  |
/// | 4     | bit 0 threaded; 1 a constraint; 2 a priority order; 3 background voxels      |
/// |       | stored active; bits 4-6 the background's palette index; 7 compare threading  |
/// | 5, 6  | origin: x = b5 % 16 - 8, y = b5 / 16 - 8, z = b6 % 16 - 8                    |
/// | 7..9  | the constraint (a, b, separator) as palette indices (skipped if invalid)     |
/// | 10..14| the priority order: a shuffle of the palette, then its length                |
/// | 16..  | one label per voxel (palette index = byte % labels), x fastest               |
///
/// Every input is valid, so any exception is a finding, and so is a violated guarantee: per
/// patch every directed edge once (so every undirected edge in at most 2 triangles); per label
/// the union of its patches, flipped where it is b, closed: every directed edge matched by its
/// reverse exactly once.

#include <vdbi/Interfaces.h>

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace {

using vdbi::Label;

constexpr std::size_t HEADER = 16;
constexpr int MAX_DIM = 6;
constexpr Label PALETTES[4][5] = {
    {0, 1, 2, 3, 4},
    {0, -1, 5, -70000, 70000},
    {INT32_MIN, INT32_MAX, 0, -1, 65536},
    {INT32_MAX, INT32_MIN, INT32_MAX - 1, INT32_MIN + 1, 1},
};

struct Input
{
    openvdb::Int32Grid::Ptr grid;
    vdbi::Options options;
    std::set<Label> labels;      ///< every label of the volume, the background included
    /// May have patches: the labels, plus a constraint's separator (inserted between a, b).
    std::set<Label> allowed;
    bool compareThreading = false;
};

Input
decode(const std::uint8_t* data, std::size_t size)
{
    const auto byte = [&](std::size_t i) -> unsigned { return i < size ? data[i] : 0u; };
    const int nx = 1 + int(byte(0) % MAX_DIM), ny = 1 + int(byte(1) % MAX_DIM);
    const int nz = 1 + int(byte(2) % MAX_DIM);
    const int k = 2 + int(byte(3) & 3u);
    const Label* palette = PALETTES[(byte(3) >> 2) & 3u];
    const unsigned flags = byte(4);

    Input in;
    const Label background = palette[((flags >> 4) & 7u) % unsigned(k)];
    in.grid = openvdb::Int32Grid::create(background);
    in.labels.insert(background);
    const openvdb::Coord origin(int(byte(5) % 16) - 8, int(byte(5) / 16) - 8,
                                int(byte(6) % 16) - 8);
    auto accessor = in.grid->getAccessor();
    std::size_t next = HEADER;
    for (int z = 0; z < nz; ++z) {
        for (int y = 0; y < ny; ++y) {
            for (int x = 0; x < nx; ++x) {
                const Label label = palette[byte(next++) % unsigned(k)];
                in.labels.insert(label);
                if (label != background || (flags & 8u)) {
                    accessor.setValueOn(origin.offsetBy(x, y, z), label);
                }
            }
        }
    }

    vdbi::RepairOptions& repair = in.options.repair;
    repair.threaded = (flags & 1u) != 0;
    if (flags & 2u) {
        const vdbi::SeparationConstraint c{palette[byte(7) % unsigned(k)],
            palette[byte(8) % unsigned(k)], palette[byte(9) % unsigned(k)]};
        if (c.a != c.b && c.separator != c.a && c.separator != c.b) {
            repair.constraints.push_back(c);
            in.allowed.insert(c.separator);
        }
    }
    if (flags & 4u) {
        std::vector<Label> order(palette, palette + k);
        for (int i = k - 1; i > 0; --i) {
            const unsigned j = byte(10 + std::size_t(k - 1 - i)) % unsigned(i + 1);
            std::swap(order[std::size_t(i)], order[j]);
        }
        order.resize(1 + byte(14) % unsigned(k));
        repair.priority = vdbi::LabelPriority(order);
    }
    in.compareThreading = (flags & 128u) != 0;
    in.allowed.insert(in.labels.begin(), in.labels.end());
    return in;
}

[[noreturn]] void
fail(const std::string& what)
{
    std::fprintf(stderr, "fuzz_pipeline: guarantee violated: %s\n", what.c_str());
    std::abort();
}

std::uint64_t
edgeKey(std::uint32_t u, std::uint32_t v)
{
    return (std::uint64_t(u) << 32) | v;
}

/// The self-contained checker (see the file comment); aborts on the first violation.
void
checkMesh(const vdbi::InterfaceMesh& mesh, const std::set<Label>& labels,
          const std::set<Label>& allowed)
{
    const std::size_t n = mesh.points.size();
    if (!mesh.pointKeys.empty()) {
        if (mesh.pointKeys.size() != n) fail("pointKeys and points differ in number");
        std::set<vdbi::VertexKey> keys(mesh.pointKeys.begin(), mesh.pointKeys.end());
        if (keys.size() != n) fail("two points with the same key");
    }
    std::size_t first = 0;
    std::map<Label, std::vector<std::size_t>> patchesOf;
    for (std::size_t p = 0; p < mesh.patches.size(); ++p) {
        const vdbi::InterfacePatch& patch = mesh.patches[p];
        if (!(patch.a < patch.b)) fail("patch with a >= b");
        if (p > 0 && !(std::make_pair(mesh.patches[p - 1].a, mesh.patches[p - 1].b)
                       < std::make_pair(patch.a, patch.b))) {
            fail("patches not sorted by (a, b) or repeated");
        }
        if (patch.firstTriangle != first || patch.triangleCount == 0) {
            fail("patches not contiguous, or empty");
        }
        first += patch.triangleCount;
        if (!allowed.count(patch.a) || !allowed.count(patch.b)) fail("patch of an absent label");
        patchesOf[patch.a].push_back(p);
        patchesOf[patch.b].push_back(p);
    }
    if (first != mesh.triangles.size()) fail("triangles outside every patch");
    for (const openvdb::Vec3I& t : mesh.triangles) {
        if (t[0] >= n || t[1] >= n || t[2] >= n) fail("triangle index out of range");
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) fail("degenerate triangle");
    }
    // A volume of several labels has an interface around every one of them.
    if (labels.size() > 1) {
        for (const Label label : labels) {
            if (!patchesOf.count(label)) fail("label " + std::to_string(label) + " has no patch");
        }
    }

    // Per patch: directed edges unique, undirected edges in at most 2 triangles. Sorted
    // arrays rather than hash maps: the meshes have tens of thousands of edges.
    std::vector<std::uint64_t> directed, undirected;
    for (const vdbi::InterfacePatch& patch : mesh.patches) {
        directed.clear();
        undirected.clear();
        for (std::size_t t = patch.firstTriangle;
             t < patch.firstTriangle + patch.triangleCount; ++t) {
            const openvdb::Vec3I& tri = mesh.triangles[t];
            for (int e = 0; e < 3; ++e) {
                const std::uint32_t u = tri[e], v = tri[(e + 1) % 3];
                directed.push_back(edgeKey(u, v));
                undirected.push_back(edgeKey(std::min(u, v), std::max(u, v)));
            }
        }
        std::sort(directed.begin(), directed.end());
        std::sort(undirected.begin(), undirected.end());
        if (std::adjacent_find(directed.begin(), directed.end()) != directed.end()) {
            fail("directed edge twice in a patch");
        }
        for (std::size_t i = 2; i < undirected.size(); ++i) {
            if (undirected[i] == undirected[i - 2]) fail("edge in 3 or more triangles of a patch");
        }
    }
    // Per label: the union, oriented outward, is closed.
    for (const auto& [label, patches] : patchesOf) {
        directed.clear();
        for (const std::size_t p : patches) {
            const vdbi::InterfacePatch& patch = mesh.patches[p];
            const bool flip = patch.b == label;
            for (std::size_t t = patch.firstTriangle;
                 t < patch.firstTriangle + patch.triangleCount; ++t) {
                const openvdb::Vec3I& tri = mesh.triangles[t];
                for (int e = 0; e < 3; ++e) {
                    std::uint32_t u = tri[e], v = tri[(e + 1) % 3];
                    if (flip) std::swap(u, v);
                    directed.push_back(edgeKey(u, v));
                }
            }
        }
        std::sort(directed.begin(), directed.end());
        const std::string where = "the surface of label " + std::to_string(label);
        if (std::adjacent_find(directed.begin(), directed.end()) != directed.end()) {
            fail(where + " has a directed edge twice");
        }
        for (const std::uint64_t key : directed) {
            if (!std::binary_search(directed.begin(), directed.end(), (key << 32) | (key >> 32))) {
                fail(where + " is not closed (an edge without its reverse)");
            }
        }
    }
}

} // namespace

extern "C" int
LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    static const bool initialized = (openvdb::initialize(), true);
    (void)initialized;

    Input in = decode(data, size);
    const vdbi::Result result = vdbi::extractInterfaces(*in.grid, in.options);
    checkMesh(result.mesh, in.labels, in.allowed);
    if (in.compareThreading) {
        // Thread scheduling must not change a single byte of the result.
        in.options.repair.threaded = !in.options.repair.threaded;
        const vdbi::InterfaceMesh other = vdbi::extractInterfaces(*in.grid, in.options).mesh;
        const vdbi::InterfaceMesh& mesh = result.mesh;
        if (other.points != mesh.points || other.triangles != mesh.triangles
            || other.pointKeys != mesh.pointKeys || other.patches.size() != mesh.patches.size()) {
            fail("threaded and serial runs differ");
        }
        for (std::size_t p = 0; p < mesh.patches.size(); ++p) {
            const vdbi::InterfacePatch &x = mesh.patches[p], &y = other.patches[p];
            if (x.a != y.a || x.b != y.b || x.firstTriangle != y.firstTriangle
                || x.triangleCount != y.triangleCount) {
                fail("threaded and serial runs differ in their patches");
            }
        }
    }
    return 0;
}
