// SPDX-License-Identifier: Apache-2.0
/// @file TestLargeLabels.cc
/// @brief Negative labels, labels above 2^16 and the whole int32 range (INT32_MIN, INT32_MAX,
/// also as the background) through extractInterfaces, the label priority and the writers.
/// @details Why the results must not change: the method looks at labels only through equality
/// and their priority order (numerical by default). A label map that keeps the order therefore
/// must give exactly the mesh of the small labels, with the labels of its patches mapped. That
/// is checked on random volumes with critical elements, with and without a priority order and
/// a constraint, so that any arithmetic on labels (a difference, a sum, a narrowing) that
/// overflows near the int32 limits shows up as a difference.

#include <vdbi/Interfaces.h>
#include <vdbi/MeshWriter.h>
#include <vdbi/Types.h>

#include "support/HandMadeGrids.h"
#include "support/MeshChecker.h"
#include "support/RandomVolumes.h"
#include "support/RawExtraction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

using vdbi::Label;

class TestLargeLabels : public ::testing::Test
{
protected:
    void SetUp() override
    {
        mDir = fs::temp_directory_path()
            / ("vdbi_large_labels_" + std::to_string(::getpid()) + "_"
               + ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(mDir);
        fs::create_directories(mDir);
    }
    void TearDown() override { fs::remove_all(mDir); }

    fs::path mDir;
};

namespace {

constexpr Label MIN = std::numeric_limits<Label>::min();
constexpr Label MAX = std::numeric_limits<Label>::max();

/// Order-preserving maps of the small labels 0..3 onto large ones.
const std::vector<std::vector<Label>>&
labelMaps()
{
    static const std::vector<std::vector<Label>> maps = {
        {MIN, -1, 65536, MAX},                 // the extremes and 2^16
        {MIN, MIN + 1, MAX - 1, MAX},          // neighbours of the extremes
        {-70000, -65537, -1, 100000},          // negative and beyond 16 bits
        {65536, 65537, 1 << 20, 1 << 30},      // all above 2^16
    };
    return maps;
}

/// A random size^3 volume of the labels 0..3 (x fastest), some of them critical.
std::vector<Label>
randomDense(std::uint64_t seed, int size)
{
    vdbi_test::Rng rng(seed);
    std::vector<Label> labels(std::size_t(size * size * size));
    for (Label& l : labels) l = Label(rng.below(4));
    return labels;
}

openvdb::Int32Grid::Ptr
mappedGrid(const std::vector<Label>& small, int size, Label background,
           const std::vector<Label>& map, const openvdb::Coord& origin)
{
    std::vector<Label> labels(small.size());
    std::transform(small.begin(), small.end(), labels.begin(),
                   [&](Label l) { return map[std::size_t(l)]; });
    return vdbi_test::gridFromDense(size, size, size, labels, origin,
                                    map[std::size_t(background)]);
}

/// "" when every patch has a < b, the patches are sorted and every label's patches, flipped
/// where it is b, form a closed surface: every directed edge matched by its reverse once.
std::string
closedSurfaceProblem(const vdbi::InterfaceMesh& mesh)
{
    std::map<Label, std::vector<std::uint64_t>> edges; // directed, (from << 32) | to
    for (std::size_t p = 0; p < mesh.patches.size(); ++p) {
        const vdbi::InterfacePatch& patch = mesh.patches[p];
        if (!(patch.a < patch.b)) return "patch (" + std::to_string(patch.a) + ", "
            + std::to_string(patch.b) + ") has a >= b";
        if (p > 0 && !(std::make_pair(mesh.patches[p - 1].a, mesh.patches[p - 1].b)
                       < std::make_pair(patch.a, patch.b))) {
            return "patches not sorted by (a, b)";
        }
        for (std::size_t t = patch.firstTriangle; t < patch.firstTriangle + patch.triangleCount;
             ++t) {
            const openvdb::Vec3I& tri = mesh.triangles[t];
            for (int e = 0; e < 3; ++e) {
                const std::uint64_t u = tri[e], v = tri[(e + 1) % 3];
                edges[patch.a].push_back((u << 32) | v);
                edges[patch.b].push_back((v << 32) | u); // flipped: outward from b
            }
        }
    }
    for (auto& [label, directed] : edges) {
        std::sort(directed.begin(), directed.end());
        for (std::size_t i = 0; i < directed.size(); ++i) {
            const std::uint64_t edge = directed[i];
            const std::uint64_t reverse = (edge << 32) | (edge >> 32);
            if ((i > 0 && directed[i - 1] == edge)
                || !std::binary_search(directed.begin(), directed.end(), reverse)) {
                return "the surface of label " + std::to_string(label) + " is not closed at "
                    + std::to_string(edge >> 32) + "-" + std::to_string(edge & 0xffffffffu);
            }
        }
    }
    return "";
}

/// "" when @a large is @a small with every label mapped through @a map.
std::string
differenceUnderMap(const vdbi::InterfaceMesh& small, const vdbi::InterfaceMesh& large,
                   const std::vector<Label>& map)
{
    if (small.points != large.points) return "points differ";
    if (small.triangles != large.triangles) return "triangles differ";
    if (small.pointKeys != large.pointKeys) return "keys differ";
    if (small.patches.size() != large.patches.size()) {
        return "patch count " + std::to_string(small.patches.size()) + " vs "
            + std::to_string(large.patches.size());
    }
    for (std::size_t p = 0; p < small.patches.size(); ++p) {
        const vdbi::InterfacePatch &s = small.patches[p], &l = large.patches[p];
        if (map[std::size_t(s.a)] != l.a || map[std::size_t(s.b)] != l.b
            || s.firstTriangle != l.firstTriangle || s.triangleCount != l.triangleCount) {
            return "patch " + std::to_string(p) + ": (" + std::to_string(s.a) + ", "
                + std::to_string(s.b) + ") became (" + std::to_string(l.a) + ", "
                + std::to_string(l.b) + ")";
        }
    }
    return "";
}

/// Runs the small volume and every mapped one with @a options (whose priority order and
/// constraints are given in small labels and mapped along), and compares.
void
expectSameUnderEveryMap(const std::vector<Label>& small, int size, Label background,
                        const std::vector<Label>& order,
                        const std::vector<vdbi::SeparationConstraint>& constraints,
                        const std::string& what)
{
    const openvdb::Coord origin(-3, 5, -9); // across leaf boundaries, negative coordinates
    const std::vector<Label> identity = {0, 1, 2, 3};
    vdbi::Options options;
    options.repair.priority = vdbi::LabelPriority(order);
    options.repair.constraints = constraints;
    const vdbi::Result reference =
        vdbi_test::extractRaw(*mappedGrid(small, size, background, identity, origin), options);
    ASSERT_EQ(closedSurfaceProblem(reference.mesh), "") << what;
    ASSERT_GT(reference.mesh.patches.size(), 2u) << what;

    for (const std::vector<Label>& map : labelMaps()) {
        const std::string where = what + ", labels " + std::to_string(map[0]) + " "
            + std::to_string(map[1]) + " " + std::to_string(map[2]) + " "
            + std::to_string(map[3]);
        vdbi::Options mapped = options;
        std::vector<Label> mappedOrder;
        for (const Label l : order) mappedOrder.push_back(map[std::size_t(l)]);
        mapped.repair.priority = vdbi::LabelPriority(mappedOrder);
        for (vdbi::SeparationConstraint& c : mapped.repair.constraints) {
            c = {map[std::size_t(c.a)], map[std::size_t(c.b)], map[std::size_t(c.separator)]};
        }
        const openvdb::Int32Grid::Ptr grid = mappedGrid(small, size, background, map, origin);
        const vdbi::Result result = vdbi_test::extractRaw(*grid, mapped);
        EXPECT_EQ(differenceUnderMap(reference.mesh, result.mesh, map), "") << where;
        EXPECT_EQ(closedSurfaceProblem(result.mesh), "") << where;
        EXPECT_EQ(result.statistics.criticalEdges, reference.statistics.criticalEdges) << where;
        EXPECT_EQ(result.statistics.criticalVertices, reference.statistics.criticalVertices)
            << where;
        EXPECT_EQ(result.statistics.labelCount, reference.statistics.labelCount) << where;
        const vdbi_test::MeshReport report = vdbi_test::checkMesh(result.mesh);
        EXPECT_TRUE(report.ok()) << where << ": " << report.summary();
    }
}

/// Sum of the triangle areas of every patch, by label pair.
std::map<std::pair<Label, Label>, double>
patchAreas(const vdbi::InterfaceMesh& mesh)
{
    std::map<std::pair<Label, Label>, double> areas;
    for (const vdbi::InterfacePatch& patch : mesh.patches) {
        double& area = areas[{patch.a, patch.b}];
        for (std::size_t t = patch.firstTriangle; t < patch.firstTriangle + patch.triangleCount;
             ++t) {
            const openvdb::Vec3I& tri = mesh.triangles[t];
            const openvdb::Vec3d& p = mesh.points[tri[0]];
            area += 0.5 * (mesh.points[tri[1]] - p).cross(mesh.points[tri[2]] - p).length();
        }
    }
    return areas;
}

std::string
readAll(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

template<typename T>
T
readLE(const std::string& data, std::size_t& pos)
{
    if (pos + sizeof(T) > data.size()) throw std::runtime_error("truncated");
    unsigned char bytes[sizeof(T)];
    for (std::size_t k = 0; k < sizeof(T); ++k) {
        bytes[k] = static_cast<unsigned char>(data[pos + k]);
    }
    pos += sizeof(T);
    T value;
    std::memcpy(&value, bytes, sizeof(T)); // the host is little-endian (x86-64, ARM64)
    return value;
}

/// The label0/label1 face properties of a binary little-endian PLY as written by
/// writeInterfaceMesh (float x y z; uchar count, int indices; int label0 label1).
std::vector<std::array<Label, 2>>
plyLabels(const fs::path& path)
{
    const std::string data = readAll(path);
    std::size_t pos = 0, vertices = 0, faces = 0;
    bool hasLabels = false;
    for (;;) {
        const std::size_t eol = data.find('\n', pos);
        if (eol == std::string::npos) throw std::runtime_error("no end_header");
        const std::string line = data.substr(pos, eol - pos);
        pos = eol + 1;
        std::istringstream words(line);
        std::string word, what;
        words >> word;
        if (word == "element") {
            std::size_t count = 0;
            words >> what >> count;
            (what == "vertex" ? vertices : faces) = count;
        } else if (line == "property int label0") {
            hasLabels = true;
        } else if (word == "end_header") {
            break;
        }
    }
    if (!hasLabels) throw std::runtime_error("no label0 property");
    pos += vertices * 3 * sizeof(float);
    std::vector<std::array<Label, 2>> labels;
    for (std::size_t f = 0; f < faces; ++f) {
        if (readLE<std::uint8_t>(data, pos) != 3) throw std::runtime_error("not a triangle");
        pos += 3 * sizeof(std::int32_t);
        const Label a = readLE<std::int32_t>(data, pos);
        const Label b = readLE<std::int32_t>(data, pos);
        labels.push_back({a, b});
    }
    if (pos != data.size()) throw std::runtime_error("trailing bytes");
    return labels;
}

/// The BoundaryLabels cell array of a .vtp with raw appended data.
std::vector<std::array<Label, 2>>
vtpLabels(const fs::path& path)
{
    const std::string data = readAll(path);
    const std::size_t array = data.find("Name=\"BoundaryLabels\"");
    const std::size_t offsetAt = data.find("offset=\"", array);
    const std::size_t appended = data.find("<AppendedData encoding=\"raw\">");
    if (array == std::string::npos || offsetAt == std::string::npos
        || appended == std::string::npos) {
        throw std::runtime_error("no BoundaryLabels array or appended data");
    }
    std::size_t pos = data.find('_', appended) + 1 + std::stoull(data.substr(offsetAt + 8));
    const std::uint64_t bytes = readLE<std::uint64_t>(data, pos);
    std::vector<std::array<Label, 2>> labels(bytes / 8);
    for (auto& pair : labels) {
        pair[0] = readLE<std::int32_t>(data, pos);
        pair[1] = readLE<std::int32_t>(data, pos);
    }
    return labels;
}

/// Group name -> number of faces in it, of an .obj file.
std::map<std::string, std::size_t>
objGroups(const fs::path& path)
{
    std::ifstream in(path);
    std::map<std::string, std::size_t> groups;
    std::string line, group;
    while (std::getline(in, line)) {
        if (line.compare(0, 2, "g ") == 0) {
            group = line.substr(2);
            groups[group];
        } else if (line.compare(0, 2, "f ") == 0) {
            ++groups[group];
        }
    }
    return groups;
}

std::string
token(Label l)
{
    return l < 0 ? "m" + std::to_string(-std::int64_t(l)) : std::to_string(l);
}

} // namespace

TEST_F(TestLargeLabels, testPriorityKeysAtTheExtremes)
{
    // The default order is numerical over the whole int32 range.
    const vdbi::LabelPriority numerical;
    EXPECT_TRUE(numerical.higher(MIN, MAX));
    EXPECT_TRUE(numerical.higher(MIN, MIN + 1));
    EXPECT_TRUE(numerical.higher(MAX - 1, MAX));
    EXPECT_TRUE(numerical.higher(-1, 0));
    EXPECT_FALSE(numerical.higher(MAX, MIN));
    EXPECT_EQ(numerical.pick(MAX, MIN), MIN);
    EXPECT_EQ(numerical.pick(65536, -65536), -65536);
    EXPECT_LT(numerical.key(MIN), numerical.key(MAX));

    // A user order puts its labels first, ahead of every other label, even INT32_MIN.
    const vdbi::LabelPriority user({MAX, 0, MIN});
    EXPECT_TRUE(user.higher(MAX, 0));
    EXPECT_TRUE(user.higher(0, MIN));
    EXPECT_TRUE(user.higher(MIN, MIN + 1));   // listed before unlisted
    EXPECT_TRUE(user.higher(MAX, MIN + 1));
    EXPECT_TRUE(user.higher(MIN + 1, MAX - 1)); // unlisted: numerical
    EXPECT_TRUE(user.higher(-1, 1));
    EXPECT_EQ(user.pick(MIN + 1, MAX), MAX);
    EXPECT_EQ(user.pick(MIN, MAX - 1), MIN);
    // Keys of distinct labels are distinct and ordered as the priority.
    const std::vector<Label> labels = {MIN, MIN + 1, -65537, -1, 0, 1, 65536, MAX - 1, MAX};
    std::set<std::int64_t> keys;
    for (const Label a : labels) {
        keys.insert(user.key(a));
        for (const Label b : labels) {
            if (a != b) EXPECT_NE(user.higher(a, b), user.higher(b, a)) << a << " " << b;
        }
    }
    EXPECT_EQ(keys.size(), labels.size());
    EXPECT_THROW(vdbi::LabelPriority({MIN, MAX, MIN}), openvdb::ValueError);
}

TEST_F(TestLargeLabels, testSingleVoxelOfEveryExtremeLabel)
{
    // A voxel of one label in a background of another: one patch of the six faces, oriented
    // from the smaller label into the larger, whichever of them is the background.
    const std::vector<std::pair<Label, Label>> cases = {{MIN, MAX}, {MAX, MIN}, {MIN, 0},
        {0, MIN}, {MAX, 0}, {-1, MAX}, {65536, -65536}, {MIN + 1, MIN}, {MAX - 1, MAX}};
    for (const auto& [voxel, background] : cases) {
        const std::string what = std::to_string(voxel) + " in " + std::to_string(background);
        auto grid = vdbi_test::gridFromDense(1, 1, 1, {voxel}, openvdb::Coord(-1, 7, 8),
                                             background);
        const vdbi::Result result = vdbi_test::extractRaw(*grid);
        ASSERT_EQ(result.mesh.patches.size(), 1u) << what;
        const vdbi::InterfacePatch& patch = result.mesh.patches[0];
        EXPECT_EQ(patch.a, std::min(voxel, background)) << what;
        EXPECT_EQ(patch.b, std::max(voxel, background)) << what;
        EXPECT_EQ(closedSurfaceProblem(result.mesh), "") << what;
        EXPECT_NEAR(patchAreas(result.mesh).begin()->second, 6.0, 1e-9) << what;
        EXPECT_EQ(result.statistics.labelCount, 2u) << what;
        // The enclosed volume is +1 seen from the voxel: outward means from a into b when the
        // voxel is a, so the normals must flip with the order of the two labels.
        const vdbi_test::MeshReport report = vdbi_test::checkMesh(result.mesh);
        ASSERT_TRUE(report.ok()) << what << ": " << report.summary();
        ASSERT_TRUE(report.labels.count(voxel)) << what;
        EXPECT_NEAR(report.labels.at(voxel).volume, 1.0, 1e-9) << what;
    }
}

TEST_F(TestLargeLabels, testPatchesOfExtremeLabelsMatchTheFaces)
{
    // Nothing critical (boxes side by side): every patch is exactly its coarse faces, so its
    // area is their number, for the labels of every map and every background.
    for (const std::vector<Label>& map : labelMaps()) {
        for (const Label background : {0, 3}) {
            // Three boxes in a row along x, 2x2x2 each, of the three non-background labels.
            std::vector<Label> small(6 * 2 * 2);
            const std::vector<Label> others = background == 0 ? std::vector<Label>{1, 2, 3}
                                                               : std::vector<Label>{0, 1, 2};
            for (int z = 0; z < 2; ++z) for (int y = 0; y < 2; ++y) for (int x = 0; x < 6; ++x) {
                small[std::size_t(x + 6 * (y + 2 * z))] = others[std::size_t(x / 2)];
            }
            std::vector<Label> labels(small.size());
            std::transform(small.begin(), small.end(), labels.begin(),
                           [&](Label l) { return map[std::size_t(l)]; });
            const Label bg = map[std::size_t(background)];
            auto grid = vdbi_test::gridFromDense(6, 2, 2, labels, openvdb::Coord(4, -1, 0), bg);
            const std::string what = "background " + std::to_string(bg) + ", labels "
                + std::to_string(map[0]) + ".." + std::to_string(map[3]);

            const vdbi::Result result = vdbi_test::extractRaw(*grid);
            EXPECT_EQ(closedSurfaceProblem(result.mesh), "") << what;
            const auto faces = vdbi_test::interfaceFacesPerPair(*grid);
            const auto areas = patchAreas(result.mesh);
            ASSERT_EQ(areas.size(), faces.size()) << what;
            ASSERT_EQ(areas.size(), 5u) << what; // 3 with the background, 2 between boxes
            for (const auto& [pair, count] : faces) {
                ASSERT_TRUE(areas.count(pair)) << what << ": no patch " << pair.first << " "
                    << pair.second;
                EXPECT_LT(pair.first, pair.second) << what;
                EXPECT_NEAR(areas.at(pair), double(count), 1e-9) << what;
            }
        }
    }
}

TEST_F(TestLargeLabels, testRandomVolumesUnderOrderPreservingMaps)
{
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
        const std::vector<Label> small = randomDense(seed, 5);
        for (const Label background : {0, 3, 1}) {
            expectSameUnderEveryMap(small, 5, background, {}, {},
                "seed " + std::to_string(seed) + ", background " + std::to_string(background));
        }
    }
}

TEST_F(TestLargeLabels, testPriorityOrderUnderOrderPreservingMaps)
{
    // A user order that reverses the numerical one, and one that lists a single label: the
    // priority decides the dominant label of every critical element, so a key that
    // overflowed would change the mesh.
    const std::vector<Label> small = randomDense(11, 5);
    expectSameUnderEveryMap(small, 5, 0, {3, 2, 1, 0}, {}, "order 3 2 1 0");
    expectSameUnderEveryMap(small, 5, 3, {3}, {}, "order 3, background 3");
    expectSameUnderEveryMap(small, 5, 0, {2, 0}, {}, "order 2 0");
}

TEST_F(TestLargeLabels, testConstraintUnderOrderPreservingMaps)
{
    const std::vector<Label> small = randomDense(23, 5);
    expectSameUnderEveryMap(small, 5, 0, {}, {{0, 3, 1}}, "constraint 0,3:1");
    expectSameUnderEveryMap(small, 5, 3, {}, {{3, 1, 2}}, "constraint 3,1:2, background 3");
}

TEST_F(TestLargeLabels, testActiveTileOfExtremeLabel)
{
    // A tile of INT32_MIN next to a voxel of INT32_MAX, in backgrounds of both extremes and
    // of 0: tiles are voxelized with their value.
    for (const Label background : {0, MIN, MAX}) {
        const Label tile = background == MIN ? MAX : MIN;
        const Label voxel = background == 0 ? MAX : -1;
        auto grid = openvdb::Int32Grid::create(background);
        grid->tree().addTile(/*level=*/1, openvdb::Coord(0), tile, /*active=*/true);
        grid->tree().setValueOn(openvdb::Coord(8, 8, 0), voxel);
        const std::string what = "background " + std::to_string(background);
        const vdbi::Result result = vdbi_test::extractRaw(*grid);
        EXPECT_EQ(closedSurfaceProblem(result.mesh), "") << what;
        std::set<std::pair<Label, Label>> pairs;
        for (const vdbi::InterfacePatch& p : result.mesh.patches) pairs.insert({p.a, p.b});
        const std::set<std::pair<Label, Label>> expected = {
            {std::min(background, tile), std::max(background, tile)},
            {std::min(background, voxel), std::max(background, voxel)}};
        EXPECT_EQ(pairs, expected) << what;
        EXPECT_EQ(result.statistics.labelCount, 3u) << what;
    }
}

TEST_F(TestLargeLabels, testWritersKeepExtremeLabels)
{
    // Labels INT32_MIN, -1, 65536, INT32_MAX with background INT32_MAX, through .ply (read
    // back: label0/label1 per face), .vtp (the BoundaryLabels array), .obj (group names with
    // m for minus) and the per-label surfaces (file names).
    const std::vector<Label> map = labelMaps()[0];
    const std::vector<Label> small = randomDense(5, 4);
    auto grid = mappedGrid(small, 4, 3, map, openvdb::Coord(0));
    const vdbi::InterfaceMesh mesh = vdbi_test::extractRaw(*grid).mesh;
    ASSERT_EQ(closedSurfaceProblem(mesh), "");
    const std::vector<std::array<Label, 2>> expected = mesh.triangleLabels();
    std::set<Label> labels;
    for (const vdbi::InterfacePatch& p : mesh.patches) {
        labels.insert(p.a);
        labels.insert(p.b);
    }
    ASSERT_TRUE(labels.count(MIN) && labels.count(MAX) && labels.count(65536));

    vdbi::writeInterfaceMesh(mesh, (mDir / "mesh.ply").string());
    EXPECT_EQ(plyLabels(mDir / "mesh.ply"), expected);

    vdbi::writeInterfaceMesh(mesh, (mDir / "mesh.vtp").string());
    EXPECT_EQ(vtpLabels(mDir / "mesh.vtp"), expected);

    vdbi::writeInterfaceMesh(mesh, (mDir / "mesh.obj").string());
    std::map<std::string, std::size_t> groups;
    for (const vdbi::InterfacePatch& p : mesh.patches) {
        groups["patch_" + token(p.a) + "_" + token(p.b)] = p.triangleCount;
    }
    EXPECT_EQ(objGroups(mDir / "mesh.obj"), groups);
    EXPECT_TRUE(groups.count("patch_m2147483648_2147483647"));

    vdbi::writePerLabelSurfaces(mesh, mDir.string(), "ply", /*background=*/MAX);
    for (const Label l : labels) {
        const fs::path file = mDir / ("label_" + token(l) + ".ply");
        EXPECT_EQ(fs::exists(file), l != MAX) << file;
    }
    EXPECT_TRUE(fs::exists(mDir / "label_m2147483648.ply"));
}

#ifdef VDBI_CLI_PATH
TEST_F(TestLargeLabels, testCliKeepsExtremeLabelsFromFileToFile)
{
    // A row of four MET_INT voxels INT32_MIN, -1, 65536, INT32_MAX in background 0, read from
    // a .mha by the CLI and written as .obj and per-label surfaces. Raw extraction: each
    // voxel is a unit cube, so a shared face is 2 triangles, an end voxel's faces to the
    // background 10 and a middle voxel's 8.
    const std::vector<Label> row = {MIN, -1, 65536, MAX};
    std::string data;
    for (const Label l : row) {
        const auto u = static_cast<std::uint32_t>(l);
        for (int i = 0; i < 4; ++i) data += char((u >> (8 * i)) & 0xff);
    }
    std::ofstream(mDir / "row.mha", std::ios::binary)
        << "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
           "DimSize = 4 1 1\nElementType = MET_INT\nElementDataFile = LOCAL\n" << data;
    const std::string command = "cd '" + mDir.string() + "' && '" + VDBI_CLI_PATH
        + "' row.mha --no-remesh -o row.obj --per-label surfaces --per-label-format ply";
    ASSERT_EQ(std::system(command.c_str()), 0);

    const std::map<std::string, std::size_t> groups = {{"patch_m2147483648_m1", 2},
        {"patch_m2147483648_0", 10}, {"patch_m1_0", 8}, {"patch_m1_65536", 2},
        {"patch_0_65536", 8}, {"patch_0_2147483647", 10}, {"patch_65536_2147483647", 2}};
    EXPECT_EQ(objGroups(mDir / "row.obj"), groups);
    std::set<std::string> files;
    for (const auto& entry : fs::directory_iterator(mDir / "surfaces")) {
        files.insert(entry.path().filename().string());
    }
    EXPECT_EQ(files, (std::set<std::string>{"label_m2147483648.ply", "label_m1.ply",
        "label_65536.ply", "label_2147483647.ply"}));
}
#endif // VDBI_CLI_PATH
