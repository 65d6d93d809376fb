// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/MeshWriter.cc
/// @brief Hand-written .ply, .obj, .vtp and binary .stl writers over the flat InterfaceMesh.
/// @details Why not OpenMesh's IO for the per-label surfaces: going through a TriMesh means
/// add_face(), which refuses faces at complex edges or vertices (it prints a warning and
/// drops the face), so a label whose surface touches itself would silently lose triangles.
/// Binary STL and PLY are a few lines each, and writing them directly keeps every file on
/// the same atomic, stream-checked path.
///
/// Coordinates: the binary formats (.ply, .vtp, .stl) store 32-bit floats, which every
/// viewer reads (double PLY properties are not universally supported) at half the size;
/// float's 24-bit mantissa keeps a relative precision of 6e-8, far below the subvoxel
/// spacing for any volume that fits in memory. .obj is text and stores the shortest
/// decimal that reads back as the exact double.

#include <vdbi/MeshWriter.h>

#include <vdbi/AtomicFile.h>

#include <openvdb/Exceptions.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <ostream>
#include <sstream>
#include <system_error>

namespace vdbi {

namespace {

/// Collects bytes in a buffer and hands them to the stream in large blocks; values are
/// encoded little-endian byte by byte, so the output does not depend on the host.
class ByteSink
{
public:
    explicit ByteSink(std::ostream& os) : mStream(os) { mBuffer.reserve(CAPACITY); }

