// SPDX-License-Identifier: Apache-2.0

#include "support/RandomVolumes.h"

#include <openvdb/Exceptions.h>

#include <algorithm>
#include <cmath>

namespace vdbi_test {

using openvdb::Coord;
using vdbi::Label;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::uint64_t
splitmix64(std::uint64_t& state)
{
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

inline std::uint64_t
rotl(std::uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

} // namespace

Rng::Rng(std::uint64_t seed)
{
    std::uint64_t state = seed;
    for (std::uint64_t& s : mS) s = splitmix64(state);
}

std::uint64_t
Rng::next()
{
    const std::uint64_t result = rotl(mS[1] * 5, 7) * 9;
    const std::uint64_t t = mS[1] << 17;
    mS[2] ^= mS[0];
    mS[3] ^= mS[1];
    mS[1] ^= mS[2];
    mS[0] ^= mS[3];
    mS[2] ^= t;
    mS[3] = rotl(mS[3], 45);
    return result;
}

std::uint64_t
Rng::below(std::uint64_t n)
{
    return std::uint64_t((static_cast<unsigned __int128>(next()) * n) >> 64);
}

int
Rng::range(int lo, int hi)
{
    return lo + int(below(std::uint64_t(std::int64_t(hi) - lo + 1)));
}

double
Rng::uniform()
{
    return double(next() >> 11) * 0x1.0p-53;
}

const std::vector<Generator>&
allGenerators()
{
    static const std::vector<Generator> all = {Generator::Noise, Generator::BiasedNoise,
        Generator::Blobs, Generator::SmoothField, Generator::SparseScatter,
        Generator::ThinLayers};
    return all;
}

std::string
generatorName(Generator g)
{
    switch (g) {
    case Generator::Noise: return "Noise";
    case Generator::BiasedNoise: return "BiasedNoise";
    case Generator::Blobs: return "Blobs";
    case Generator::SmoothField: return "SmoothField";
    case Generator::SparseScatter: return "SparseScatter";
    case Generator::ThinLayers: return "ThinLayers";
    }
    return "?";
}

std::vector<Label>
labelPool(std::uint64_t seed, int labelCount)
{
    const int n = std::max(labelCount, 2);
    const int base = (seed % 3 == 2) ? -(n / 2) : 0;
    std::vector<Label> pool;
    for (int i = 0; i < n; ++i) pool.push_back(base + i);
    return pool;
}

namespace {

/// A dense box of labels, background 0, written into a grid at the end.
struct Box
{
    Coord origin;
    int n;
    std::vector<Label> v;

    Box(const Coord& o, int size): origin(o), n(size), v(std::size_t(size) * size * size, 0) {}
    Label& at(int x, int y, int z) { return v[x + std::size_t(n) * (y + std::size_t(n) * z)]; }
    bool inside(int x, int y, int z) const
    {
        return x >= 0 && y >= 0 && z >= 0 && x < n && y < n && z < n;
    }

    openvdb::Int32Grid::Ptr toGrid() const
    {
        openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(0);
        auto acc = grid->getAccessor();
        std::size_t i = 0;
        for (int z = 0; z < n; ++z) {
            for (int y = 0; y < n; ++y) {
                for (int x = 0; x < n; ++x, ++i) {
                    if (v[i] != 0) acc.setValueOn(origin + Coord(x, y, z), v[i]);
                }
            }
        }
        return grid;
    }
};

Label
pick(Rng& rng, const std::vector<Label>& pool)
{
    return pool[rng.below(pool.size())];
}

/// A label other than the background, if the pool has one.
Label
pickForeground(Rng& rng, const std::vector<Label>& pool)
{
    for (int tries = 0; tries < 64; ++tries) {
        const Label l = pick(rng, pool);
        if (l != 0) return l;
    }
    return pool.back() != 0 ? pool.back() : pool.front();
}

void
noise(Rng& rng, Box& box, const std::vector<Label>& pool)
{
    for (Label& l : box.v) l = pick(rng, pool);
}

void
biasedNoise(Rng& rng, Box& box, const std::vector<Label>& pool)
{
    const Label dominant = pick(rng, pool);
    const double p = 0.6 + 0.3 * rng.uniform();
    for (Label& l : box.v) l = rng.chance(p) ? dominant : pick(rng, pool);
}

void
blobs(Rng& rng, Box& box, const std::vector<Label>& pool)
{
    const int n = box.n;
    // Many small balls (radius 0.5 is a single voxel, 1 a cross) make corner and edge
    // contacts; a few large ones make smooth interfaces.
    const int count = 1 + int(rng.below(std::uint64_t(2 * n)));
    for (int b = 0; b < count; ++b) {
        const double r = 0.5 + rng.uniform() * rng.uniform() * (n / 3.0 + 1.0);
        const double cx = -r + rng.uniform() * (n + 2 * r);
        const double cy = -r + rng.uniform() * (n + 2 * r);
        const double cz = -r + rng.uniform() * (n + 2 * r);
        const Label label = pick(rng, pool);
        for (int z = 0; z < n; ++z) {
            for (int y = 0; y < n; ++y) {
                for (int x = 0; x < n; ++x) {
                    const double dx = x + 0.5 - cx, dy = y + 0.5 - cy, dz = z + 0.5 - cz;
                    if (dx * dx + dy * dy + dz * dz <= r * r) box.at(x, y, z) = label;
                }
            }
        }
    }
}

void
smoothField(Rng& rng, Box& box, const std::vector<Label>& pool)
{
    const int n = box.n;
    const int waves = 2 + int(rng.below(4));
    struct Wave { double kx, ky, kz, phase, amp; };
    std::vector<Wave> w;
    double total = 0;
    for (int i = 0; i < waves; ++i) {
        // A random direction (not normalised: any spread of directions will do) and a
        // wavelength between 2 voxels and twice the box.
        const double ux = rng.uniform() - 0.5, uy = rng.uniform() - 0.5, uz = rng.uniform() - 0.5;
        const double len = std::sqrt(ux * ux + uy * uy + uz * uz) + 1e-9;
        const double lambda = 2.0 + rng.uniform() * (2.0 * n - 2.0);
        const double k = 2.0 * kPi / lambda / len;
        const double amp = 0.2 + rng.uniform();
        w.push_back({ux * k, uy * k, uz * k, rng.uniform() * 2.0 * kPi, amp});
        total += amp;
    }
    const int bands = int(pool.size());
    for (int z = 0; z < n; ++z) {
        for (int y = 0; y < n; ++y) {
            for (int x = 0; x < n; ++x) {
                double f = 0;
                for (const Wave& q : w) {
                    f += q.amp * std::sin(q.kx * x + q.ky * y + q.kz * z + q.phase);
                }
                // Most of the mass of a sum of waves is near 0: stretch before banding.
                const double t = std::min(0.999999, std::max(0.0, 0.5 + f / total));
                box.at(x, y, z) = pool[std::size_t(t * bands)];
            }
        }
    }
}

void
thinLayers(Rng& rng, Box& box, const std::vector<Label>& pool)
{
    const int n = box.n;
    const Label fill = pick(rng, pool);
    for (Label& l : box.v) l = fill;
    const int sheets = 1 + int(rng.below(4));
    for (int i = 0; i < sheets; ++i) {
        const Label label = pick(rng, pool);
        const int axis = int(rng.below(3));
        const bool staircase = rng.chance(0.35);
        const int p = int(rng.below(std::uint64_t(staircase ? 2 * n : n)));
        for (int z = 0; z < n; ++z) {
            for (int y = 0; y < n; ++y) {
                for (int x = 0; x < n; ++x) {
                    const int c[3] = {x, y, z};
                    // A staircase sheet x_a + x_b = p touches itself only along edges: the
                    // source of many critical edges.
                    const int value = staircase ? c[axis] + c[(axis + 1) % 3] : c[axis];
                    if (value == p) box.at(x, y, z) = label;
                }
            }
        }
    }
    const int rods = 1 + int(rng.below(4));
    for (int i = 0; i < rods; ++i) {
        const Label label = pick(rng, pool);
        const int kind = int(rng.below(4)); // 0..2: along that axis, 3: space diagonal
        const int a = int(rng.below(std::uint64_t(n))), b = int(rng.below(std::uint64_t(n)));
        for (int t = 0; t < n; ++t) {
            int x, y, z;
            switch (kind) {
            case 0: x = t; y = a; z = b; break;
            case 1: x = a; y = t; z = b; break;
            case 2: x = a; y = b; z = t; break;
            default: x = t; y = (t + a) % n; z = (t + b) % n; break;
            }
            box.at(x, y, z) = label;
        }
    }
}

openvdb::Int32Grid::Ptr
sparseScatter(Rng& rng, const Coord& origin, int size, const std::vector<Label>& pool)
{
    const int extent = 4 * size;
    openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(0);
    auto acc = grid->getAccessor();
    const int count = 2 + int(rng.below(std::uint64_t(size) + 1));
    std::vector<Coord> placed;
    for (int i = 0; i < count; ++i) {
        Coord c;
        if (placed.empty() || rng.chance(0.4)) {
            // Anywhere: usually far from everything else (other leaves, other internal nodes).
            c = origin + Coord(rng.range(0, extent - 1), rng.range(0, extent - 1),
                               rng.range(0, extent - 1));
        } else {
            // Next to an earlier voxel, often only by an edge or a corner.
            Coord d;
            do {
                d = Coord(rng.range(-1, 1), rng.range(-1, 1), rng.range(-1, 1));
            } while (d == Coord(0));
            c = placed[rng.below(placed.size())] + d;
        }
        placed.push_back(c);
        acc.setValueOn(c, pickForeground(rng, pool));
    }
    return grid;
}

} // namespace

openvdb::Int32Grid::Ptr
randomVolume(Generator g, std::uint64_t seed, int size, int labelCount)
{
    if (size < 1) OPENVDB_THROW(openvdb::ValueError, "randomVolume: size " << size << " < 1");
    // Mix the generator into the stream so that equal seeds of two generators differ.
    Rng rng(seed * 0x2545F4914F6CDD1Dull + std::uint64_t(g) + 1);
    const std::vector<Label> pool = labelPool(seed, labelCount);
    const Coord origin(rng.range(-12, 12), rng.range(-12, 12), rng.range(-12, 12));
    if (g == Generator::SparseScatter) return sparseScatter(rng, origin, size, pool);

    Box box(origin, size);
    switch (g) {
    case Generator::Noise: noise(rng, box, pool); break;
    case Generator::BiasedNoise: biasedNoise(rng, box, pool); break;
    case Generator::Blobs: blobs(rng, box, pool); break;
    case Generator::SmoothField: smoothField(rng, box, pool); break;
    case Generator::ThinLayers: thinLayers(rng, box, pool); break;
    case Generator::SparseScatter: break;
    }
    return box.toGrid();
}

} // namespace vdbi_test
