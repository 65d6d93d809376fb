// SPDX-License-Identifier: Apache-2.0
/// @file TestMeshWriter.cc
/// @brief Round trips through every writer with small independent readers, and the
/// failure paths of the atomic writes.

#include <vdbi/AtomicFile.h>
#include <vdbi/MeshWriter.h>

#include "support/TestFiles.h"

#include <openvdb/Exceptions.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace {

using vdbi_test::listFolder;
using vdbi_test::readText;

using vdbi::InterfaceMesh;
using vdbi::InterfacePatch;
using vdbi::Label;

// ---------------------------------------------------------------------------------------
// The test mesh: two unit cubes side by side in a background of label 0, cube A = [0,1]^3
// of label -3, cube B = [1,2]x[0,1]^2 of label 2. Patches (-3,0), (-3,2) and (0,2); every
// label's patches form a closed surface. World coordinates are scaled and shifted so they
// are not exactly representable as floats.

constexpr double SCALE = 0.1;
const openvdb::Vec3d ORIGIN(0.05, -1.3, 7.7);

int
cornerIndex(int x, int y, int z)
{
    return x + 3 * (y + 2 * z);
}

/// The face of the cube at (x0, 0, 0) on @a axis, @a side 0 or 1, as a quad counter-clockwise
/// seen from outside the cube.
std::array<int, 4>
cubeFace(int x0, int axis, int side)
{
    // Tangents u, v with u x v = the outward normal.
    static const int tangents[3][2][2] = {{{2, 1}, {1, 2}}, {{0, 2}, {2, 0}}, {{1, 0}, {0, 1}}};
    const int u = tangents[axis][side][0], v = tangents[axis][side][1];
    std::array<int, 3> base = {x0, 0, 0};
    base[axis] += side;
    std::array<int, 4> quad;
    for (int c = 0; c < 4; ++c) {
        std::array<int, 3> p = base;
        if (c == 1 || c == 2) p[u] += 1;
        if (c == 2 || c == 3) p[v] += 1;
        quad[c] = cornerIndex(p[0], p[1], p[2]);
    }
    return quad;
}

void
addQuad(InterfaceMesh& mesh, const std::array<int, 4>& q, bool flip)
{
    if (flip) {
        mesh.triangles.emplace_back(q[0], q[2], q[1]);
        mesh.triangles.emplace_back(q[0], q[3], q[2]);
    } else {
        mesh.triangles.emplace_back(q[0], q[1], q[2]);
        mesh.triangles.emplace_back(q[0], q[2], q[3]);
    }
}

InterfaceMesh
twoCubes()
{
    InterfaceMesh mesh;
    for (int z = 0; z < 2; ++z) {
        for (int y = 0; y < 2; ++y) {
            for (int x = 0; x < 3; ++x) {
                mesh.points.push_back(ORIGIN + SCALE * openvdb::Vec3d(x, y, z));
            }
        }
    }
    // Patch (a, b) has its normals pointing from a into b.
    // (-3, 0): cube A's faces but +x, outward from A.
    InterfacePatch p{-3, 0, mesh.triangles.size(), 0};
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            if (axis == 0 && side == 1) continue;
            addQuad(mesh, cubeFace(0, axis, side), false);
        }
    }
    p.triangleCount = mesh.triangles.size() - p.firstTriangle;
    mesh.patches.push_back(p);
    // (-3, 2): the shared face, +x, from A into B.
    p = InterfacePatch{-3, 2, mesh.triangles.size(), 0};
    addQuad(mesh, cubeFace(0, 0, 1), false);
    p.triangleCount = mesh.triangles.size() - p.firstTriangle;
    mesh.patches.push_back(p);
    // (0, 2): cube B's faces but -x, from outside into B, i.e. inward.
    p = InterfacePatch{0, 2, mesh.triangles.size(), 0};
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            if (axis == 0 && side == 0) continue;
            addQuad(mesh, cubeFace(1, axis, side), true);
        }
    }
    p.triangleCount = mesh.triangles.size() - p.firstTriangle;
    mesh.patches.push_back(p);
    return mesh;
}

