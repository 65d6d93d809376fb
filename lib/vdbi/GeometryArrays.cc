// SPDX-License-Identifier: Apache-2.0

#include <vdbi/GeometryArrays.h>

#include <openvdb/Exceptions.h>

#include <charconv>
#include <cstdlib>  // for std::abs on long long
#include <limits>
#include <sstream>
#include <system_error>

namespace vdbi {

namespace {

constexpr std::size_t MAX_INT = static_cast<std::size_t>(std::numeric_limits<int>::max());

bool
isSeparator(char c, bool semicolon)
{
    return c == ' ' || c == '\t' || c == ',' || c == '\r' || c == '\n'
        || (semicolon && c == ';');
}

/// Splits @a text at separators; ';' separates only when @a semicolon.
std::vector<std::string>
tokens(const std::string& text, bool semicolon)
{
    std::vector<std::string> result;
    std::size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && isSeparator(text[i], semicolon)) ++i;
        const std::size_t start = i;
        while (i < text.size() && !isSeparator(text[i], semicolon)) ++i;
        if (i > start) result.push_back(text.substr(start, i - start));
    }
    return result;
}

/// @throw openvdb::ValueError naming @a token
Label
parseLabel(const std::string& token, const char* what, const std::string& context)
{
    // from_chars takes a '-' but no '+'.
    const std::size_t skip = (token.size() > 1 && token[0] == '+' && token[1] != '-') ? 1 : 0;
    const char* last = token.data() + token.size();
    Label value = 0;
    const auto [end, error] = std::from_chars(token.data() + skip, last, value);
    if (error == std::errc::result_out_of_range) {
        OPENVDB_THROW(openvdb::ValueError, what << " \"" << context << "\": '" << token
            << "' is out of the range of a 32-bit label");
    }
    if (error != std::errc() || end != last) {
        OPENVDB_THROW(openvdb::ValueError, what << " \"" << context << "\": '" << token
            << "' is not an integer label");
    }
    return value;
}

std::string
trimmed(const std::string& text)
{
    const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    std::size_t begin = 0, end = text.size();
    while (begin < end && space(text[begin])) ++begin;
    while (end > begin && space(text[end - 1])) --end;
    return text.substr(begin, end - begin);
}

} // namespace


GeometryArrays
makeGeometryArrays(const InterfaceMesh& mesh)
{
    const std::size_t pointCount = mesh.points.size();
    const std::size_t triangleCount = mesh.triangles.size();
    if (pointCount > MAX_INT || triangleCount > MAX_INT / 3 || mesh.patches.size() > MAX_INT) {
        OPENVDB_THROW(openvdb::ValueError, "the mesh is too large for int indices: "
            << pointCount << " points, " << triangleCount << " triangles");
    }

    GeometryArrays arrays;
    arrays.points.resize(3 * pointCount);
    for (std::size_t i = 0; i < pointCount; ++i) {
        for (int c = 0; c < 3; ++c) {
            arrays.points[3 * i + c] = static_cast<float>(mesh.points[i][c]);
        }
    }

    arrays.vertices.resize(3 * triangleCount);
    for (std::size_t t = 0; t < triangleCount; ++t) {
        for (int c = 0; c < 3; ++c) {
            const openvdb::Index32 index = mesh.triangles[t][c];
            if (index >= pointCount) {
                OPENVDB_THROW(openvdb::ValueError, "triangle " << t << " refers to point "
                    << index << " of " << pointCount);
            }
            arrays.vertices[3 * t + c] = static_cast<int>(index);
        }
    }

    arrays.polyCounts.assign(triangleCount, 3);
    arrays.labelA.assign(triangleCount, 0);
    arrays.labelB.assign(triangleCount, 0);
    arrays.patch.assign(triangleCount, -1);
    arrays.patchNames.reserve(mesh.patches.size());
    for (std::size_t p = 0; p < mesh.patches.size(); ++p) {
        const InterfacePatch& patch = mesh.patches[p];
        if (patch.firstTriangle > triangleCount
            || patch.triangleCount > triangleCount - patch.firstTriangle)
        {
            OPENVDB_THROW(openvdb::ValueError, "patch " << p << " (" << patch.a << ", "
                << patch.b << ") refers to triangles past the end (" << triangleCount << ")");
        }
        for (std::size_t t = patch.firstTriangle;
             t < patch.firstTriangle + patch.triangleCount; ++t)
        {
            arrays.labelA[t] = patch.a;
            arrays.labelB[t] = patch.b;
            arrays.patch[t] = static_cast<int>(p);
        }
        arrays.patchNames.push_back(patchName(patch.a, patch.b));
    }
    for (std::size_t t = 0; t < triangleCount; ++t) {
        if (arrays.patch[t] < 0) {
            OPENVDB_THROW(openvdb::ValueError, "triangle " << t << " belongs to no patch");
        }
    }
    return arrays;
}


std::string
patchName(Label a, Label b)
{
    const auto label = [](Label l) {
        // Through long long: -INT32_MIN does not fit a Label.
        const long long value = l;
        return (value < 0 ? "m" : "") + std::to_string(std::abs(value));
    };
    return "patch_" + label(a) + "_" + label(b);
}


std::vector<SeparationConstraint>
parseConstraints(const std::string& text)
{
    std::vector<SeparationConstraint> constraints;
    std::size_t begin = 0;
    while (begin <= text.size()) {
        std::size_t end = text.find_first_of(";\n", begin);
        if (end == std::string::npos) end = text.size();
        const std::string part = text.substr(begin, end - begin);
        const std::vector<std::string> labels = tokens(part, /*semicolon=*/false);
        if (!labels.empty()) {
            const std::string context = trimmed(part);
            if (labels.size() != 3) {
                OPENVDB_THROW(openvdb::ValueError, "constraint \"" << context << "\" has "
                    << labels.size() << (labels.size() == 1 ? " label" : " labels")
                    << ", expected three: A B C (A and B always separated by C)");
            }
            SeparationConstraint c;
            c.a = parseLabel(labels[0], "constraint", context);
            c.b = parseLabel(labels[1], "constraint", context);
            c.separator = parseLabel(labels[2], "constraint", context);
            constraints.push_back(c);
        }
        begin = end + 1;
    }
    return constraints;
}


std::vector<Label>
parseLabels(const std::string& text)
{
    std::vector<Label> labels;
    const std::string context = trimmed(text);
    for (const std::string& token : tokens(text, /*semicolon=*/false)) {
        labels.push_back(parseLabel(token, "label list", context));
    }
    return labels;
}

} // namespace vdbi
