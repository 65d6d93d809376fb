// SPDX-License-Identifier: Apache-2.0

#include <vdbi/FaceCentreCoverage.h>

#include <vdbi/CandidateGrid.h>
#include <vdbi/RadixSort.h>
#include <vdbi/RawPatchDistance.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

namespace vdbi {

namespace {

using Vec3d = openvdb::Vec3d;

/// Groups of cells a search keeps the triangles of.
constexpr std::size_t CACHED_GROUPS = 509;
/// Raw face centres per task: the largest patch (a third of the frog) is searched by both
/// threads, not by one while the other waits.
constexpr std::size_t CENTRES_PER_TASK = 1 << 14;

/// A remeshed patch's triangles in voxel units, and (cell, triangle) for every cell of
/// two limits their bounding boxes overlap, by cell.
struct PatchCells
{
    std::vector<RawPatchDistance::Corners> triangles;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
    double cellInverse = 0.0;
};

Vec3d
scaled(const Vec3d& w, const Vec3d& inverse)
{
    return Vec3d(w[0] * inverse[0], w[1] * inverse[1], w[2] * inverse[2]);
}

PatchCells
cellsOfPatch(const InterfaceMesh& mesh, std::size_t p, const Vec3d& inverse, double limit)
{
    const InterfacePatch& op = mesh.patches[p];
    PatchCells cells;
    cells.cellInverse = 1.0 / (2.0 * limit);
    cells.triangles.resize(op.triangleCount);
    cells.entries.reserve(2 * op.triangleCount);
    for (std::size_t k = 0; k < op.triangleCount; ++k) {
        const openvdb::Vec3I& t = mesh.triangles[op.firstTriangle + k];
        RawPatchDistance::Corners& c = cells.triangles[k];
        for (int i = 0; i < 3; ++i) c.c[i] = scaled(mesh.points[t[i]], inverse);
        const Vec3d low = openvdb::math::minComponent(c.c[0], openvdb::math::minComponent(
            c.c[1], c.c[2]));
        const Vec3d high = openvdb::math::maxComponent(c.c[0], openvdb::math::maxComponent(
            c.c[1], c.c[2]));
        const openvdb::Vec3i lowCell = cellOf(low, cells.cellInverse);
        const openvdb::Vec3i highCell = cellOf(high, cells.cellInverse);
        for (int x = lowCell[0]; x <= highCell[0]; ++x) {
            for (int y = lowCell[1]; y <= highCell[1]; ++y) {
                for (int z = lowCell[2]; z <= highCell[2]; ++z) {
                    cells.entries.emplace_back(cellKey(openvdb::Vec3i(x, y, z)),
                                               std::uint32_t(k));
                }
            }
        }
    }
    // Made by triangle: sorted by (key, triangle).
    sortByPackedKey<3, CELL_KEY_BITS>(cells.entries, [](const auto& e) { return e.first; });
    return cells;
}

/// The far centres (see findFarFaceCentres()) among centres [@a begin, @a end) (voxel units)
/// of patch @a p, appended to @a far.
void
findFarCentresIn(const PatchCells& cells, std::size_t p, const Vec3d* begin, const Vec3d* end,
                 const Vec3d& voxel, double limit, std::vector<FaceCentre>& far)
{
    const std::vector<RawPatchDistance::Corners>& triangles = cells.triangles;
    const auto& entries = cells.entries;
    // Raw triangles come block by block, and their centres in their order: the centres of a
    // block look at a few groups of cells, again and again. Each group's triangles are
    // gathered once into a small cache.
    struct Group
    {
        openvdb::Vec3i cell{std::numeric_limits<int>::min()};
        std::vector<std::uint32_t> triangles;
    };
    std::vector<Group> cache(CACHED_GROUPS);
    std::size_t lastNear = triangles.size();
    for (const Vec3d* c = begin; c != end; ++c) {
        const Vec3d& centre = *c;
        const openvdb::Vec3i lowCell = cellOf(centre - Vec3d(limit), cells.cellInverse);
        Group& group = cache[cellKey(lowCell) % CACHED_GROUPS];
        if (group.cell != lowCell) {
            group.cell = lowCell;
            group.triangles.clear();
            forEachEntryInCells(entries, lowCell, lowCell + openvdb::Vec3i(1),
                                [&](std::uint32_t k) { group.triangles.push_back(k); });
        }
        const std::vector<std::uint32_t>& candidates = group.triangles;
        // The triangle that held the centre before mostly holds this one too.
        bool near = lastNear < triangles.size()
            && RawPatchDistance::isWithin(centre, triangles[lastNear], limit);
        for (std::size_t i = 0; i < candidates.size() && !near; ++i) {
            const std::uint32_t k = candidates[i];
            if (RawPatchDistance::isWithin(centre, triangles[k], limit)) {
                near = true;
                lastNear = k;
            }
        }
        if (!near) {
            far.push_back({std::uint32_t(p), Vec3d(centre[0] * voxel[0], centre[1] * voxel[1],
                                                   centre[2] * voxel[2])});
        }
    }
}

/// The far centres of patch @a p, from its raw centres @a centres in tasks of
/// CENTRES_PER_TASK.
void
findFarCentresOfPatch(const std::vector<Vec3d>& centres, const InterfaceMesh& mesh,
                      std::size_t p, const Vec3d& voxel, double limit, bool threaded,
                      std::vector<FaceCentre>& far)
{
    const Vec3d inverse(1.0 / voxel[0], 1.0 / voxel[1], 1.0 / voxel[2]);
    const PatchCells cells = cellsOfPatch(mesh, p, inverse, limit);
    const std::size_t tasks = (centres.size() + CENTRES_PER_TASK - 1) / CENTRES_PER_TASK;
    std::vector<std::vector<FaceCentre>> perTask(tasks);
    auto body = [&](std::size_t k) {
        const Vec3d* begin = centres.data() + k * CENTRES_PER_TASK;
        const Vec3d* end = centres.data() + std::min(centres.size(), (k + 1) * CENTRES_PER_TASK);
        findFarCentresIn(cells, p, begin, end, voxel, limit, perTask[k]);
    };
    if (threaded && tasks > 1) {
        tbb::parallel_for(std::size_t(0), tasks, body);
    } else {
        for (std::size_t k = 0; k < tasks; ++k) body(k);
    }
    // In the order of the raw triangles, on any number of threads.
    for (const std::vector<FaceCentre>& part : perTask) {
        far.insert(far.end(), part.begin(), part.end());
    }
}

} // namespace


std::vector<Vec3d>
rawFaceCentresOf(const InterfaceMesh& raw, std::size_t patch, const Vec3d& voxel)
{
    const Vec3d inverse(1.0 / voxel[0], 1.0 / voxel[1], 1.0 / voxel[2]);
    const InterfacePatch& rp = raw.patches[patch];
    std::vector<Vec3d> centres;
    for (std::size_t t = rp.firstTriangle; t < rp.firstTriangle + rp.triangleCount; ++t) {
        const openvdb::Vec3I& tri = raw.triangles[t];
        const Vec3d corner[3] = {scaled(raw.points[tri[0]], inverse),
                                 scaled(raw.points[tri[1]], inverse),
                                 scaled(raw.points[tri[2]], inverse)};
        const Vec3d centre = voxelFaceCentre(corner[0], corner[1], corner[2]);
        if (ownsFaceCentre(corner, centre)) centres.push_back(centre);
    }
    return centres;
}


std::vector<FaceCentre>
findFarFaceCentres(const InterfaceMesh& raw, const InterfaceMesh& mesh, const Vec3d& voxel,
                   double limit, bool threaded)
{
    RawFaceCentres centres(raw.patches.size());
    auto body = [&](std::size_t p) { centres[p] = rawFaceCentresOf(raw, p, voxel); };
    if (threaded) {
        tbb::parallel_for(std::size_t(0), centres.size(), body);
    } else {
        for (std::size_t p = 0; p < centres.size(); ++p) body(p);
    }
    return findFarFaceCentres(centres, mesh, voxel, limit, threaded);
}


std::vector<FaceCentre>
findFarFaceCentres(const RawFaceCentres& centres, const InterfaceMesh& mesh, const Vec3d& voxel,
                   double limit, bool threaded)
{
    const std::size_t count = std::min(centres.size(), mesh.patches.size());
    std::vector<std::vector<FaceCentre>> perPatch(count);
    auto body = [&](std::size_t p) {
        findFarCentresOfPatch(centres[p], mesh, p, voxel, limit, threaded, perPatch[p]);
    };
    if (threaded) {
        tbb::parallel_for(std::size_t(0), count, body);
    } else {
        for (std::size_t p = 0; p < count; ++p) body(p);
    }
    std::vector<FaceCentre> far;
    for (const std::vector<FaceCentre>& part : perPatch) {
        far.insert(far.end(), part.begin(), part.end());
    }
    return far;
}

} // namespace vdbi