// ---------------------------------------------------------------------------------------
// Independent readers


template<typename T>
T
readLE(const std::string& data, std::size_t& pos)
{
    if (pos + sizeof(T) > data.size()) throw std::runtime_error("read beyond the end");
    std::uint64_t bits = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) {
        bits |= std::uint64_t(static_cast<unsigned char>(data[pos + i])) << (8 * i);
    }
    pos += sizeof(T);
    T value;
    if constexpr (sizeof(T) == 8) {
        std::memcpy(&value, &bits, 8);
    } else if constexpr (sizeof(T) == 4) {
        const std::uint32_t b = static_cast<std::uint32_t>(bits);
        std::memcpy(&value, &b, 4);
    } else if constexpr (sizeof(T) == 2) {
        const std::uint16_t b = static_cast<std::uint16_t>(bits);
        std::memcpy(&value, &b, 2);
    } else {
        const std::uint8_t b = static_cast<std::uint8_t>(bits);
        std::memcpy(&value, &b, 1);
    }
    return value;
}

struct SimpleMesh
{
    std::vector<std::array<float, 3>> points;
    std::vector<std::array<std::int64_t, 3>> triangles;
    std::vector<std::array<Label, 2>> labels;
    std::vector<std::string> headerLines;
};

/// Binary little-endian PLY with float x y z, a uchar/int face list and optionally
/// int label0, label1 face properties.
SimpleMesh
readPly(const fs::path& path)
{
    const std::string data = readText(path);
    SimpleMesh mesh;
    std::size_t pos = 0;
    std::size_t vertexCount = 0, faceCount = 0;
    bool hasLabels = false;
    while (true) {
        const std::size_t eol = data.find('\n', pos);
        if (eol == std::string::npos) throw std::runtime_error("no end_header");
        const std::string line = data.substr(pos, eol - pos);
        pos = eol + 1;
        mesh.headerLines.push_back(line);
        std::istringstream ls(line);
        std::string word;
        ls >> word;
        if (word == "element") {
            std::string what;
            std::size_t count;
            ls >> what >> count;
            (what == "vertex" ? vertexCount : faceCount) = count;
        } else if (line == "property int label0") {
            hasLabels = true;
        } else if (word == "end_header") {
            break;
        }
    }
    for (std::size_t i = 0; i < vertexCount; ++i) {
        std::array<float, 3> p;
        for (float& c : p) c = readLE<float>(data, pos);
        mesh.points.push_back(p);
    }
    for (std::size_t i = 0; i < faceCount; ++i) {
        if (readLE<std::uint8_t>(data, pos) != 3) throw std::runtime_error("not a triangle");
        std::array<std::int64_t, 3> t;
        for (auto& v : t) v = readLE<std::int32_t>(data, pos);
        mesh.triangles.push_back(t);
        if (hasLabels) {
            const Label a = readLE<std::int32_t>(data, pos);
            const Label b = readLE<std::int32_t>(data, pos);
            mesh.labels.push_back({a, b});
        }
    }
    if (pos != data.size()) throw std::runtime_error("trailing bytes");
    return mesh;
}

/// Binary STL; points are merged by exact float equality.
SimpleMesh
readStl(const fs::path& path, std::string* header = nullptr)
{
    const std::string data = readText(path);
    if (header) *header = data.substr(0, 80);
    std::size_t pos = 80;
    const std::uint32_t count = readLE<std::uint32_t>(data, pos);
    SimpleMesh mesh;
    std::map<std::array<float, 3>, std::int64_t> index;
    for (std::uint32_t t = 0; t < count; ++t) {
        std::array<float, 3> normal;
        for (float& c : normal) c = readLE<float>(data, pos);
        std::array<std::int64_t, 3> tri;
        std::array<std::array<float, 3>, 3> corners;
        for (int k = 0; k < 3; ++k) {
            for (float& c : corners[k]) c = readLE<float>(data, pos);
            const auto it = index.emplace(corners[k], std::int64_t(mesh.points.size()));
            if (it.second) mesh.points.push_back(corners[k]);
            tri[k] = it.first->second;
        }
        // The stored normal must agree with the corner order.
        const openvdb::Vec3d p0(corners[0][0], corners[0][1], corners[0][2]);
        const openvdb::Vec3d p1(corners[1][0], corners[1][1], corners[1][2]);
        const openvdb::Vec3d p2(corners[2][0], corners[2][1], corners[2][2]);
        const openvdb::Vec3d n = (p1 - p0).cross(p2 - p0).unit();
        EXPECT_NEAR(n.dot(openvdb::Vec3d(normal[0], normal[1], normal[2])), 1.0, 1e-6);
        EXPECT_EQ(readLE<std::uint16_t>(data, pos), 0);
        mesh.triangles.push_back(tri);
    }
    if (pos != data.size()) throw std::runtime_error("trailing bytes");
    return mesh;
}

