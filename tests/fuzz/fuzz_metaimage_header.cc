// SPDX-License-Identifier: Apache-2.0
/// @file fuzz/fuzz_metaimage_header.cc
/// @brief Fuzz target: vdbi::parseMetaImageHeader on arbitrary bytes.
/// @details Bad input must end in an openvdb::Exception; a header that parses must be
/// consistent (positive sizes, byte counts without overflow, the end of the header inside the
/// input, the stream left there). Anything else is a finding.

#include <vdbi/MetaImageReader.h>

#include <openvdb/Exceptions.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace {

[[noreturn]] void
fail(const char* what)
{
    std::fprintf(stderr, "fuzz_metaimage_header: %s\n", what);
    std::abort();
}

} // namespace

extern "C" int
LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    vdbi::MetaImageHeader header;
    try {
        header = vdbi::parseMetaImageHeader(in, "fuzz.mhd");
    } catch (const openvdb::Exception&) {
        return 0; // rejected bad input: expected
    }
    // The parser promises that the byte count of the data fits 64 bits.
    std::uint64_t voxels = 1, bytes = 0;
    for (const std::int32_t n : header.dimSize) {
        if (n < 1) fail("a DimSize below 1 was accepted");
        if (__builtin_mul_overflow(voxels, std::uint64_t(n), &voxels)) {
            fail("DimSize overflows 64 bits but was accepted");
        }
    }
    const std::uint64_t elementBytes = std::uint64_t(vdbi::metaElementBytes(header.elementType));
    if (elementBytes != 1 && elementBytes != 2 && elementBytes != 4) fail("element size");
    if (__builtin_mul_overflow(voxels, elementBytes, &bytes)) {
        fail("the data size overflows 64 bits but was accepted");
    }
    if (header.voxelCount() != voxels) fail("voxelCount() is not the product of DimSize");
    if (header.dataBytes() != bytes) fail("dataBytes() is not voxelCount() x element size");
    if (header.headerBytes > size) fail("the header ends after the input");
    const std::streamoff at = in.tellg();
    if (at != -1 && std::uint64_t(at) != header.headerBytes) {
        fail("the stream is not left at the end of the header");
    }
    if (header.elementDataFile.empty()) fail("an empty ElementDataFile was accepted");
    if (header.headerSize < -1 || header.compressedDataSize < -1) fail("negative sizes");
    for (int k = 0; k < 3; ++k) {
        if (!(header.spacing[k] > 0.0)) fail("a spacing <= 0 was accepted");
    }
    return 0;
}
