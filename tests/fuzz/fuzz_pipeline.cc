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

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
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

    in.options.remesh = false; // repair and extraction, whose counts the checks below know
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

/// Directed edges u -> v, each with a tag (a patch or a label), grouped by u with a counting
/// sort (a global sort dominated the checks, which run on every input), sorted per u: so
/// duplicates are neighbours, and two sets of edges are equal when their arrays are.
class DirectedEdges
{
public:
    /// @a forEachEdge(op) calls op(u, v, tag) for every edge, twice over the same edges.
    template<typename ForEachEdge>
    DirectedEdges(std::size_t vertices, ForEachEdge&& forEachEdge) : mFirst(vertices + 1, 0u)
    {
        std::size_t count = 0;
        forEachEdge([&](std::uint32_t u, std::uint32_t, std::uint32_t) {
            ++mFirst[u + 1];
            ++count;
        });
        for (std::size_t v = 1; v < mFirst.size(); ++v) mFirst[v] += mFirst[v - 1];
        mTargets.resize(count);
        std::vector<std::uint32_t> next(mFirst.begin(), mFirst.end() - 1);
        forEachEdge([&](std::uint32_t u, std::uint32_t v, std::uint32_t tag) {
            mTargets[next[u]++] = (std::uint64_t(v) << 32) | tag;
        });
        for (std::size_t u = 0; u + 1 < mFirst.size(); ++u) {
            std::sort(mTargets.begin() + mFirst[u], mTargets.begin() + mFirst[u + 1]);
        }
    }
    /// Whether an edge u -> v with the same tag is there twice.
    bool hasDuplicate() const
    {
        for (std::size_t u = 0; u + 1 < mFirst.size(); ++u) {
            for (std::uint32_t i = mFirst[u] + 1; i < mFirst[u + 1]; ++i) {
                if (mTargets[i] == mTargets[i - 1]) return true;
            }
        }
        return false;
    }
    bool operator==(const DirectedEdges& o) const
    {
        return mFirst == o.mFirst && mTargets == o.mTargets;
    }

private:
    std::vector<std::uint32_t> mFirst;   ///< per vertex, its first edge in mTargets
    std::vector<std::uint64_t> mTargets; ///< v << 32 | tag
};

/// The self-contained checker (see the file comment); aborts on the first violation.
void
checkMesh(const vdbi::InterfaceMesh& mesh, const std::set<Label>& labels,
          const std::set<Label>& allowed)
{
    const std::size_t n = mesh.points.size();
    if (!mesh.pointKeys.empty()) {
        if (mesh.pointKeys.size() != n) fail("pointKeys and points differ in number");
        std::vector<vdbi::VertexKey> keys = mesh.pointKeys;
        std::sort(keys.begin(), keys.end());
        if (std::adjacent_find(keys.begin(), keys.end()) != keys.end()) {
            fail("two points with the same key");
        }
    }
    std::size_t first = 0;
    std::set<Label> labelsWithPatch;
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
        labelsWithPatch.insert(patch.a);
        labelsWithPatch.insert(patch.b);
    }
    if (first != mesh.triangles.size()) fail("triangles outside every patch");
    for (const openvdb::Vec3I& t : mesh.triangles) {
        if (t[0] >= n || t[1] >= n || t[2] >= n) fail("triangle index out of range");
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) fail("degenerate triangle");
    }
    // A volume of several labels has an interface around every one of them.
    if (labels.size() > 1) {
        for (const Label label : labels) {
            if (!labelsWithPatch.count(label)) {
                fail("label " + std::to_string(label) + " has no patch");
            }
        }
    }

    // Every triangle edge u -> v of a patch (a, b), in the patch's orientation.
    const auto forEachTriangleEdge = [&mesh](auto&& op) {
        for (std::uint32_t p = 0; p < mesh.patches.size(); ++p) {
            const vdbi::InterfacePatch& patch = mesh.patches[p];
            for (std::size_t t = patch.firstTriangle;
                 t < patch.firstTriangle + patch.triangleCount; ++t) {
                const openvdb::Vec3I& tri = mesh.triangles[t];
                for (int e = 0; e < 3; ++e) op(p, std::uint32_t(tri[e]), tri[(e + 1) % 3]);
            }
        }
    };
    // Per patch: every directed edge once, so every undirected edge in at most 2 triangles.
    const DirectedEdges patchEdges(n, [&](auto&& op) {
        forEachTriangleEdge([&](std::uint32_t p, std::uint32_t u, std::uint32_t v) {
            op(u, v, p);
        });
    });
    if (patchEdges.hasDuplicate()) fail("directed edge twice in a patch");
    // Per label: the union of its patches, flipped where it is b, is closed: every directed
    // edge once, and the edges equal their reverses. Tags are indices into labelList.
    const std::vector<Label> labelList(allowed.begin(), allowed.end());
    const auto tagOf = [&labelList](Label l) {
        return std::uint32_t(std::lower_bound(labelList.begin(), labelList.end(), l)
            - labelList.begin());
    };
    std::vector<std::array<std::uint32_t, 2>> patchTags;
    for (const vdbi::InterfacePatch& patch : mesh.patches) {
        patchTags.push_back({tagOf(patch.a), tagOf(patch.b)});
    }
    const auto labelEdges = [&](bool reversed) {
        return DirectedEdges(n, [&](auto&& op) {
            forEachTriangleEdge([&](std::uint32_t p, std::uint32_t u, std::uint32_t v) {
                if (reversed) std::swap(u, v);
                op(u, v, patchTags[p][0]);
                op(v, u, patchTags[p][1]);
            });
        });
    };
    const DirectedEdges forward = labelEdges(false);
    if (forward.hasDuplicate()) fail("the surface of a label has a directed edge twice");
    if (!(forward == labelEdges(true))) {
        fail("the surface of a label is not closed (an edge without its reverse)");
    }
}

} // namespace

extern "C" int
LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    static const bool initialized = [] {
        openvdb::initialize();
#ifdef __GLIBC__
        // Keep freed memory for the next input: each run builds and frees trees with tables of
        // hundreds of kilobytes, and returning them to the kernel made page faults a fifth of it.
        mallopt(M_MMAP_THRESHOLD, 256 << 20);
        mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
        return true;
    }();
    (void)initialized;

    Input in = decode(data, size);
    vdbi::Result result = vdbi::extractInterfaces(*in.grid, in.options);
    // The checker's own test (tests/fuzz/CMakeLists.txt): one triangle turned over must fail.
    static const bool breakMesh = std::getenv("VDBI_FUZZ_BREAK_MESH") != nullptr;
    if (breakMesh && !result.mesh.triangles.empty()) {
        std::swap(result.mesh.triangles[0][1], result.mesh.triangles[0][2]);
    }
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