struct ObjFile
{
    std::vector<std::array<double, 3>> points;
    /// Group name -> triangles (0-based), in file order of the groups.
    std::vector<std::pair<std::string, std::vector<std::array<std::int64_t, 3>>>> groups;
};

ObjFile
readObj(const fs::path& path)
{
    std::ifstream in(path);
    ObjFile obj;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::string word;
        ls >> word;
        if (word == "v") {
            std::array<double, 3> p;
            ls >> p[0] >> p[1] >> p[2];
            obj.points.push_back(p);
        } else if (word == "g") {
            std::string name;
            ls >> name;
            obj.groups.emplace_back(name, std::vector<std::array<std::int64_t, 3>>());
        } else if (word == "f") {
            std::array<std::int64_t, 3> t;
            ls >> t[0] >> t[1] >> t[2];
            for (auto& v : t) --v;
            if (obj.groups.empty()) throw std::runtime_error("face outside a group");
            obj.groups.back().second.push_back(t);
        } else if (!word.empty() && word[0] != '#') {
            throw std::runtime_error("unexpected OBJ line: " + line);
        }
    }
    return obj;
}

/// The value of attribute @a name in the XML tag starting at @a tagPos.
std::string
xmlAttribute(const std::string& xml, std::size_t tagPos, const std::string& name)
{
    const std::size_t end = xml.find('>', tagPos);
    const std::string tag = xml.substr(tagPos, end - tagPos);
    const std::size_t at = tag.find(" " + name + "=\"");
    if (at == std::string::npos) return "";
    const std::size_t begin = at + name.size() + 3;
    return tag.substr(begin, tag.find('"', begin) - begin);
}

struct VtpFile
{
    std::size_t numberOfPoints = 0, numberOfPolys = 0;
    std::vector<std::array<float, 3>> points;
    std::vector<std::int64_t> connectivity, offsets;
    std::vector<std::array<Label, 2>> boundaryLabels;
};

