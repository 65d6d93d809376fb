// SPDX-License-Identifier: Apache-2.0

#include "support/SeparationChecker.h"

#include "support/RefinedChecker.h"

#include <openvdb/Exceptions.h>

#include <algorithm>
#include <cstdlib>
#include <utility>

namespace vdbi_test {

using openvdb::Coord;
using openvdb::CoordBBox;
using vdbi::Label;
using vdbi::SeparationConstraint;

namespace {

bool
contains(const std::vector<Label>& labels, Label l)
{
    return std::find(labels.begin(), labels.end(), l) != labels.end();
}

template<typename T>
void
shuffle(std::vector<T>& v, Rng& rng)
{
    for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[rng.below(i)]);
}

/// Gap in fine voxels, along one axis, from the fine voxel at offset @a o (0..s-1) inside its
/// coarse voxel to the coarse voxel @a d (-2..2) voxels away.
inline int
axisGap(int o, int d, int s)
{
    switch (d) {
        case -2: return s + o;
        case -1: return o;
        case 0: return 0;
        case 1: return s - 1 - o;
        default: return 2 * s - 1 - o;
    }
}

/// @brief Distance (coarse units, Chebyshev, closed cubes) from fine voxel @a f to the
/// nearest coarse voxel labelled @a label, 2 if there is none within 2 voxels; any value at
/// most @a enough may be returned early (only the largest distance over all subvoxels is
/// wanted). @a coarseLabel(c) gives the input label of coarse voxel c.
template<typename CoarseLabel>
double
distanceToLabel(const Coord& f, Label label, int s, double enough, CoarseLabel&& coarseLabel)
{
    const Coord home = vdbi::coarseOf(f, s);
    const Coord o = f - Coord(s * home.x(), s * home.y(), s * home.z());
    // Every voxel at Chebyshev offset 1 is nearer than any at offset 2: search by rings.
    for (int radius = 1; radius <= 2; ++radius) {
        int best = 2 * s;
        for (int dz = -radius; dz <= radius; ++dz) {
            for (int dy = -radius; dy <= radius; ++dy) {
                for (int dx = -radius; dx <= radius; ++dx) {
                    if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != radius) continue;
                    if (coarseLabel(home.offsetBy(dx, dy, dz)) != label) continue;
                    const int g = std::max({axisGap(o.x(), dx, s), axisGap(o.y(), dy, s),
                                            axisGap(o.z(), dz, s)});
                    if (g <= enough * s + 1e-9) return double(g) / s;
                    best = std::min(best, g);
                }
            }
        }
        if (best < 2 * s) return double(best) / s;
    }
    return 2.0;
}

/// Adds the distance of one relabelled subvoxel to @a r (separator or not).
template<typename CoarseLabel>
void
measure(const Coord& f, Label label, int s, const std::vector<Label>& seps,
        const SeparationReport& sofar, SeparationReport& r, CoarseLabel&& coarseLabel)
{
    ++r.relabelled;
    double& worst = contains(seps, label) ? r.maxSeparatorDistance : r.maxDistance;
    const double known = std::max(worst, contains(seps, label) ? sofar.maxSeparatorDistance
                                                               : sofar.maxDistance);
    worst = std::max(worst, distanceToLabel(f, label, s, known, coarseLabel));
}

} // namespace

std::size_t
touchingPoints(const vdbi::RefinedLabels& r, const std::vector<SeparationConstraint>& cs)
{
    const auto points = checkPoints(*r.coarse, *r.subdivided, r.subdivision);
    vdbi::RefinedLabels::Accessor acc(r);
    std::size_t touching = 0;
    for (auto it = points->cbeginValueOn(); it; ++it) {
        Label l[8];
        for (int n = 0; n < 8; ++n) {
            l[n] = acc.fineLabel(it.getCoord().offsetBy((n & 1) - 1, ((n >> 1) & 1) - 1,
                                                        ((n >> 2) & 1) - 1));
        }
        for (const SeparationConstraint& c : cs) {
            const bool a = std::find(l, l + 8, c.a) != l + 8;
            const bool b = std::find(l, l + 8, c.b) != l + 8;
            touching += (a && b) ? 1 : 0;
        }
    }
    return touching;
}

