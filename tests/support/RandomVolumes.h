// SPDX-License-Identifier: Apache-2.0
/// @file support/RandomVolumes.h
/// @brief Seeded random label volumes for property tests, from a portable RNG (the same
/// volumes on every platform and standard library: no std::*_distribution).

#pragma once

#include <vdbi/Types.h>

#include <openvdb/openvdb.h>

#include <cstdint>
#include <string>
#include <vector>

namespace vdbi_test {

/// @brief xoshiro256** seeded through splitmix64: small, fast, fully specified.
class Rng
{
public:
    explicit Rng(std::uint64_t seed);

    std::uint64_t next();
    /// Uniform in [0, n) for n > 0 (multiply-shift; the tiny bias is irrelevant here).
    std::uint64_t below(std::uint64_t n);
    /// Uniform integer in [lo, hi] (inclusive).
    int range(int lo, int hi);
    /// Uniform in [0, 1), 53 bits.
    double uniform();
    /// True with probability @a p.
    bool chance(double p) { return uniform() < p; }

private:
    std::uint64_t mS[4];
};

/// The kinds of random volume.
enum class Generator {
    Noise,         ///< every voxel of a size^3 box gets a uniformly chosen label
    BiasedNoise,   ///< like Noise, but one label takes 60-90 % of the voxels
    Blobs,         ///< random balls of labels, later balls painted over earlier ones
    SmoothField,   ///< a thresholded sum of random plane waves cut into label bands
    SparseScatter, ///< a few voxels in a (4 size)^3 box, some far apart, some in contact
    ThinLayers     ///< 1-voxel-thick sheets (axis-aligned and staircase) and rods
};

/// Every generator, in declaration order.
const std::vector<Generator>& allGenerators();

/// "Noise", "BiasedNoise", ...
std::string generatorName(Generator g);

/// @brief The labels a volume draws from: @a labelCount distinct values including the
/// background 0. For seeds with seed % 3 == 2 they straddle 0 (for example -2..2), else they
/// are 0..labelCount-1, so that some volumes exercise negative labels and the label order.
std::vector<vdbi::Label> labelPool(std::uint64_t seed, int labelCount);

/// @brief A random label volume, background 0, all non-background voxels active.
/// @details The box is [o, o + size)^3 with a seed-dependent origin o in [-12, 12]^3, so that
/// leaf boundaries and negative coordinates occur. The same (g, seed, size, labelCount)
/// always gives the same grid.
/// @param labelCount  distinct labels including the background (at least 2)
openvdb::Int32Grid::Ptr randomVolume(Generator g, std::uint64_t seed, int size, int labelCount);

} // namespace vdbi_test