/// Enough of the VTK XML format to decode what the writer claims: the header attributes, the
/// DataArray tags, and raw appended blocks with UInt64 byte counts.
VtpFile
readVtp(const fs::path& path)
{
    const std::string data = readText(path);
    const std::size_t appended = data.find("<AppendedData encoding=\"raw\">");
    if (appended == std::string::npos) throw std::runtime_error("no raw AppendedData");
    const std::size_t base = data.find('_', appended) + 1;
    const std::string xml = data.substr(0, appended);

    const std::size_t fileTag = xml.find("<VTKFile");
    EXPECT_EQ(xmlAttribute(xml, fileTag, "type"), "PolyData");
    EXPECT_EQ(xmlAttribute(xml, fileTag, "byte_order"), "LittleEndian");
    EXPECT_EQ(xmlAttribute(xml, fileTag, "header_type"), "UInt64");
    EXPECT_EQ(xmlAttribute(xml, fileTag, "version"), "1.0");

    VtpFile vtp;
    const std::size_t piece = xml.find("<Piece");
    vtp.numberOfPoints = std::stoull(xmlAttribute(xml, piece, "NumberOfPoints"));
    vtp.numberOfPolys = std::stoull(xmlAttribute(xml, piece, "NumberOfPolys"));

    // Each array must be inside the right element.
    const std::size_t cellData = xml.find("<CellData>"), cellDataEnd = xml.find("</CellData>");
    const std::size_t pointsTag = xml.find("<Points>"), pointsEnd = xml.find("</Points>");
    const std::size_t polys = xml.find("<Polys>"), polysEnd = xml.find("</Polys>");

    std::size_t pos = 0;
    int arrays = 0;
    while ((pos = xml.find("<DataArray", pos)) != std::string::npos) {
        ++arrays;
        const std::string name = xmlAttribute(xml, pos, "Name");
        const std::string type = xmlAttribute(xml, pos, "type");
        EXPECT_EQ(xmlAttribute(xml, pos, "format"), "appended");
        std::size_t at = base + std::stoull(xmlAttribute(xml, pos, "offset"));
        const std::uint64_t bytes = readLE<std::uint64_t>(data, at);
        if (name == "BoundaryLabels") {
            EXPECT_TRUE(pos > cellData && pos < cellDataEnd);
            EXPECT_EQ(type, "Int32");
            EXPECT_EQ(xmlAttribute(xml, pos, "NumberOfComponents"), "2");
            EXPECT_EQ(bytes, vtp.numberOfPolys * 8);
            for (std::size_t i = 0; i < bytes / 8; ++i) {
                const Label a = readLE<std::int32_t>(data, at);
                const Label b = readLE<std::int32_t>(data, at);
                vtp.boundaryLabels.push_back({a, b});
            }
        } else if (name == "Points") {
            EXPECT_TRUE(pos > pointsTag && pos < pointsEnd);
            EXPECT_EQ(type, "Float32");
            EXPECT_EQ(xmlAttribute(xml, pos, "NumberOfComponents"), "3");
            EXPECT_EQ(bytes, vtp.numberOfPoints * 12);
            for (std::size_t i = 0; i < bytes / 12; ++i) {
                std::array<float, 3> p;
                for (float& c : p) c = readLE<float>(data, at);
                vtp.points.push_back(p);
            }
        } else if (name == "connectivity" || name == "offsets") {
            EXPECT_TRUE(pos > polys && pos < polysEnd);
            EXPECT_EQ(type, "Int64");
            auto& out = name == "connectivity" ? vtp.connectivity : vtp.offsets;
            for (std::size_t i = 0; i < bytes / 8; ++i) out.push_back(readLE<std::int64_t>(data, at));
        } else {
            ADD_FAILURE() << "unexpected DataArray " << name;
        }
        ++pos;
    }
    EXPECT_EQ(arrays, 4);
    const std::string tail = "\n  </AppendedData>\n</VTKFile>\n";
    EXPECT_EQ(data.substr(data.size() - tail.size()), tail);
    return vtp;
}

/// Every directed edge once and its reverse once: closed and consistently oriented.
void
expectClosedAndOriented(const SimpleMesh& mesh, const std::string& what)
{
    std::map<std::pair<std::int64_t, std::int64_t>, int> edges;
    for (const auto& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
    }
    for (const auto& [edge, count] : edges) {
        EXPECT_EQ(count, 1) << what << ": edge " << edge.first << "-" << edge.second;
        const auto reverse = edges.find({edge.second, edge.first});
        EXPECT_TRUE(reverse != edges.end() && reverse->second == 1)
            << what << ": edge " << edge.first << "-" << edge.second << " is a border";
    }
}

double
signedVolume(const SimpleMesh& mesh)
{
    double volume = 0.0;
    for (const auto& t : mesh.triangles) {
        openvdb::Vec3d p[3];
        for (int k = 0; k < 3; ++k) {
            const auto& q = mesh.points[t[k]];
            p[k] = openvdb::Vec3d(q[0], q[1], q[2]);
        }
        volume += p[0].dot(p[1].cross(p[2])) / 6.0;
    }
    return volume;
}

std::array<float, 3>
toFloat(const openvdb::Vec3d& p)
{
    return {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
}

} // namespace

class TestMeshWriter : public ::testing::Test
{
protected:
    std::string file(const std::string& name) const { return mFolder.file(name); }

    vdbi_test::TempFolder mFolder;
};