std::vector<Label>
separators(const std::vector<SeparationConstraint>& constraints)
{
    std::vector<Label> out;
    for (const SeparationConstraint& c : constraints) out.push_back(c.separator);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

std::vector<SeparationConstraint>
randomConstraints(Rng& rng, const std::vector<Label>& pool, int count)
{
    if (count < 1 || pool.size() < std::size_t(count) + 2) {
        OPENVDB_THROW(openvdb::ValueError, "randomConstraints: " << count
            << " constraints need " << count + 2 << " labels, not " << pool.size());
    }
    std::vector<Label> labels = pool;
    shuffle(labels, rng);
    // One or two separators; a quarter of the time the first is a label the volume lacks.
    const std::size_t separatorCount =
        (labels.size() >= std::size_t(count) + 3 && rng.chance(0.5)) ? 2 : 1;
    std::vector<Label> seps(labels.begin(), labels.begin() + separatorCount);
    std::vector<Label> paired(labels.begin() + separatorCount, labels.end());
    if (rng.chance(0.25)) {
        paired.push_back(seps[0]);
        seps[0] = *std::max_element(pool.begin(), pool.end()) + 1;
    }
    std::vector<std::pair<Label, Label>> pairs;
    for (std::size_t i = 0; i < paired.size(); ++i) {
        for (std::size_t j = i + 1; j < paired.size(); ++j) {
            pairs.emplace_back(paired[i], paired[j]);
        }
    }
    shuffle(pairs, rng);
    std::vector<SeparationConstraint> out;
    for (int n = 0; n < count; ++n) {
        const Label sep = seps[rng.below(seps.size())];
        out.push_back({pairs[n].first, pairs[n].second, sep});
    }
    return out;
}

SeparationReport
measureDistances(const vdbi::RefinedLabels& labels,
                 const std::vector<SeparationConstraint>& constraints)
{
    SeparationReport r;
    const std::vector<Label> seps = separators(constraints);
    auto coarse = labels.coarse->getConstAccessor();
    auto coarseLabel = [&coarse](const Coord& c) { return coarse.getValue(c); };
    for (auto it = labels.fine->cbeginValueOn(); it; ++it) {
        if (!it.isVoxelValue()) continue;
        const Coord f = it.getCoord();
        if (*it == coarse.getValue(vdbi::coarseOf(f, labels.subdivision))) continue;
        measure(f, *it, labels.subdivision, seps, r, r, coarseLabel);
    }
    return r;
}

void
SeparationReport::add(const SeparationReport& o)
{
    repairs += o.repairs;
    pointsChecked += o.pointsChecked;
    nonManifold += o.nonManifold;
    touching += o.touching;
    outsideBox += o.outsideBox;
    failingRepairs += o.failingRepairs;
    relabelled += o.relabelled;
    maxDistance = std::max(maxDistance, o.maxDistance);
    maxSeparatorDistance = std::max(maxSeparatorDistance, o.maxSeparatorDistance);
}

SmallVolumeChecker::SmallVolumeChecker(const openvdb::Int32Grid& coarse, const CoordBBox& box,
                                       int s)
    : mS(s)
    , mBackground(coarse.background())
    , mBox(box)
{
    const Coord fineMin(s * box.min().x(), s * box.min().y(), s * box.min().z());
    mFineOrigin = fineMin.offsetBy(-1);
    mFineDims = Coord(s * box.dim().x() + 2, s * box.dim().y() + 2, s * box.dim().z() + 2);

    mCoarseBox = box;
    mCoarseBox.expand(2);
    auto acc = coarse.getConstAccessor();
    mCoarse.reserve(mCoarseBox.volume());
    for (int z = mCoarseBox.min().z(); z <= mCoarseBox.max().z(); ++z) {
        for (int y = mCoarseBox.min().y(); y <= mCoarseBox.max().y(); ++y) {
            for (int x = mCoarseBox.min().x(); x <= mCoarseBox.max().x(); ++x) {
                mCoarse.push_back(acc.getValue(Coord(x, y, z)));
            }
        }
    }

    mStoredFine = CoordBBox();
    forEachStoredLabel(coarse, [&](const CoordBBox& b, Label) {
        if (!box.isInside(b)) {
            OPENVDB_THROW(openvdb::ValueError, "SmallVolumeChecker: labels outside the box");
        }
        mStoredFine.expand(CoordBBox(Coord(s * b.min().x(), s * b.min().y(), s * b.min().z()),
            Coord(s * b.max().x() + s - 1, s * b.max().y() + s - 1, s * b.max().z() + s - 1)));
    });

    const std::size_t cx = std::size_t(mCoarseBox.dim().x());
    const std::size_t cy = std::size_t(mCoarseBox.dim().y());
    mUpsampled.assign(std::size_t(mFineDims.x()) * mFineDims.y() * mFineDims.z(), mBackground);
    for (int z = 1; z + 1 < mFineDims.z(); ++z) {
        for (int y = 1; y + 1 < mFineDims.y(); ++y) {
            for (int x = 1; x + 1 < mFineDims.x(); ++x) {
                const Coord f = mFineOrigin.offsetBy(x, y, z);
                const Coord c = vdbi::coarseOf(f, s) - mCoarseBox.min();
                mUpsampled[index(f)] = mCoarse[std::size_t(c.x())
                    + cx * (std::size_t(c.y()) + cy * std::size_t(c.z()))];
            }
        }
    }
    mWork = mUpsampled;

    // Per coarse voxel of the box and label: the offsets of the neighbours with that label,
    // by Chebyshev ring (every voxel of ring 1 is nearer than any of ring 2).
    mLabels = mCoarse;
    std::sort(mLabels.begin(), mLabels.end());
    mLabels.erase(std::unique(mLabels.begin(), mLabels.end()), mLabels.end());
    for (auto& ring : mRings) ring.assign(std::size_t(box.volume()) * mLabels.size(), {});
    auto cacc = coarse.getConstAccessor();
    std::size_t cell = 0;
    for (int z = box.min().z(); z <= box.max().z(); ++z) {
        for (int y = box.min().y(); y <= box.max().y(); ++y) {
            for (int x = box.min().x(); x <= box.max().x(); ++x, ++cell) {
                for (auto d = CoordBBox(Coord(-2), Coord(2)).begin(); d; ++d) {
                    const int ring = std::max({std::abs((*d).x()), std::abs((*d).y()),
                                               std::abs((*d).z())});
                    if (ring == 0) continue;
                    const Label l = cacc.getValue(Coord(x, y, z) + *d);
                    const std::size_t li = std::size_t(
                        std::find(mLabels.begin(), mLabels.end(), l) - mLabels.begin());
                    mRings[ring - 1][cell * mLabels.size() + li].push_back(*d);
                }
            }
        }
    }
}

std::size_t
SmallVolumeChecker::index(const Coord& f) const
{
    const Coord d = f - mFineOrigin;
    return std::size_t(d.x())
        + std::size_t(mFineDims.x()) * (std::size_t(d.y()) + std::size_t(mFineDims.y()) * d.z());
}

double
SmallVolumeChecker::distanceToLabel(const Coord& f, Label label, double enough) const
{
    const Coord home = vdbi::coarseOf(f, mS);
    const Coord o = f - Coord(mS * home.x(), mS * home.y(), mS * home.z());
    const std::size_t l = std::size_t(
        std::find(mLabels.begin(), mLabels.end(), label) - mLabels.begin());
    if (l == mLabels.size()) return 2.0;
    const Coord h = home - mBox.min();
    const std::size_t cell = (std::size_t(h.x()) + std::size_t(mBox.dim().x())
        * (std::size_t(h.y()) + std::size_t(mBox.dim().y()) * h.z())) * mLabels.size() + l;
    for (int ring = 0; ring < 2; ++ring) {
        int best = 2 * mS;
        for (const Coord& d : mRings[ring][cell]) {
            const int g = std::max({axisGap(o.x(), d.x(), mS), axisGap(o.y(), d.y(), mS),
                                    axisGap(o.z(), d.z(), mS)});
            if (g <= enough * mS + 1e-9) return double(g) / mS;
            best = std::min(best, g);
        }
        if (best < 2 * mS) return double(best) / mS;
    }
    return 2.0;
}

void
SmallVolumeChecker::check(const vdbi::RefinedLabels& labels,
                          const std::vector<SeparationConstraint>& constraints,
                          SeparationReport& report)
{
    SeparationReport r;
    r.repairs = 1;
    const std::vector<Label> seps = separators(constraints);
    const CoordBBox fineBox(mFineOrigin.offsetBy(1), mFineOrigin + mFineDims.offsetBy(-2));
    if (labels.fine->tree().activeTileCount() > 0) {
        OPENVDB_THROW(openvdb::ValueError, "SmallVolumeChecker: active fine tiles");
    }
    // mWork holds the upsampled labels between calls: write the changes, undo them at the end.
    mChanged.clear();
    CoordBBox changed;
    for (auto leaf = labels.fine->tree().cbeginLeaf(); leaf; ++leaf) {
        for (auto it = leaf->cbeginValueOn(); it; ++it) {
            const Coord f = it.getCoord();
            if (!fineBox.isInside(f)) {
                ++r.outsideBox;
                continue;
            }
            const std::size_t i = index(f);
            const Label label = *it;
            if (label == mUpsampled[i]) continue;
            ++r.relabelled;
            const bool isSeparator = contains(seps, label);
            double& worst = isSeparator ? r.maxSeparatorDistance : r.maxDistance;
            const double known = std::max(worst, isSeparator ? report.maxSeparatorDistance
                                                             : report.maxDistance);
            worst = std::max(worst, distanceToLabel(f, label, known));
            mWork[i] = label;
            mChanged.push_back(i);
            changed.expand(f);
        }
    }

    // Points whose 8 voxels meet the stored or changed voxels; all others see the background.
    // Per row of points, a point is skipped when its two columns of 4 voxels are uniform and
    // equal (the common case, tested in a loop the compiler can vectorize).
    CoordBBox voxels = mStoredFine;
    voxels.expand(changed);
    if (!voxels.empty()) {
        const std::size_t dy = std::size_t(mFineDims.x()),
            dz = std::size_t(mFineDims.x()) * mFineDims.y();
        const std::size_t offsets[8] = {0, 1, dy, 1 + dy, dz, 1 + dz, dy + dz, 1 + dy + dz};
        const int n = voxels.max().x() - voxels.min().x() + 3; // voxel columns min - 1 .. max + 1
        mColumnLabel.resize(std::size_t(n));
        mColumnUniform.resize(std::size_t(n));
        for (int z = voxels.min().z(); z <= voxels.max().z() + 1; ++z) {
            for (int y = voxels.min().y(); y <= voxels.max().y() + 1; ++y) {
                const Label* row = mWork.data() + index(Coord(voxels.min().x() - 1, y - 1, z - 1));
                for (int i = 0; i < n; ++i) {
                    const Label l = row[i];
                    mColumnLabel[i] = l;
                    mColumnUniform[i] = (row[i + dy] == l) & (row[i + dz] == l)
                        & (row[i + dy + dz] == l);
                }
                for (int i = 1; i < n; ++i) {
                    if (mColumnUniform[i - 1] & mColumnUniform[i]
                        & (mColumnLabel[i - 1] == mColumnLabel[i])) {
                        continue;
                    }
                    const Label* corner = row + (i - 1);
                    Label l[8];
                    for (int k = 0; k < 8; ++k) l[k] = corner[offsets[k]];
                    ++r.pointsChecked;
                    unsigned done = 0;
                    for (int k = 0; k < 8; ++k) {
                        if ((done >> k) & 1u) continue;
                        unsigned mask = 0;
                        for (int j = k; j < 8; ++j) mask |= unsigned(l[j] == l[k]) << j;
                        done |= mask;
                        r.nonManifold += isManifoldMask(std::uint8_t(mask)) ? 0 : 1;
                    }
                    for (const SeparationConstraint& c : constraints) {
                        const bool a = std::find(l, l + 8, c.a) != l + 8;
                        const bool b = std::find(l, l + 8, c.b) != l + 8;
                        r.touching += (a && b) ? 1 : 0;
                    }
                }
            }
        }
    }
    for (const std::size_t i : mChanged) mWork[i] = mUpsampled[i];
    r.failingRepairs = (r.nonManifold + r.touching + r.outsideBox) > 0 ? 1 : 0;
    report.add(r);
}

} // namespace vdbi_test