    template<typename UInt>
    void putUnsigned(UInt value)
    {
        static_assert(std::is_unsigned<UInt>::value, "unsigned only");
        for (std::size_t i = 0; i < sizeof(UInt); ++i) {
            mBuffer.push_back(static_cast<char>((value >> (8 * i)) & 0xFFu));
        }
        if (mBuffer.size() >= CAPACITY) flush();
    }
    void putU8(std::uint8_t v) { putUnsigned(v); }
    void putU16(std::uint16_t v) { putUnsigned(v); }
    void putU32(std::uint32_t v) { putUnsigned(v); }
    void putU64(std::uint64_t v) { putUnsigned(v); }
    void putI32(std::int32_t v) { putUnsigned(static_cast<std::uint32_t>(v)); }
    void putI64(std::int64_t v) { putUnsigned(static_cast<std::uint64_t>(v)); }
    void putF32(float v)
    {
        static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559,
            "IEEE 754 single precision floats required");
        std::uint32_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        putUnsigned(bits);
    }
    void putText(const std::string& text)
    {
        mBuffer.insert(mBuffer.end(), text.begin(), text.end());
        if (mBuffer.size() >= CAPACITY) flush();
    }
    void flush()
    {
        if (!mBuffer.empty()) {
            mStream.write(mBuffer.data(), static_cast<std::streamsize>(mBuffer.size()));
            mBuffer.clear();
        }
    }

private:
    static constexpr std::size_t CAPACITY = 1 << 20;
    std::ostream& mStream;
    std::vector<char> mBuffer;
};

std::string
lowerCase(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(),
        [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

/// The extension of @a path without the dot, lower case.
std::string
extensionOf(const std::string& path)
{
    std::string ext = std::filesystem::path(path).extension().string();
    if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
    return lowerCase(ext);
}

/// A label as it appears in names: "m" instead of the minus sign, so names stay plain words
/// ("patch_m3_5", "label_m3.stl") for tools that split on '-' or take it for an option.
std::string
labelToken(Label label)
{
    if (label < 0) {
        return "m" + std::to_string(-static_cast<std::int64_t>(label));
    }
    return std::to_string(label);
}

/// Checks what the writers rely on: indices in range, every triangle in exactly one patch.
void
validateMesh(const InterfaceMesh& mesh)
{
    const std::size_t n = mesh.points.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const openvdb::Vec3I& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            if (tri[k] >= n) {
                OPENVDB_THROW(openvdb::ValueError, "invalid InterfaceMesh: triangle " << t
                    << " refers to point " << tri[k] << " of " << n);
            }
        }
    }
    std::vector<char> covered(mesh.triangles.size(), 0);
    for (const InterfacePatch& p : mesh.patches) {
        if (p.firstTriangle > mesh.triangles.size()
            || p.triangleCount > mesh.triangles.size() - p.firstTriangle)
        {
            OPENVDB_THROW(openvdb::ValueError, "invalid InterfaceMesh: patch (" << p.a << ", "
                << p.b << ") covers triangles beyond the " << mesh.triangles.size()
                << " there are");
        }
        for (std::size_t t = p.firstTriangle; t < p.firstTriangle + p.triangleCount; ++t) {
            if (covered[t]++) {
                OPENVDB_THROW(openvdb::ValueError,
                    "invalid InterfaceMesh: triangle " << t << " is in two patches");
            }
        }
    }
    const auto missing = std::find(covered.begin(), covered.end(), 0);
    if (missing != covered.end()) {
        OPENVDB_THROW(openvdb::ValueError, "invalid InterfaceMesh: triangle "
            << (missing - covered.begin()) << " is in no patch");
    }
}

/// The formats index points with 32-bit signed integers.
void
checkIndexRange(const std::string& path, std::size_t pointCount, std::size_t triangleCount)
{
    constexpr auto maxIndex = static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
    if (pointCount > maxIndex || triangleCount > maxIndex) {
        OPENVDB_THROW(openvdb::IoError, path << ": " << pointCount << " points and "
            << triangleCount << " triangles exceed the format's 32-bit indices");
    }
}

// ---------------------------------------------------------------------------------------
// PLY

/// The patches with triangles, in triangle order: after validateMesh() their ranges tile the
/// triangles, so a writer reads each triangle's label pair from them in turn, without an
/// array of pairs (55 MB for frog).
std::vector<InterfacePatch>
patchesInTriangleOrder(const std::vector<InterfacePatch>& patches)
{
    std::vector<InterfacePatch> order;
    for (const InterfacePatch& p : patches) {
        if (p.triangleCount > 0) order.push_back(p);
    }
    std::sort(order.begin(), order.end(), [](const InterfacePatch& x, const InterfacePatch& y) {
        return x.firstTriangle < y.firstTriangle;
    });
    return order;
}

/// Binary little-endian PLY; @a patches (covering every triangle) adds the face properties
/// label0 and label1.
void
writePlyBody(std::ostream& os, const PointArray& points, const TriangleArray& triangles,
             const std::vector<InterfacePatch>* patches, const std::string& comment)
{
    const bool labels = patches != nullptr;
    std::ostringstream header;
    header << "ply\n"
           << "format binary_little_endian 1.0\n";
    if (!comment.empty()) header << "comment " << comment << "\n";
    header << "element vertex " << points.size() << "\n"
           << "property float x\n"
           << "property float y\n"
           << "property float z\n"
           << "element face " << triangles.size() << "\n"
           << "property list uchar int vertex_indices\n";
    if (labels) {
        header << "property int label0\n"
               << "property int label1\n";
    }
    header << "end_header\n";

    ByteSink sink(os);
    sink.putText(header.str());
    for (const openvdb::Vec3d& p : points) {
        for (int k = 0; k < 3; ++k) sink.putF32(static_cast<float>(p[k]));
    }
    auto putTriangle = [&](const openvdb::Vec3I& t) {
        sink.putU8(3);
        for (int k = 0; k < 3; ++k) sink.putI32(static_cast<std::int32_t>(t[k]));
    };
    if (!labels) {
        for (const openvdb::Vec3I& t : triangles) putTriangle(t);
    } else {
        for (const InterfacePatch& p : patchesInTriangleOrder(*patches)) {
            for (std::size_t t = p.firstTriangle; t < p.firstTriangle + p.triangleCount; ++t) {
                putTriangle(triangles[t]);
                sink.putI32(p.a);
                sink.putI32(p.b);
            }
        }
    }
    sink.flush();
}

// ---------------------------------------------------------------------------------------
// OBJ

void
appendNumber(std::string& out, double value)
{
    char buffer[64];
    // Shortest representation that reads back as the same double.
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    out.append(buffer, result.ptr);
}

void
appendNumber(std::string& out, std::size_t value)
{
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    out.append(buffer, result.ptr);
}

void
writeObjBody(std::ostream& os, const InterfaceMesh& mesh)
{
    std::string out;
    out.reserve(1 << 20);
    const auto flushIfFull = [&]() {
        if (out.size() >= (1u << 20)) {
            os.write(out.data(), static_cast<std::streamsize>(out.size()));
            out.clear();
        }
    };

    out += "# VDB Interfaces: interface patches between labels.\n"
           "# Group patch_A_B holds the triangles between labels A < B, counter-clockwise\n"
           "# seen from label B; an m marks a negative label (patch_m3_5: -3 and 5).\n";
    out += "# ";
    appendNumber(out, mesh.points.size());
    out += " vertices, ";
    appendNumber(out, mesh.triangles.size());
    out += " triangles, ";
    appendNumber(out, mesh.patches.size());
    out += " patches\n";

    for (const openvdb::Vec3d& p : mesh.points) {
        out += "v ";
        appendNumber(out, p[0]);
        out += ' ';
        appendNumber(out, p[1]);
        out += ' ';
        appendNumber(out, p[2]);
        out += '\n';
        flushIfFull();
    }
    for (const InterfacePatch& patch : mesh.patches) {
        out += "g patch_" + labelToken(patch.a) + "_" + labelToken(patch.b) + "\n";
        for (std::size_t t = patch.firstTriangle; t < patch.firstTriangle + patch.triangleCount;
             ++t)
        {
            out += 'f';
            for (int k = 0; k < 3; ++k) {
                out += ' ';
                appendNumber(out, static_cast<std::size_t>(mesh.triangles[t][k]) + 1);
            }
            out += '\n';
            flushIfFull();
        }
    }
    os.write(out.data(), static_cast<std::streamsize>(out.size()));
}

// ---------------------------------------------------------------------------------------
// VTP

/// VTK XML PolyData, version 1.0 with 64-bit block headers, all arrays in one raw appended
/// block: the layout VTK's own writer produces with SetDataModeToAppended() and
/// EncodeAppendedDataOff(), so no base64 and no size limit.
void
writeVtpBody(std::ostream& os, const InterfaceMesh& mesh)
{
    const std::uint64_t n = mesh.points.size();
    const std::uint64_t m = mesh.triangles.size();
    const std::uint64_t labelBytes = m * 2 * sizeof(std::int32_t);
    const std::uint64_t pointBytes = n * 3 * sizeof(float);
    const std::uint64_t connectivityBytes = m * 3 * sizeof(std::int64_t);
    const std::uint64_t offsetBytes = m * sizeof(std::int64_t);
    // Each block is its UInt64 byte count followed by the data; offsets count from the byte
    // after the '_' that opens the appended data.
    const std::uint64_t labelOffset = 0;
    const std::uint64_t pointOffset = labelOffset + 8 + labelBytes;
    const std::uint64_t connectivityOffset = pointOffset + 8 + pointBytes;
    const std::uint64_t offsetOffset = connectivityOffset + 8 + connectivityBytes;

    std::ostringstream xml;
    xml << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\""
           " header_type=\"UInt64\">\n"
        << "  <PolyData>\n"
        << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfVerts=\"0\" NumberOfLines=\"0\""
           " NumberOfStrips=\"0\" NumberOfPolys=\"" << m << "\">\n"
        << "      <CellData>\n"
        << "        <DataArray type=\"Int32\" Name=\"BoundaryLabels\" NumberOfComponents=\"2\""
           " format=\"appended\" offset=\"" << labelOffset << "\"/>\n"
        << "      </CellData>\n"
        << "      <Points>\n"
        << "        <DataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\""
           " format=\"appended\" offset=\"" << pointOffset << "\"/>\n"
        << "      </Points>\n"
        << "      <Polys>\n"
        << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\""
           " offset=\"" << connectivityOffset << "\"/>\n"
        << "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\""
           " offset=\"" << offsetOffset << "\"/>\n"
        << "      </Polys>\n"
        << "    </Piece>\n"
        << "  </PolyData>\n"
        << "  <AppendedData encoding=\"raw\">\n"
        << "   _";

    ByteSink sink(os);
    sink.putText(xml.str());

    sink.putU64(labelBytes);
    for (const InterfacePatch& p : patchesInTriangleOrder(mesh.patches)) {
        for (std::size_t t = 0; t < p.triangleCount; ++t) {
            sink.putI32(p.a);
            sink.putI32(p.b);
        }
    }

    sink.putU64(pointBytes);
    for (const openvdb::Vec3d& p : mesh.points) {
        for (int k = 0; k < 3; ++k) sink.putF32(static_cast<float>(p[k]));
    }

    sink.putU64(connectivityBytes);
    for (const openvdb::Vec3I& tri : mesh.triangles) {
        for (int k = 0; k < 3; ++k) sink.putI64(static_cast<std::int64_t>(tri[k]));
    }

    // VTK's offsets are the end of each cell in the connectivity array (no leading 0).
    sink.putU64(offsetBytes);
    for (std::uint64_t t = 1; t <= m; ++t) sink.putI64(static_cast<std::int64_t>(3 * t));

    sink.putText("\n  </AppendedData>\n</VTKFile>\n");
    sink.flush();
}

// ---------------------------------------------------------------------------------------
// STL

/// Binary STL: 80-byte header, triangle count, then per triangle the unit normal, three
/// corners and a zero attribute word. The normal is computed from the float corners so it
/// agrees with what a reader sees.
void
writeStlBody(std::ostream& os, const PointArray& points, const TriangleArray& triangles,
             const std::string& title)
{
    ByteSink sink(os);
    // The header must not start with "solid", which readers take for ASCII STL.
    std::string header = title.substr(0, 80);
    header.resize(80, ' ');
    sink.putText(header);
    sink.putU32(static_cast<std::uint32_t>(triangles.size()));
    for (const openvdb::Vec3I& tri : triangles) {
        openvdb::Vec3d corner[3];
        for (int k = 0; k < 3; ++k) {
            const openvdb::Vec3d& p = points[tri[k]];
            corner[k] = openvdb::Vec3d(static_cast<float>(p[0]), static_cast<float>(p[1]),
                                       static_cast<float>(p[2]));
        }
        openvdb::Vec3d normal = (corner[1] - corner[0]).cross(corner[2] - corner[0]);
        const double length = normal.length();
        normal = length > 0.0 ? normal / length : openvdb::Vec3d(0.0);
        for (int k = 0; k < 3; ++k) sink.putF32(static_cast<float>(normal[k]));
        for (int c = 0; c < 3; ++c) {
            for (int k = 0; k < 3; ++k) sink.putF32(static_cast<float>(corner[c][k]));
        }
        sink.putU16(0);
    }
    sink.flush();
}

} // namespace