TEST_F(TestMeshWriter, testTestMeshIsConsistent)
{
    // The fixture itself: every label's patches close up (checked through the per-label
    // writer below); here only the counts.
    const InterfaceMesh mesh = twoCubes();
    EXPECT_EQ(mesh.pointCount(), 12u);
    EXPECT_EQ(mesh.triangleCount(), 22u);
    ASSERT_EQ(mesh.patches.size(), 3u);
    EXPECT_EQ(mesh.patches[0].triangleCount, 10u);
    EXPECT_EQ(mesh.patches[1].triangleCount, 2u);
    EXPECT_EQ(mesh.patches[2].triangleCount, 10u);
}

TEST_F(TestMeshWriter, testPlyRoundTrip)
{
    const InterfaceMesh mesh = twoCubes();
    vdbi::writeInterfaceMesh(mesh, file("cubes.ply"));
    EXPECT_EQ(listFolder(mFolder.path()), std::vector<std::string>{"cubes.ply"});

    const SimpleMesh ply = readPly(file("cubes.ply"));
    ASSERT_GE(ply.headerLines.size(), 2u);
    EXPECT_EQ(ply.headerLines[0], "ply");
    EXPECT_EQ(ply.headerLines[1], "format binary_little_endian 1.0");
    const std::vector<std::string> expectedProperties = {"property float x",
        "property float y", "property float z", "property list uchar int vertex_indices",
        "property int label0", "property int label1"};
    for (const std::string& property : expectedProperties) {
        EXPECT_NE(std::find(ply.headerLines.begin(), ply.headerLines.end(), property),
                  ply.headerLines.end()) << property;
    }

    ASSERT_EQ(ply.points.size(), mesh.points.size());
    for (std::size_t i = 0; i < mesh.points.size(); ++i) {
        EXPECT_EQ(ply.points[i], toFloat(mesh.points[i])) << "point " << i;
    }
    ASSERT_EQ(ply.triangles.size(), mesh.triangles.size());
    const auto labels = mesh.triangleLabels();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) EXPECT_EQ(ply.triangles[t][k], mesh.triangles[t][k]);
        EXPECT_EQ(ply.labels[t], labels[t]) << "triangle " << t;
    }
    EXPECT_EQ(ply.labels.front(), (std::array<Label, 2>{-3, 0}));
    EXPECT_EQ(ply.labels.back(), (std::array<Label, 2>{0, 2}));
}

TEST_F(TestMeshWriter, testObjRoundTrip)
{
    const InterfaceMesh mesh = twoCubes();
    vdbi::writeInterfaceMesh(mesh, file("cubes.obj"));
    const ObjFile obj = readObj(file("cubes.obj"));

    // Text coordinates are the shortest exact decimal of the double.
    ASSERT_EQ(obj.points.size(), mesh.points.size());
    for (std::size_t i = 0; i < mesh.points.size(); ++i) {
        for (int k = 0; k < 3; ++k) EXPECT_EQ(obj.points[i][k], mesh.points[i][k]);
    }
    ASSERT_EQ(obj.groups.size(), 3u);
    const std::vector<std::string> names = {"patch_m3_0", "patch_m3_2", "patch_0_2"};
    for (std::size_t g = 0; g < 3; ++g) {
        EXPECT_EQ(obj.groups[g].first, names[g]);
        const InterfacePatch& patch = mesh.patches[g];
        ASSERT_EQ(obj.groups[g].second.size(), patch.triangleCount);
        for (std::size_t t = 0; t < patch.triangleCount; ++t) {
            for (int k = 0; k < 3; ++k) {
                EXPECT_EQ(obj.groups[g].second[t][k], mesh.triangles[patch.firstTriangle + t][k]);
            }
        }
    }
}

