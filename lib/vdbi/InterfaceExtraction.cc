// SPDX-License-Identifier: Apache-2.0

#include <vdbi/InterfaceExtraction.h>

#include <vdbi/BlockFaces.h>
#include <vdbi/Interruption.h>
#include <vdbi/LabelWindow.h>
#include <vdbi/ParallelRanges.h>

#include <openvdb/Exceptions.h>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <functional>

namespace vdbi {

namespace {

using openvdb::Coord;
using extraction::BlockMesh;
using extraction::KEY_UNIT;
using extraction::LabelPair;
using extraction::LocalKey;
using extraction::MAX_SUBDIVISION;
using extraction::PatchRun;
using extraction::keyComponent;

/// Leaf origins of both trees; blocks are these leaves and their + neighbours.
std::vector<Coord>
extractionBlocks(const RefinedLabels& labels, bool threaded)
{
    std::vector<const openvdb::Int32Tree::LeafNodeType*> leaves;
    labels.coarse->tree().getNodes(leaves);
    std::vector<const openvdb::MaskTree::LeafNodeType*> maskLeaves;
    labels.subdivided->tree().getNodes(maskLeaves);
    std::vector<Coord> origins;
    origins.reserve(leaves.size() + maskLeaves.size());
    for (const auto* leaf : leaves) origins.push_back(leaf->origin());
    for (const auto* leaf : maskLeaves) origins.push_back(leaf->origin());
    if (threaded) tbb::parallel_sort(origins.begin(), origins.end());
    else std::sort(origins.begin(), origins.end());
    origins.erase(std::unique(origins.begin(), origins.end()), origins.end());
    return withPositiveNeighbours(origins);
}

/// @brief What a thread walks blocks with in step 1 of the extraction, kept from one range
/// of blocks to the next.
/// @details Made anew for every range (167 ranges for frog on 2 threads), they took frog's
/// extraction to 0.276-0.293 s on one TBB thread, against 0.259 s serial (one for all).
struct BlockScratch
{
    explicit BlockScratch(const RefinedLabels& refined)
        : labels(refined.coarse->tree()), subdivided(refined.subdivided->tree()), walker(refined)
    {}

