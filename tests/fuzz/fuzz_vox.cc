// SPDX-License-Identifier: Apache-2.0
/// @file fuzz/fuzz_vox.cc
/// @brief Fuzz target: vdbi::readVoxBuffer on arbitrary bytes.
/// @details Bad input must end in an openvdb::Exception; a grid that comes back must hold what
/// the format can express (palette indices 1..255 at coordinates 0..255). Anything else (a
/// crash, a sanitizer report, another exception, a violated property) is a finding. Built with
/// -fsanitize=fuzzer for libFuzzer, or with replay_main.cc for the test suite.

#include <vdbi/VoxReader.h>

#include <openvdb/Exceptions.h>
#include <openvdb/openvdb.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int
LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    static const bool initialized = (openvdb::initialize(), true);
    (void)initialized;

    openvdb::Int32Grid::Ptr grid;
    try {
        grid = vdbi::readVoxBuffer(data, size, "fuzz.vox");
    } catch (const openvdb::Exception&) {
        return 0; // rejected bad input: expected
    }
    if (!grid || grid->background() != 0) {
        std::fprintf(stderr, "fuzz_vox: no grid or a background other than 0\n");
        std::abort();
    }
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        const openvdb::Coord ijk = it.getCoord();
        const bool inside = it.isVoxelValue() && ijk.x() >= 0 && ijk.y() >= 0 && ijk.z() >= 0
            && ijk.x() < 256 && ijk.y() < 256 && ijk.z() < 256;
        if (!inside || *it < 1 || *it > 255) {
            std::fprintf(stderr, "fuzz_vox: voxel (%d, %d, %d) = %d is not a palette index in"
                " the model\n", ijk.x(), ijk.y(), ijk.z(), int(*it));
            std::abort();
        }
    }
    return 0;
}