TEST_F(TestMeshWriter, testVtpRoundTrip)
{
    const InterfaceMesh mesh = twoCubes();
    vdbi::writeInterfaceMesh(mesh, file("cubes.vtp"));
    const VtpFile vtp = readVtp(file("cubes.vtp"));

    EXPECT_EQ(vtp.numberOfPoints, mesh.points.size());
    EXPECT_EQ(vtp.numberOfPolys, mesh.triangles.size());
    ASSERT_EQ(vtp.points.size(), mesh.points.size());
    for (std::size_t i = 0; i < mesh.points.size(); ++i) {
        EXPECT_EQ(vtp.points[i], toFloat(mesh.points[i])) << "point " << i;
    }
    ASSERT_EQ(vtp.connectivity.size(), 3 * mesh.triangles.size());
    ASSERT_EQ(vtp.offsets.size(), mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        EXPECT_EQ(vtp.offsets[t], std::int64_t(3 * (t + 1)));
        for (int k = 0; k < 3; ++k) EXPECT_EQ(vtp.connectivity[3 * t + k], mesh.triangles[t][k]);
    }
    EXPECT_EQ(vtp.boundaryLabels, mesh.triangleLabels());
}

TEST_F(TestMeshWriter, testEmptyMesh)
{
    // A volume of one label has no interfaces: every format must still be valid.
    const InterfaceMesh mesh;
    for (const std::string name : {"empty.ply", "empty.obj", "empty.vtp"}) {
        vdbi::writeInterfaceMesh(mesh, file(name));
        EXPECT_TRUE(fs::exists(file(name))) << name;
    }
    EXPECT_TRUE(readPly(file("empty.ply")).triangles.empty());
    EXPECT_TRUE(readObj(file("empty.obj")).groups.empty());
    const VtpFile vtp = readVtp(file("empty.vtp"));
    EXPECT_EQ(vtp.numberOfPoints, 0u);
    EXPECT_EQ(vtp.numberOfPolys, 0u);
    vdbi::writePerLabelSurfaces(mesh, mFolder.path().string());
    EXPECT_EQ(listFolder(mFolder.path()).size(), 3u);
}

TEST_F(TestMeshWriter, testUpperCaseExtension)
{
    vdbi::writeInterfaceMesh(twoCubes(), file("cubes.PLY"));
    EXPECT_EQ(readPly(file("cubes.PLY")).triangles.size(), 22u);
}

TEST_F(TestMeshWriter, testPerLabelStl)
{
    const InterfaceMesh mesh = twoCubes();
    vdbi::writePerLabelSurfaces(mesh, mFolder.path().string(), "stl");
    // The background 0 is skipped; negative labels are spelled with an m.
    EXPECT_EQ(listFolder(mFolder.path()), (std::vector<std::string>{"label_2.stl", "label_m3.stl"}));

    for (const std::string name : {"label_2.stl", "label_m3.stl"}) {
        std::string header;
        const SimpleMesh stl = readStl(file(name), &header);
        EXPECT_NE(header.rfind("solid", 0), 0u) << "binary STL must not start with 'solid'";
        EXPECT_EQ(stl.triangles.size(), 12u) << name;
        EXPECT_EQ(stl.points.size(), 8u) << name;
        expectClosedAndOriented(stl, name);
        // A unit cube scaled by SCALE, outward: positive volume SCALE^3.
        EXPECT_NEAR(signedVolume(stl), SCALE * SCALE * SCALE, 1e-6) << name;
    }
}

TEST_F(TestMeshWriter, testPerLabelPly)
{
    const InterfaceMesh mesh = twoCubes();
    // With background -3 the surfaces of 0 and 2 are written instead; 0's is the outside of
    // the two cubes, so its outward orientation points into them: negative volume.
    vdbi::writePerLabelSurfaces(mesh, mFolder.path().string(), "ply", /*background=*/-3);
    EXPECT_EQ(listFolder(mFolder.path()), (std::vector<std::string>{"label_0.ply", "label_2.ply"}));

    const SimpleMesh label2 = readPly(file("label_2.ply"));
    EXPECT_TRUE(label2.labels.empty());
    EXPECT_EQ(label2.triangles.size(), 12u);
    EXPECT_EQ(label2.points.size(), 8u);
    expectClosedAndOriented(label2, "label_2.ply");
    EXPECT_NEAR(signedVolume(label2), SCALE * SCALE * SCALE, 1e-6);

    // Label 0 only touches (-3,0) and (0,2): the outside of both cubes but the shared face.
    const SimpleMesh label0 = readPly(file("label_0.ply"));
    EXPECT_EQ(label0.triangles.size(), 20u);
    expectClosedAndOriented(label0, "label_0.ply");
    EXPECT_NEAR(signedVolume(label0), -2 * SCALE * SCALE * SCALE, 1e-6);

    // Only the points a label uses are written.
    for (const auto& p : label2.points) EXPECT_GE(p[0], static_cast<float>(ORIGIN[0] + SCALE) - 1e-6);
}