    LabelWindow::Accessor labels;
    MaskWindow::Accessor subdivided;
    LabelWindow window;
    MaskWindow mask;
    extraction::BlockFaceWalker walker;
    std::vector<std::uint8_t> owner;   ///< per face key of a block: handOverDirection()
};

/// Runs @a body(begin, end) over ranges of [0, n), polling the interrupter once per range.
template<typename Body>
void
forEachChunk(std::size_t n, bool threaded, InterruptFlag& interrupt, const Body& body,
             std::size_t grain)
{
    forEachRange(n, grain, threaded, [&](std::size_t begin, std::size_t end) {
        if (!interrupt.poll()) body(begin, end);
    });
}

/// Bit a of the result: @a k lies on the block's max face along axis a (@a limit = 8 * 2s).
int
handOverDirection(LocalKey k, int limit)
{
    return int(keyComponent(k, 0) == limit) | (int(keyComponent(k, 1) == limit) << 1)
        | (int(keyComponent(k, 2) == limit) << 2);
}

/// Writes the triangles of @a block, corners @a corner (indices into its keys, whose global
/// indices are @a global), to their places in @a mesh: those of its local patch l from
/// start[l] on (start[l] is moved past them).
template<typename Index>
void
scatterTriangles(const BlockMesh& block, const Index* corner,
                 const std::uint32_t* global, std::size_t* start, InterfaceMesh& mesh)
{
    for (const PatchRun& run : block.runs) {
        openvdb::Vec3I* to = mesh.triangles.data() + start[run.patch];
        start[run.patch] += run.count;
        for (std::uint32_t t = 0; t < run.count; ++t, corner += 3) {
            to[t] = openvdb::Vec3I(global[corner[0]], global[corner[1]], global[corner[2]]);
        }
    }
}

} // namespace

InterfaceMesh
extractInterfacePatches(const RefinedLabels& labels, const ExtractionOptions& options)
{
    checkInterrupt(options.interrupter, "extraction");
    const int s = labels.subdivision;
    const int K = 2 * s;
    const int limit = BLOCK_DIM * K; // local key component of a block's max faces
    if (s < 1 || s > MAX_SUBDIVISION) {
        OPENVDB_THROW(openvdb::ValueError, "extraction: subdivision " << s
            << " out of range [1, " << MAX_SUBDIVISION << "]");
    }
    // What moving a key by 8 * 2s along the axes of d subtracts: the offset from a block's
    // local keys to those of its neighbour at origin + 8d.
    LocalKey neighbourShift[8];
    for (int d = 0; d < 8; ++d) {
        neighbourShift[d] = LocalKey(((d & 1) ? limit * KEY_UNIT[0] : 0)
            + ((d & 2) ? limit * KEY_UNIT[1] : 0) + ((d & 4) ? limit * KEY_UNIT[2] : 0));
    }
    const std::vector<Coord> origins = extractionBlocks(labels, options.threaded);
    const std::size_t blockCount = origins.size();
    std::vector<BlockMesh> blocks(blockCount);
    InterruptFlag interrupt(options.interrupter);
    auto blockIndex = [&](const Coord& origin) -> std::ptrdiff_t {
        const auto it = std::lower_bound(origins.begin(), origins.end(), origin);
        return (it != origins.end() && *it == origin) ? it - origins.begin() : -1;
    };
    auto neighbourOrigin = [&](std::size_t n, int d, int sign) {
        return origins[n].offsetBy((d & 1) ? sign * BLOCK_DIM : 0,
            (d & 2) ? sign * BLOCK_DIM : 0, (d & 4) ? sign * BLOCK_DIM : 0);
    };

    tbb::enumerable_thread_specific<BlockScratch> scratches(std::cref(labels));
    // 1. Triangles per block, with block-local keys, sorted by the block that numbers them:
    //    itself, or for the keys on its max faces the neighbour beyond.
    forEachChunk(blockCount, options.threaded, interrupt,
                 [&](std::size_t begin, std::size_t end) {
        BlockScratch& scratch = scratches.local();
        std::vector<std::uint8_t>& owner = scratch.owner;
        for (std::size_t n = begin; n < end; ++n) {
            // Blocks outside the owner box emit nothing but still number their keys.
            if (!options.ownerBox.empty() && !options.ownerBox.hasOverlap(
                    openvdb::CoordBBox(origins[n], origins[n].offsetBy(BLOCK_DIM - 1)))) {
                continue;
            }
            scratch.window.load(scratch.labels, origins[n]);
            const bool hasMask = scratch.mask.load(scratch.subdivided, origins[n]);
            BlockMesh& block = blocks[n];
            scratch.walker.walk(scratch.window, hasMask ? &scratch.mask : nullptr,
                                options.ownerBox, block);
            // Keys inside the block are its alone, numbered in their order; the face keys by
            // their owners, in step 2. The owners' lists are sized first: grown key by key,
            // they cost an allocation per doubling.
            const std::size_t faceCount = block.keys.size() - block.insideCount;
            block.rank.resize(faceCount);
            owner.resize(faceCount);
            std::size_t ownerCount[8] = {};
            for (std::size_t f = 0; f < faceCount; ++f) {
                owner[f] = std::uint8_t(handOverDirection(block.keys[block.insideCount + f],
                                                          limit));
                ++ownerCount[owner[f]];
            }
            for (int d = 0; d < 8; ++d) block.byOwner[d].reserve(ownerCount[d]);
            for (std::size_t f = 0; f < faceCount; ++f) {
                block.byOwner[owner[f]].push_back(std::uint32_t(block.insideCount + f));
            }
        }
    }, 4);
    interrupt.throwIfStopped("extraction");
    scratches.clear();   // the walkers are done: their buffers go before the output is made
    std::size_t triangleTotal = 0;
    for (const BlockMesh& block : blocks) triangleTotal += block.triangleCount();
    InterfaceMesh mesh;
    // Uninitialized (see PointArray): the pages are first touched by the parallel loops
    // that fill them.
    mesh.triangles.resize(triangleTotal);

    // 2. Every block numbers the keys on its min faces, its own and those of its neighbours
    //    at origin - 8d on their max faces, in key order after its inside ones, and tells
    //    every key its rank: each key has one owner, so the writes of different blocks go to
    //    different places.
    forEachChunk(blockCount, options.threaded, interrupt,
                 [&](std::size_t begin, std::size_t end) {
        // key << 32 | d << 29 | i: key i of the block at origin - 8d, in this block's local
        // coordinates. A block holds fewer than 2^29 keys ((8 * 2s + 1)^3 <= 241^3 < 2^29).
        std::vector<std::uint64_t> entries;
        BlockMesh* from[8];
        for (std::size_t n = begin; n < end; ++n) {
            entries.clear();
            for (int d = 0; d < 8; ++d) {
                const std::ptrdiff_t x = d == 0 ? std::ptrdiff_t(n)
                    : blockIndex(neighbourOrigin(n, d, -1));
                from[d] = x < 0 ? nullptr : &blocks[std::size_t(x)];
                if (!from[d]) continue;
                for (const std::uint32_t i : from[d]->byOwner[d]) {
                    const LocalKey k = from[d]->keys[i] - neighbourShift[d];
                    entries.push_back((std::uint64_t(k) << 32) | (std::uint64_t(d) << 29) | i);
                }
            }
            std::sort(entries.begin(), entries.end());
            std::vector<LocalKey>& faceKeys = blocks[n].faceKeys;
            const std::uint32_t inside = blocks[n].insideCount;
            faceKeys.reserve(entries.size());
            for (const std::uint64_t e : entries) {
                const auto k = LocalKey(e >> 32);
                if (faceKeys.empty() || faceKeys.back() != k) faceKeys.push_back(k);
                BlockMesh* owner = from[(e >> 29) & 7u];
                owner->rank[(e & ((1u << 29) - 1)) - owner->insideCount] =
                    inside + std::uint32_t(faceKeys.size() - 1);
            }
        }
    }, 8);
    interrupt.throwIfStopped("extraction");

    std::vector<std::size_t> vertexOffset(blockCount + 1, 0);
    for (std::size_t n = 0; n < blockCount; ++n) {
        vertexOffset[n + 1] = vertexOffset[n] + blocks[n].ownedCount();
    }

    // 3. Patches in (a, b) order; inside a patch, block order then emission order. Every
    //    (block, local patch) gets the place of its first triangle, in a flat array: only
    //    the pairs that occur are visited, so this is linear in the output.
    std::vector<std::size_t> firstLocal(blockCount + 1, 0);
    for (std::size_t n = 0; n < blockCount; ++n) {
        firstLocal[n + 1] = firstLocal[n] + blocks[n].patches.size();
    }
    std::vector<LabelPair> pairs; // sorted; few, so a search beats a tree of nodes
    for (const BlockMesh& block : blocks) {
        for (const LabelPair& p : block.patches) {
            const auto it = std::lower_bound(pairs.begin(), pairs.end(), p);
            if (it == pairs.end() || *it != p) pairs.insert(it, p);
        }
    }
    mesh.keyScale = K;
    mesh.patches.resize(pairs.size());
    std::vector<std::uint32_t> patchOf(firstLocal.back());
    std::vector<std::size_t> start(firstLocal.back());
    std::vector<std::size_t> next(pairs.size(), 0); // per patch, then where its next run goes
    for (std::size_t n = 0; n < blockCount; ++n) {
        const BlockMesh& block = blocks[n];
        for (std::size_t l = 0; l < block.patches.size(); ++l) {
            const auto p = std::size_t(
                std::lower_bound(pairs.begin(), pairs.end(), block.patches[l]) - pairs.begin());
            patchOf[firstLocal[n] + l] = std::uint32_t(p);
            next[p] += block.patchCounts[l];
        }
    }
    std::size_t total = 0;
    for (std::size_t p = 0; p < pairs.size(); ++p) {
        InterfacePatch& patch = mesh.patches[p];
        patch.a = pairs[p][0];
        patch.b = pairs[p][1];
        patch.firstTriangle = total;
        patch.triangleCount = next[p];
        total += next[p];
        next[p] = patch.firstTriangle;
    }
    for (std::size_t n = 0; n < blockCount; ++n) {
        for (std::size_t i = firstLocal[n]; i < firstLocal[n + 1]; ++i) {
            start[i] = next[patchOf[i]];
            next[patchOf[i]] += blocks[n].patchCounts[i - firstLocal[n]];
        }
    }

    // 4. Per block, in one pass over its data: the global indices of its keys (their owners'
    //    offsets plus their ranks), its triangles at their places, then the points it
    //    numbers (its inside keys, then its face keys).
    mesh.points.resize(vertexOffset.back());
    if (options.pointKeys) mesh.pointKeys.resize(vertexOffset.back());
    std::atomic<bool> lostKey{false};
    // @a toWorld maps a global key to world space.
    auto finishBlocks = [&](const auto& toWorld) {
        forEachChunk(blockCount, options.threaded, interrupt,
                     [&](std::size_t begin, std::size_t end) {
            // Every key of a block gets its global index before the triangles read it.
            extraction::UninitializedVector<std::uint32_t> global;
            for (std::size_t n = begin; n < end; ++n) {
                BlockMesh& block = blocks[n];
                global.resize(block.keys.size());
                for (std::uint32_t i = 0; i < block.insideCount; ++i) {
                    global[i] = std::uint32_t(vertexOffset[n] + i);
                }
                for (int d = 0; d < 8; ++d) {
                    if (block.byOwner[d].empty()) continue;
                    const std::ptrdiff_t owner = d == 0 ? std::ptrdiff_t(n)
                        : blockIndex(neighbourOrigin(n, d, 1));
                    if (owner < 0) {
                        lostKey = true;
                        continue;
                    }
                    const std::size_t offset = vertexOffset[std::size_t(owner)];
                    for (const std::uint32_t i : block.byOwner[d]) {
                        global[i] = std::uint32_t(offset + block.rank[i - block.insideCount]);
                    }
                }
                if (block.corners32.empty()) {
                    scatterTriangles(block, block.corners16.data(), global.data(),
                                     start.data() + firstLocal[n], mesh);
                } else {
                    scatterTriangles(block, block.corners32.data(), global.data(),
                                     start.data() + firstLocal[n], mesh);
                }
                const std::int64_t base[3] = {std::int64_t(K) * origins[n].x(),
                    std::int64_t(K) * origins[n].y(), std::int64_t(K) * origins[n].z()};
                // Points [first, first + count) from local keys @a local.
                auto write = [&](std::size_t first, const LocalKey* local, std::size_t count) {
                    openvdb::Vec3d* points = mesh.points.data() + first;
                    VertexKey* keys = options.pointKeys ? mesh.pointKeys.data() + first
                                                        : nullptr;
                    for (std::size_t i = 0; i < count; ++i) {
                        const VertexKey k = {base[0] + keyComponent(local[i], 0),
                            base[1] + keyComponent(local[i], 1),
                            base[2] + keyComponent(local[i], 2)};
                        points[i] = toWorld(k);
                        if (keys) keys[i] = k;
                    }
                };
                write(vertexOffset[n], block.keys.data(), block.insideCount);
                write(vertexOffset[n] + block.insideCount, block.faceKeys.data(),
                      block.faceKeys.size());
                // Freed here, in parallel, rather than all at once at the end.
                block = BlockMesh();
            }
        }, 8);
    };
    // A key k of block X is at coarse index (2s X + k) / 2s; voxel centres sit at integer
    // indices in OpenVDB, so the cube of voxel c spans [c - 0.5, c + 0.5] there.
    const openvdb::math::Transform& xform = labels.coarse->transform();
    // The usual maps (axis-aligned scale, and offset, as from image files) come down to
    // world = k * step + offset per axis: no division and no virtual call per point.
    const auto* scale = dynamic_cast<const openvdb::math::ScaleMap*>(xform.baseMap().get());
    const auto* scaleTranslate =
        dynamic_cast<const openvdb::math::ScaleTranslateMap*>(xform.baseMap().get());
    if (scale || scaleTranslate) {
        const openvdb::Vec3d voxel = scale ? scale->getScale() : scaleTranslate->getScale();
        const openvdb::Vec3d step = voxel / double(K),
            offset = (scale ? openvdb::Vec3d(0.0) : scaleTranslate->getTranslation())
                - 0.5 * voxel;
        finishBlocks([step, offset](const VertexKey& k) {
            return openvdb::Vec3d(double(k[0]) * step[0] + offset[0],
                double(k[1]) * step[1] + offset[1], double(k[2]) * step[2] + offset[2]);
        });
    } else {
        finishBlocks([&xform, K](const VertexKey& k) {
            return xform.indexToWorld(openvdb::Vec3d(double(k[0]) / double(K) - 0.5,
                double(k[1]) / double(K) - 0.5, double(k[2]) / double(K) - 0.5));
        });
    }
    interrupt.throwIfStopped("extraction");
    if (lostKey) throw TopologyError("extraction: a vertex key has no owner block");
    return mesh;
}

} // namespace vdbi
