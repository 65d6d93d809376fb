// SPDX-License-Identifier: Apache-2.0

#include "support/BlockEnumeration.h"

#include "support/HandMadeGrids.h"

#include <algorithm>
#include <map>

namespace vdbi_test {

using vdbi::Label;

const std::vector<std::array<int, 8>>&
cubeSymmetries()
{
    static const std::vector<std::array<int, 8>> syms = [] {
        std::vector<std::array<int, 8>> out;
        std::array<int, 3> axes = {0, 1, 2};
        // Axis permutations in lexicographic order (identity first), then flips (none first).
        do {
            for (int flip = 0; flip < 8; ++flip) {
                std::array<int, 8> p;
                for (int i = 0; i < 8; ++i) {
                    const int c[3] = {i & 1, (i >> 1) & 1, (i >> 2) & 1};
                    int d[3];
                    for (int a = 0; a < 3; ++a) d[a] = c[axes[a]] ^ ((flip >> a) & 1);
                    p[i] = d[0] + 2 * d[1] + 4 * d[2];
                }
                out.push_back(p);
            }
        } while (std::next_permutation(axes.begin(), axes.end()));
        return out;
    }();
    return syms;
}

const std::vector<std::array<int, 12>>&
box223Symmetries()
{
    static const std::vector<std::array<int, 12>> syms = [] {
        std::vector<std::array<int, 12>> out;
        for (int swap = 0; swap < 2; ++swap) {
            for (int flip = 0; flip < 8; ++flip) {
                std::array<int, 12> p;
                for (int i = 0; i < 12; ++i) {
                    int x = i & 1, y = (i >> 1) & 1, z = i >> 2;
                    if (swap) std::swap(x, y);
                    if (flip & 1) x = 1 - x;
                    if (flip & 2) y = 1 - y;
                    if (flip & 4) z = 2 - z;
                    p[i] = x + 2 * y + 4 * z;
                }
                out.push_back(p);
            }
        }
        return out;
    }();
    return syms;
}

std::vector<std::array<std::uint8_t, 8>>
orderedSetPartitions8()
{
    // A rank vector is an ordered set partition exactly when its values cover 0..max.
    std::vector<std::array<std::uint8_t, 8>> out;
    std::array<std::uint8_t, 8> r{};
    for (std::uint32_t code = 0; code < (1u << 24); ++code) {
        unsigned used = 0, top = 0;
        for (int i = 0; i < 8; ++i) {
            r[i] = std::uint8_t((code >> (3 * (7 - i))) & 7u);
            used |= 1u << r[i];
            top = std::max<unsigned>(top, r[i]);
        }
        if (used == (2u << top) - 1u) out.push_back(r);
    }
    return out;
}

namespace {

std::uint32_t
packBlock(const std::array<std::uint8_t, 8>& r)
{
    std::uint32_t code = 0;
    for (int i = 0; i < 8; ++i) code = (code << 3) | r[i];
    return code;
}

} // namespace

std::array<std::uint8_t, 8>
canonicalBlock(const std::array<std::uint8_t, 8>& ranks)
{
    std::array<std::uint8_t, 8> best = ranks, image{};
    std::uint32_t bestCode = packBlock(ranks);
    for (const auto& p : cubeSymmetries()) {
        for (int i = 0; i < 8; ++i) image[p[i]] = ranks[i];
        const std::uint32_t code = packBlock(image);
        if (code < bestCode) {
            bestCode = code;
            best = image;
        }
    }
    return best;
}

const std::vector<BlockClass>&
blockClasses()
{
    static const std::vector<BlockClass> classes = [] {
        std::map<std::uint32_t, std::size_t> orbit; // canonical code -> partitions in class
        for (const auto& r : orderedSetPartitions8()) ++orbit[packBlock(canonicalBlock(r))];
        std::vector<BlockClass> out;
        for (int withBackground = 0; withBackground < 2; ++withBackground) {
            for (const auto& entry : orbit) {
                BlockClass c;
                for (int i = 0; i < 8; ++i) {
                    const Label rank = Label((entry.first >> (3 * (7 - i))) & 7u);
                    c.labels[i] = withBackground ? rank : rank + 1;
                }
                c.hasBackground = withBackground != 0;
                c.orbitSize = entry.second;
                out.push_back(c);
            }
        }
        return out;
    }();
    return classes;
}

const std::vector<Box223Class>&
box223Classes()
{
    static const std::vector<Box223Class> classes = [] {
        constexpr std::uint32_t total = 531441; // 3^12
        const auto& syms = box223Symmetries();
        std::vector<std::uint32_t> canonical(total);
        std::array<int, 12> digits{}, image{};
        for (std::uint32_t code = 0; code < total; ++code) {
            std::uint32_t c = code;
            for (int i = 0; i < 12; ++i, c /= 3) digits[i] = int(c % 3);
            std::uint32_t best = code;
            for (const auto& p : syms) {
                for (int i = 0; i < 12; ++i) image[p[i]] = digits[i];
                std::uint32_t v = 0;
                for (int i = 11; i >= 0; --i) v = v * 3 + std::uint32_t(image[i]);
                best = std::min(best, v);
            }
            canonical[code] = best;
        }
        std::map<std::uint32_t, std::size_t> orbit;
        for (std::uint32_t code = 0; code < total; ++code) ++orbit[canonical[code]];
        std::vector<Box223Class> out;
        for (const auto& entry : orbit) {
            Box223Class k;
            std::uint32_t c = entry.first;
            for (int i = 0; i < 12; ++i, c /= 3) k.labels[i] = Label(c % 3);
            k.orbitSize = entry.second;
            out.push_back(k);
        }
        return out;
    }();
    return classes;
}

openvdb::Int32Grid::Ptr
blockGrid(const BlockLabels& labels)
{
    return gridFromDense(2, 2, 2, std::vector<Label>(labels.begin(), labels.end()));
}

openvdb::Int32Grid::Ptr
box223Grid(const Box223Labels& labels)
{
    return gridFromDense(2, 2, 3, std::vector<Label>(labels.begin(), labels.end()));
}

void
forEachBlockClass(const std::function<void(std::size_t, const BlockClass&)>& f)
{
    const auto& classes = blockClasses();
    for (std::size_t i = 0; i < classes.size(); ++i) f(i, classes[i]);
}

void
forEachBox223Class(const std::function<void(std::size_t, const Box223Class&)>& f)
{
    const auto& classes = box223Classes();
    for (std::size_t i = 0; i < classes.size(); ++i) f(i, classes[i]);
}

} // namespace vdbi_test