TEST_F(TestMeshWriter, testPerLabelFormats)
{
    const InterfaceMesh mesh = twoCubes();
    vdbi::writePerLabelSurfaces(mesh, mFolder.path().string(), ".STL");
    EXPECT_EQ(listFolder(mFolder.path()), (std::vector<std::string>{"label_2.stl", "label_m3.stl"}));
    EXPECT_THROW(vdbi::writePerLabelSurfaces(mesh, mFolder.path().string(), "obj"), openvdb::ValueError);
}

TEST_F(TestMeshWriter, testMissingFolder)
{
    const InterfaceMesh mesh = twoCubes();
    for (const std::string ext : {".ply", ".obj", ".vtp"}) {
        const std::string path = file("missing/out" + ext);
        try {
            vdbi::writeInterfaceMesh(mesh, path);
            ADD_FAILURE() << "no exception for " << path;
        } catch (const openvdb::IoError& e) {
            const std::string expected = "IoError: " + path + ": cannot open for writing: ";
            EXPECT_EQ(std::string(e.what()).rfind(expected, 0), 0u) << e.what();
            EXPECT_NE(std::string(e.what()).find("No such file or directory"),
                      std::string::npos) << e.what();
        }
    }
    EXPECT_TRUE(listFolder(mFolder.path()).empty());

    try {
        vdbi::writePerLabelSurfaces(mesh, file("missing"));
        ADD_FAILURE() << "no exception";
    } catch (const openvdb::IoError& e) {
        EXPECT_EQ(std::string(e.what()), "IoError: " + file("missing") + ": no such folder");
    }
    EXPECT_TRUE(listFolder(mFolder.path()).empty());
}

TEST_F(TestMeshWriter, testRenameFailureLeavesNothing)
{
    // The target is a folder: the temporary file is written, the rename fails, and the
    // temporary file must be gone afterwards.
    fs::create_directory(file("out.ply"));
    try {
        vdbi::writeInterfaceMesh(twoCubes(), file("out.ply"));
        ADD_FAILURE() << "no exception";
    } catch (const openvdb::IoError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("IoError: " + file("out.ply") + ": ", 0), 0u)
            << e.what();
    }
    EXPECT_EQ(listFolder(mFolder.path()), std::vector<std::string>{"out.ply"});
    EXPECT_TRUE(fs::is_directory(file("out.ply")));
}

TEST_F(TestMeshWriter, testUnknownExtension)
{
    for (const std::string name : {"out.stl", "out", "out.ply.bak"}) {
        try {
            vdbi::writeInterfaceMesh(twoCubes(), file(name));
            ADD_FAILURE() << "no exception for " << name;
        } catch (const openvdb::ValueError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(file(name)), std::string::npos) << what;
            EXPECT_NE(what.find("unknown mesh format"), std::string::npos) << what;
        }
    }
    EXPECT_TRUE(listFolder(mFolder.path()).empty());
}

TEST_F(TestMeshWriter, testInvalidMesh)
{
    InterfaceMesh mesh = twoCubes();
    mesh.triangles[3][1] = 12; // one past the points
    EXPECT_THROW(vdbi::writeInterfaceMesh(mesh, file("bad.ply")), openvdb::ValueError);
    mesh = twoCubes();
    mesh.patches.pop_back(); // triangles outside every patch
    EXPECT_THROW(vdbi::writeInterfaceMesh(mesh, file("bad.obj")), openvdb::ValueError);
    EXPECT_TRUE(listFolder(mFolder.path()).empty());
}