// ---------------------------------------------------------------------------------------

void
writeInterfaceMesh(const InterfaceMesh& mesh, const std::string& path)
{
    const std::string ext = extensionOf(path);
    if (ext != "ply" && ext != "obj" && ext != "vtp") {
        OPENVDB_THROW(openvdb::ValueError, path << ": unknown mesh format \""
            << std::filesystem::path(path).extension().string()
            << "\" (expected .ply, .obj or .vtp)");
    }
    validateMesh(mesh);

    if (ext == "ply") {
        checkIndexRange(path, mesh.points.size(), mesh.triangles.size());
        writeFileAtomically(path, [&](std::ostream& os) {
            writePlyBody(os, mesh.points, mesh.triangles, &mesh.patches,
                "VDB Interfaces: label0 < label1, triangles counter-clockwise seen from label1");
        });
    } else if (ext == "obj") {
        writeFileAtomically(path, [&](std::ostream& os) { writeObjBody(os, mesh); });
    } else {
        writeFileAtomically(path, [&](std::ostream& os) { writeVtpBody(os, mesh); });
    }
}

void
writePerLabelSurfaces(const InterfaceMesh& mesh, const std::string& dir, const std::string& ext,
                      Label background)
{
    std::string format = lowerCase(ext);
    if (!format.empty() && format[0] == '.') format.erase(0, 1);
    if (format != "stl" && format != "ply") {
        OPENVDB_THROW(openvdb::ValueError, "unknown surface format \"" << ext
            << "\" (expected stl or ply)");
    }
    validateMesh(mesh);

    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) {
        OPENVDB_THROW(openvdb::IoError, dir << ": no such folder");
    }

    // The labels that own at least one triangle, in increasing order.
    std::vector<Label> labels;
    for (const InterfacePatch& p : mesh.patches) {
        if (p.triangleCount == 0) continue;
        labels.push_back(p.a);
        labels.push_back(p.b);
    }
    std::sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
    labels.erase(std::remove(labels.begin(), labels.end(), background), labels.end());

    // Marks which points the current label uses; only touched entries are reset, so the
    // cost is the label's size, not the mesh's.
    constexpr std::uint32_t UNUSED = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> remap(mesh.points.size(), UNUSED);

    for (const Label label : labels) {
        PointArray points;
        TriangleArray triangles;
        std::vector<std::uint32_t> used;
        for (const InterfacePatch& p : mesh.patches) {
            if (p.a != label && p.b != label) continue;
            // Patch normals point from a into b: outward for a, inward for b.
            const bool flip = (p.b == label);
            for (std::size_t t = p.firstTriangle; t < p.firstTriangle + p.triangleCount; ++t) {
                openvdb::Vec3I tri = mesh.triangles[t];
                if (flip) std::swap(tri[1], tri[2]);
                for (int k = 0; k < 3; ++k) {
                    std::uint32_t& r = remap[tri[k]];
                    if (r == UNUSED) {
                        r = static_cast<std::uint32_t>(points.size());
                        points.push_back(mesh.points[tri[k]]);
                        used.push_back(tri[k]);
                    }
                    tri[k] = r;
                }
                triangles.push_back(tri);
            }
        }
        for (const std::uint32_t i : used) remap[i] = UNUSED;

        const std::string path =
            (std::filesystem::path(dir) / ("label_" + labelToken(label) + "." + format)).string();
        const std::string title = "VDB Interfaces: closed surface of label "
            + std::to_string(label) + ", outward oriented";
        checkIndexRange(path, points.size(), triangles.size());
        if (format == "stl") {
            writeFileAtomically(path, [&](std::ostream& os) {
                writeStlBody(os, points, triangles, title);
            });
        } else {
            writeFileAtomically(path, [&](std::ostream& os) {
                writePlyBody(os, points, triangles, nullptr, title);
            });
        }
    }
}

} // namespace vdbi