TEST_F(TestMeshWriter, testReplacesExistingFile)
{
    {
        std::ofstream old(file("cubes.ply"));
        old << "old content";
    }
    vdbi::writeInterfaceMesh(twoCubes(), file("cubes.ply"));
    EXPECT_EQ(readPly(file("cubes.ply")).triangles.size(), 22u);
    EXPECT_EQ(listFolder(mFolder.path()), std::vector<std::string>{"cubes.ply"});
}

TEST_F(TestMeshWriter, testAtomicFileBodyThrows)
{
    // An exception while writing propagates unchanged and leaves neither file.
    EXPECT_THROW(vdbi::writeFileAtomically(file("report.json"), [](std::ostream& os) {
        os << "{ \"half\": ";
        throw std::runtime_error("stop");
    }), std::runtime_error);
    EXPECT_TRUE(listFolder(mFolder.path()).empty());

    // The same with an existing target: it keeps its content.
    {
        std::ofstream old(file("report.json"));
        old << "old";
    }
    EXPECT_THROW(vdbi::writeFileAtomically(file("report.json"), [](std::ostream&) {
        throw openvdb::ValueError("stop");
    }), openvdb::ValueError);
    EXPECT_EQ(readText(file("report.json")), "old");
    EXPECT_EQ(listFolder(mFolder.path()), std::vector<std::string>{"report.json"});
}

TEST_F(TestMeshWriter, testAtomicFileCommitAndDiscard)
{
    {
        vdbi::AtomicFile out(file("a.txt"), /*binary=*/false);
        EXPECT_EQ(out.tempPath(), file("a.txt") + ".tmp-" + std::to_string(::getpid()));
        out.stream() << "hello\n";
        EXPECT_TRUE(fs::exists(out.tempPath()));
        EXPECT_FALSE(fs::exists(file("a.txt")));
        out.commit();
        EXPECT_TRUE(out.isCommitted());
        EXPECT_FALSE(fs::exists(out.tempPath()));
    }
    EXPECT_EQ(readText(file("a.txt")), "hello\n");
    {
        vdbi::AtomicFile out(file("b.txt"));
        out.stream() << "never";
        // Destroyed without commit.
    }
    EXPECT_EQ(listFolder(mFolder.path()), std::vector<std::string>{"a.txt"});

    vdbi::AtomicFile failing(file("c.txt"));
    try {
        failing.fail("disk on fire");
    } catch (const openvdb::IoError& e) {
        EXPECT_EQ(std::string(e.what()), "IoError: " + file("c.txt") + ": disk on fire");
    }
    EXPECT_EQ(listFolder(mFolder.path()), std::vector<std::string>{"a.txt"});
}

TEST_F(TestMeshWriter, testAtomicFileFailedStream)
{
    // A stream that went bad while writing (as on a full disk) must not be committed.
    vdbi::AtomicFile out(file("d.txt"));
    out.stream() << "partial";
    out.stream().setstate(std::ios::badbit);
    EXPECT_THROW(out.commit(), openvdb::IoError);
    EXPECT_TRUE(listFolder(mFolder.path()).empty());
}

TEST_F(TestMeshWriter, testRemoveAllTemporaryFiles)
{
    // The cleanup closes the registry for the whole process, so it runs in a child: one
    // started afresh ("threadsafe"), since a plain fork of a process with TBB workers can
    // hang; _Exit skips the static destructors for the same reason.
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const std::string path = file("e.txt");
    EXPECT_EXIT({
        vdbi::AtomicFile out(path);
        out.stream() << "partial";
        out.stream().flush();
        vdbi::removeAllTemporaryFiles();
        const bool removed = !fs::exists(out.tempPath());
        bool refused = false;
        try {
            vdbi::AtomicFile late(file("f.txt"));
        } catch (const openvdb::IoError&) {
            refused = true;
        }
        const bool passed = removed && refused && listFolder(mFolder.path()).empty();
        // _Exit skips the fixture's destructor: the child's own folder goes here.
        std::error_code ec;
        fs::remove_all(mFolder.path(), ec);
        std::_Exit(passed ? 0 : 1);
    }, ::testing::ExitedWithCode(0), "");
    EXPECT_TRUE(listFolder(mFolder.path()).empty());
}
