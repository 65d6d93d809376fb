// SPDX-License-Identifier: Apache-2.0

#include <vdbi/InterfaceExtraction.h>

#include <vdbi/Interruption.h>
#include <vdbi/LabelWindow.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <memory>

namespace vdbi {

namespace {

using openvdb::Coord;
using LabelPair = std::array<Label, 2>;

/// Which coarse voxels of a block's window are subdivided.
class MaskWindow
{
public:
    using Accessor = openvdb::tree::ValueAccessor<const openvdb::MaskTree, false>;

    /// Returns false (and loads nothing) when no subdivided voxel is near the block.
    bool load(Accessor& acc, const Coord& origin)
    {
        using LeafT = openvdb::MaskTree::LeafNodeType;
        const Coord lo = origin.offsetBy(-1);
        bool any = false;
        for (int n = 0; n < 27; ++n) {
            const Coord leafOrigin = origin.offsetBy((n % 3 - 1) * BLOCK_DIM,
                ((n / 3) % 3 - 1) * BLOCK_DIM, (n / 9 - 1) * BLOCK_DIM);
            mLeaves[n] = acc.probeConstLeaf(leafOrigin);
            mTiles[n] = !mLeaves[n] && acc.isValueOn(leafOrigin);
            any = any || mLeaves[n] || mTiles[n];
        }
        if (!any) return false;
        for (int x = 0; x < DIM; ++x) for (int y = 0; y < DIM; ++y) for (int z = 0; z < DIM; ++z) {
            const int n = part(x) + 3 * part(y) + 9 * part(z);
            const Coord g = lo.offsetBy(x, y, z);
            mOn[LabelWindow::index(x, y, z)] =
                mLeaves[n] ? mLeaves[n]->isValueOn(LeafT::coordToOffset(g)) : mTiles[n];
        }
        return true;
    }
    bool at(int flat) const { return mOn[flat]; }

private:
    static constexpr int DIM = LabelWindow::DIM;
    static int part(int w) { return w == 0 ? 0 : (w <= BLOCK_DIM ? 1 : 2); }
    const openvdb::MaskTree::LeafNodeType* mLeaves[27];
    bool mTiles[27];
    bool mOn[DIM * DIM * DIM];
};

/// Triangles of one block, before vertices are numbered globally.
struct BlockMesh
{
    std::vector<VertexKey> keys;            ///< distinct corner keys, in order of first use
    std::vector<std::uint32_t> corners;     ///< 3 per triangle: indices into keys
    std::vector<LabelPair> patches;         ///< distinct label pairs, in order of first use
    std::vector<std::uint32_t> patchOf;     ///< per triangle: index into patches
    std::vector<std::size_t> patchCounts;   ///< triangles per entry of patches
    std::vector<VertexKey> owned;           ///< keys this block numbers (see ownerOf), sorted
    std::vector<std::uint32_t> global;      ///< global index of every entry of keys
};

/// Open-addressing map from the keys of one block to their indices in BlockMesh::keys.
class KeyIndex
{
public:
    void reset(std::vector<VertexKey>& keys)
    {
        mKeys = &keys;
        if (mSlots.empty()) mSlots.assign(1 << 12, 0);
        else std::fill(mSlots.begin(), mSlots.end(), 0u);
    }

    std::uint32_t insert(const VertexKey& k)
    {
        if (2 * (mKeys->size() + 1) > mSlots.size()) grow();
        std::size_t h = slotOf(k);
        while (mSlots[h] != 0) {
            if ((*mKeys)[mSlots[h] - 1] == k) return mSlots[h] - 1;
            h = (h + 1) & (mSlots.size() - 1);
        }
        mKeys->push_back(k);
        mSlots[h] = std::uint32_t(mKeys->size());
        return mSlots[h] - 1;
    }

private:
    std::size_t slotOf(const VertexKey& k) const
    {
        std::uint64_t h = std::uint64_t(k[0]) * 0x9E3779B97F4A7C15ull;
        h ^= std::uint64_t(k[1]) * 0xC2B2AE3D27D4EB4Full + (h >> 29);
        h ^= std::uint64_t(k[2]) * 0x165667B19E3779F9ull + (h >> 32);
        h ^= h >> 31;
        return std::size_t(h) & (mSlots.size() - 1);
    }

    void grow()
    {
        mSlots.assign(mSlots.size() * 2, 0);
        for (std::size_t i = 0; i < mKeys->size(); ++i) {
            std::size_t h = slotOf((*mKeys)[i]);
            while (mSlots[h] != 0) h = (h + 1) & (mSlots.size() - 1);
            mSlots[h] = std::uint32_t(i + 1);
        }
    }

    std::vector<std::uint32_t> mSlots; ///< index + 1 into *mKeys, 0 = empty
    std::vector<VertexKey>* mKeys = nullptr;
};

/// A key with component @a ka along axis @a a and kb, kc along the next two axes (cyclic).
VertexKey
keyOf(int a, std::int64_t ka, std::int64_t kb, std::int64_t kc)
{
    VertexKey k;
    k[a] = ka;
    k[(a + 1) % 3] = kb;
    k[(a + 2) % 3] = kc;
    return k;
}

std::int64_t
floorDiv64(std::int64_t a, std::int64_t b)
{
    const std::int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}

/// Emits the faces owned by the voxels of one block (face (v, a) is owned by voxel v).
class FaceWalker
{
public:
    FaceWalker(const RefinedLabels& labels)
        : mS(labels.subdivision)
        , mFine(labels.fine->tree())
        , mFineLabels(std::size_t(mS) * mS * mS)
        , mFacePairs(std::size_t(mS) * mS)
        , mUsed(std::size_t(mS) * mS)
    {}

    void walk(const LabelWindow& w, const MaskWindow* mask, const openvdb::CoordBBox& owners,
              BlockMesh& out)
    {
        mOut = &out;
        mIndex.reset(out.keys);
        const Coord& o = w.origin();
        const bool clipped = !owners.empty();
        for (int i = 0; i < BLOCK_DIM; ++i) {
            for (int j = 0; j < BLOCK_DIM; ++j) {
                for (int k = 0; k < BLOCK_DIM; ++k) {
                    const Coord v = o.offsetBy(i, j, k);
                    if (clipped && !owners.isInside(v)) continue;
                    const int flat = LabelWindow::index(i + 1, j + 1, k + 1);
                    const Label upper = w.data()[flat];
                    const bool upperSub = mask && mask->at(flat);
                    if (upperSub) interiorFaces(v, upper);
                    for (int a = 0; a < 3; ++a) {
                        const int lowerFlat = flat - LabelWindow::STRIDE[a];
                        const Label lower = w.data()[lowerFlat];
                        const bool lowerSub = mask && mask->at(lowerFlat);
                        if (upperSub || lowerSub) {
                            splitFace(v, a, lower, lowerSub, upper, upperSub);
                        } else if (lower != upper) {
                            coarseFace(v, a, lower, upper, flat, mask);
                        }
                    }
                }
            }
        }
    }

private:
    /// Appends the triangles of a polygon given counter-clockwise seen from +a: as a fan
    /// around @a centre, or (no centre, 4 corners) as two triangles.
    void emitTriangle(const VertexKey& p, const VertexKey& q, const VertexKey& r,
                      Label lower, Label upper)
    {
        // Patch (a, b) with a < b has its normal from a into b; +axis points lower -> upper.
        const bool up = lower < upper;
        const LabelPair pair = up ? LabelPair{lower, upper} : LabelPair{upper, lower};
        if (mOut->patches.empty() || mOut->patches[mLastPatch] != pair) {
            const auto it = std::find(mOut->patches.begin(), mOut->patches.end(), pair);
            mLastPatch = std::size_t(it - mOut->patches.begin());
            if (it == mOut->patches.end()) mOut->patches.push_back(pair);
        }
        mOut->patchOf.push_back(std::uint32_t(mLastPatch));
        mOut->corners.push_back(mIndex.insert(p));
        mOut->corners.push_back(mIndex.insert(up ? q : r));
        mOut->corners.push_back(mIndex.insert(up ? r : q));
    }

    void emitQuad(const VertexKey (&c)[4], Label lower, Label upper)
    {
        emitTriangle(c[0], c[1], c[2], lower, upper);
        emitTriangle(c[0], c[2], c[3], lower, upper);
    }

    /// A coarse face between two voxels that are not subdivided.
    void coarseFace(const Coord& v, int a, Label lower, Label upper, int flat,
                    const MaskWindow* mask)
    {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        // A side (edge) is split when a voxel around it is subdivided. Sides in CCW order:
        // c = 0 along +b, b = 1 along +c, c = 1 along -b, b = 0 along -c.
        bool split[4] = {false, false, false, false};
        if (mask) {
            const int sa = LabelWindow::STRIDE[a], sb = LabelWindow::STRIDE[b],
                      sc = LabelWindow::STRIDE[c];
            for (int da = -1; da <= 0; ++da) {
                const int f = flat + da * sa;
                split[0] = split[0] || mask->at(f) || mask->at(f - sc);
                split[1] = split[1] || mask->at(f) || mask->at(f + sb);
                split[2] = split[2] || mask->at(f) || mask->at(f + sc);
                split[3] = split[3] || mask->at(f) || mask->at(f - sb);
            }
        }
        if (split[0] || split[1] || split[2] || split[3]) {
            fan(v, a, split, lower, upper);
            return;
        }
        const std::int64_t K = 2 * mS; // key units per coarse voxel
        const std::int64_t va = K * v[a], vb = K * v[b], vc = K * v[c];
        const VertexKey corner[4] = {keyOf(a, va, vb, vc), keyOf(a, va, vb + K, vc),
            keyOf(a, va, vb + K, vc + K), keyOf(a, va, vb, vc + K)};
        emitQuad(corner, lower, upper);
    }

    /// The paper's rule for a coarse face with a split side: a fan from the face centre to
    /// all boundary points, s + 1 of them along each split side.
    void fan(const Coord& v, int a, const bool (&split)[4], Label lower, Label upper)
    {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const std::int64_t K = 2 * mS;
        const std::int64_t va = K * v[a], vb = K * v[b], vc = K * v[c];
        const VertexKey corner[4] = {keyOf(a, va, vb, vc), keyOf(a, va, vb + K, vc),
            keyOf(a, va, vb + K, vc + K), keyOf(a, va, vb, vc + K)};
        const VertexKey centre = keyOf(a, va, vb + mS, vc + mS);
        const std::int64_t step[4][2] = {{2, 0}, {0, 2}, {-2, 0}, {0, -2}};
        for (int side = 0; side < 4; ++side) {
            const int pieces = split[side] ? mS : 1;
            const std::int64_t scale = split[side] ? 1 : mS;
            VertexKey p = corner[side];
            for (int n = 0; n < pieces; ++n) {
                VertexKey q = p;
                q[b] += step[side][0] * scale;
                q[c] += step[side][1] * scale;
                emitTriangle(centre, p, q, lower, upper);
                p = q;
            }
        }
    }

    /// Label of fine voxel @a f inside coarse voxel @a u.
    Label fineLabel(const Coord& f, Label coarse, bool subdivided)
    {
        Label l;
        return (subdivided && mFine.probeValue(f, l)) ? l : coarse;
    }

    /// A coarse face next to a subdivided voxel: its s x s fine faces, each on its own.
    void splitFace(const Coord& v, int a, Label lower, bool lowerSub, Label upper,
                   bool upperSub)
    {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const int s = mS;
        for (int jb = 0; jb < s; ++jb) {
            for (int jc = 0; jc < s; ++jc) {
                Coord f;
                f[a] = s * v[a];
                f[b] = s * v[b] + jb;
                f[c] = s * v[c] + jc;
                Coord g = f;
                g[a] -= 1;
                mFacePairs[jb * s + jc] = {fineLabel(g, lower, lowerSub),
                                           fineLabel(f, upper, upperSub)};
            }
        }
        fineFaceGrid(Coord(s * v.x(), s * v.y(), s * v.z()), a);
    }

    /// Emits the s x s fine faces at fine point @a corner with normal @a a, whose label
    /// pairs (lower, upper) are in mFacePairs (index jb * s + jc along the next two axes).
    /// @details Faces with the same pair are merged greedily into rectangles, each a fan
    /// from its centre to all fine points on its boundary: the same surface in fewer
    /// triangles. No other face can use a point inside such a rectangle (it would need two
    /// different labels on one side of it), so this adds no T-junction.
    void fineFaceGrid(const Coord& corner, int a)
    {
        const int s = mS;
        std::fill(mUsed.begin(), mUsed.end(), char(0));
        auto isFree = [&](int x, int y, const LabelPair& pair) {
            return !mUsed[x * s + y] && mFacePairs[x * s + y] == pair;
        };
        for (int jb = 0; jb < s; ++jb) {
            for (int jc = 0; jc < s; ++jc) {
                const LabelPair pair = mFacePairs[jb * s + jc];
                if (mUsed[jb * s + jc] || pair[0] == pair[1]) continue;
                int w = 1;
                while (jc + w < s && isFree(jb, jc + w, pair)) ++w;
                int h = 1;
                for (bool grow = true; grow && jb + h < s; ) {
                    for (int y = jc; y < jc + w && grow; ++y) grow = isFree(jb + h, y, pair);
                    if (grow) ++h;
                }
                for (int x = jb; x < jb + h; ++x) {
                    for (int y = jc; y < jc + w; ++y) mUsed[x * s + y] = 1;
                }
                rectangle(corner, a, jb, jc, h, w, pair[0], pair[1]);
            }
        }
    }

    /// Fine faces [jb, jb + h) x [jc, jc + w) of the grid at @a corner as one polygon.
    void rectangle(const Coord& corner, int a, int jb, int jc, int h, int w,
                   Label lower, Label upper)
    {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const std::int64_t ka = 2 * std::int64_t(corner[a]);
        const std::int64_t kb = 2 * (std::int64_t(corner[b]) + jb);
        const std::int64_t kc = 2 * (std::int64_t(corner[c]) + jc);
        const VertexKey quad[4] = {keyOf(a, ka, kb, kc), keyOf(a, ka, kb + 2 * h, kc),
            keyOf(a, ka, kb + 2 * h, kc + 2 * w), keyOf(a, ka, kb, kc + 2 * w)};
        if (w * h <= w + h) { // a fan would not be smaller than the quads
            for (int x = 0; x < h; ++x) {
                for (int y = 0; y < w; ++y) {
                    const VertexKey q[4] = {keyOf(a, ka, kb + 2 * x, kc + 2 * y),
                        keyOf(a, ka, kb + 2 * x + 2, kc + 2 * y),
                        keyOf(a, ka, kb + 2 * x + 2, kc + 2 * y + 2),
                        keyOf(a, ka, kb + 2 * x, kc + 2 * y + 2)};
                    emitQuad(q, lower, upper);
                }
            }
            return;
        }
        const VertexKey centre = keyOf(a, ka, kb + h, kc + w);
        const int pieces[4] = {h, w, h, w};
        const std::int64_t step[4][2] = {{2, 0}, {0, 2}, {-2, 0}, {0, -2}};
        for (int side = 0; side < 4; ++side) {
            VertexKey p = quad[side];
            for (int n = 0; n < pieces[side]; ++n) {
                VertexKey q = p;
                q[b] += step[side][0];
                q[c] += step[side][1];
                emitTriangle(centre, p, q, lower, upper);
                p = q;
            }
        }
    }

    /// Fine faces inside subdivided voxel @a v, between its own subvoxels.
    void interiorFaces(const Coord& v, Label coarse)
    {
        const int s = mS;
        const Coord base(s * v.x(), s * v.y(), s * v.z());
        bool changed = false;
        for (int x = 0; x < s; ++x) for (int y = 0; y < s; ++y) for (int z = 0; z < s; ++z) {
            Label& l = mFineLabels[(x * s + y) * s + z];
            l = fineLabel(base.offsetBy(x, y, z), coarse, true);
            changed = changed || l != coarse;
        }
        if (!changed) return;
        const int stride[3] = {s * s, s, 1};
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            // Planes t = 1 .. s-1 inside the voxel; t = 0 is the voxel's face: splitFace().
            for (int t = 1; t < s; ++t) {
                for (int jb = 0; jb < s; ++jb) {
                    for (int jc = 0; jc < s; ++jc) {
                        const int idx = t * stride[a] + jb * stride[b] + jc * stride[c];
                        mFacePairs[jb * s + jc] = {mFineLabels[idx - stride[a]],
                                                   mFineLabels[idx]};
                    }
                }
                Coord corner = base;
                corner[a] += t;
                fineFaceGrid(corner, a);
            }
        }
    }

    const int mS;
    openvdb::tree::ValueAccessor<const openvdb::Int32Tree, false> mFine;
    std::vector<Label> mFineLabels;
    std::vector<LabelPair> mFacePairs;
    std::vector<char> mUsed;
    KeyIndex mIndex;
    BlockMesh* mOut = nullptr;
    std::size_t mLastPatch = 0;
};

/// Leaf origins of both trees; blocks are these leaves and their + neighbours.
std::vector<Coord>
extractionBlocks(const RefinedLabels& labels, bool threaded)
{
    std::vector<Coord> origins = blockOrigins(labels.coarse->tree(), threaded);
    std::vector<const openvdb::MaskTree::LeafNodeType*> maskLeaves;
    labels.subdivided->tree().getNodes(maskLeaves);
    for (const auto* leaf : maskLeaves) {
        for (int n = 0; n < 8; ++n) {
            origins.push_back(leaf->origin().offsetBy((n & 1) ? BLOCK_DIM : 0,
                (n & 2) ? BLOCK_DIM : 0, (n & 4) ? BLOCK_DIM : 0));
        }
    }
    std::sort(origins.begin(), origins.end());
    origins.erase(std::unique(origins.begin(), origins.end()), origins.end());
    return origins;
}

template<typename Body>
void
forEachIndex(std::size_t n, bool threaded, InterruptFlag& interrupt, const Body& body,
             std::size_t grain = 8)
{
    auto run = [&](const tbb::blocked_range<std::size_t>& r) {
        if (interrupt.poll()) return;
        for (std::size_t i = r.begin(); i < r.end(); ++i) body(i);
    };
    const tbb::blocked_range<std::size_t> all(0, n, grain);
    if (threaded) tbb::parallel_for(all, run);
    else run(all);
}

} // namespace

InterfaceMesh
extractInterfacePatches(const RefinedLabels& labels, const ExtractionOptions& options)
{
    checkInterrupt(options.interrupter, "extraction");
    const int s = labels.subdivision;
    const std::int64_t K = 2 * s;
    const std::vector<Coord> origins = extractionBlocks(labels, options.threaded);
    std::vector<BlockMesh> blocks(origins.size());
    InterruptFlag interrupt(options.interrupter);

    // 1. Triangles per block, with block-local vertex indices.
    auto walkBlocks = [&](const tbb::blocked_range<std::size_t>& range) {
        if (interrupt.poll()) return;
        LabelWindow::Accessor acc(labels.coarse->tree());
        MaskWindow::Accessor maskAcc(labels.subdivided->tree());
        auto window = std::make_unique<LabelWindow>();
        auto mask = std::make_unique<MaskWindow>();
        FaceWalker walker(labels);
        for (std::size_t n = range.begin(); n < range.end(); ++n) {
            // Blocks outside the owner box emit nothing but still number their keys.
            if (!options.ownerBox.empty() && !options.ownerBox.hasOverlap(
                    openvdb::CoordBBox(origins[n], origins[n].offsetBy(BLOCK_DIM - 1)))) {
                continue;
            }
            window->load(acc, origins[n]);
            const bool hasMask = mask->load(maskAcc, origins[n]);
            BlockMesh& block = blocks[n];
            walker.walk(*window, hasMask ? mask.get() : nullptr, options.ownerBox, block);
            block.patchCounts.assign(block.patches.size(), 0);
            for (const std::uint32_t l : block.patchOf) ++block.patchCounts[l];
        }
    };
    const tbb::blocked_range<std::size_t> allBlocks(0, origins.size(), 4);
    if (options.threaded) tbb::parallel_for(allBlocks, walkBlocks);
    else walkBlocks(allBlocks);
    interrupt.throwIfStopped("extraction");

    // 2. Every key is numbered by one block: the one holding the coarse cell it lies in.
    //    Keys of block X lie in [X, X + 8] coarse units, so their owners are X + {0, 8}^3.
    auto ownerOf = [&](const VertexKey& k) {
        return Coord(int(floorDiv64(floorDiv64(k[0], K), BLOCK_DIM) * BLOCK_DIM),
                     int(floorDiv64(floorDiv64(k[1], K), BLOCK_DIM) * BLOCK_DIM),
                     int(floorDiv64(floorDiv64(k[2], K), BLOCK_DIM) * BLOCK_DIM));
    };
    auto blockIndex = [&](const Coord& origin) -> std::ptrdiff_t {
        const auto it = std::lower_bound(origins.begin(), origins.end(), origin);
        return (it != origins.end() && *it == origin) ? it - origins.begin() : -1;
    };
    forEachIndex(origins.size(), options.threaded, interrupt, [&](std::size_t n) {
        BlockMesh& block = blocks[n];
        for (int m = 0; m < 8; ++m) {
            const std::ptrdiff_t x = blockIndex(origins[n].offsetBy((m & 1) ? -BLOCK_DIM : 0,
                (m & 2) ? -BLOCK_DIM : 0, (m & 4) ? -BLOCK_DIM : 0));
            if (x < 0) continue;
            for (const VertexKey& k : blocks[x].keys) {
                if (ownerOf(k) == origins[n]) block.owned.push_back(k);
            }
        }
        std::sort(block.owned.begin(), block.owned.end());
        block.owned.erase(std::unique(block.owned.begin(), block.owned.end()),
            block.owned.end());
    });
    interrupt.throwIfStopped("extraction");

    std::vector<std::size_t> vertexOffset(origins.size() + 1, 0);
    for (std::size_t n = 0; n < origins.size(); ++n) {
        vertexOffset[n + 1] = vertexOffset[n] + blocks[n].owned.size();
    }

    // 3. Global indices of every block's keys, through their owners (among X + {0, 8}^3).
    std::atomic<bool> lostKey{false};
    forEachIndex(origins.size(), options.threaded, interrupt, [&](std::size_t n) {
        BlockMesh& block = blocks[n];
        std::ptrdiff_t owners[8];
        for (int m = 0; m < 8; ++m) {
            owners[m] = blockIndex(origins[n].offsetBy((m & 1) ? BLOCK_DIM : 0,
                (m & 2) ? BLOCK_DIM : 0, (m & 4) ? BLOCK_DIM : 0));
        }
        block.global.resize(block.keys.size());
        for (std::size_t i = 0; i < block.keys.size(); ++i) {
            const VertexKey& k = block.keys[i];
            const Coord d = ownerOf(k) - origins[n];
            const std::ptrdiff_t owner = owners[(d.x() > 0) | ((d.y() > 0) << 1)
                | ((d.z() > 0) << 2)];
            if (owner < 0) { lostKey = true; continue; }
            const auto& owned = blocks[owner].owned;
            const auto it = std::lower_bound(owned.begin(), owned.end(), k);
            block.global[i] = std::uint32_t(vertexOffset[owner] + (it - owned.begin()));
        }
    });
    interrupt.throwIfStopped("extraction");
    if (lostKey) throw TopologyError("extraction: a vertex key has no owner block");

    // 4. Patches in (a, b) order; inside a patch, block order then emission order.
    std::map<LabelPair, std::size_t> patchIndex;
    for (const BlockMesh& block : blocks) {
        for (const LabelPair& p : block.patches) patchIndex.emplace(p, 0);
    }
    InterfaceMesh mesh;
    mesh.keyScale = int(K);
    for (auto& entry : patchIndex) {
        entry.second = mesh.patches.size();
        InterfacePatch patch;
        patch.a = entry.first[0];
        patch.b = entry.first[1];
        mesh.patches.push_back(patch);
    }
    // start[n][l]: where block n's triangles of its local patch l go. Only the (block,
    // patch) pairs that occur are visited, so this is linear in the output.
    std::vector<std::vector<std::size_t>> start(origins.size());
    std::vector<std::vector<std::pair<std::size_t, std::size_t>>> users(mesh.patches.size());
    for (std::size_t n = 0; n < origins.size(); ++n) {
        const BlockMesh& block = blocks[n];
        start[n].resize(block.patches.size());
        for (std::size_t l = 0; l < block.patches.size(); ++l) {
            users[patchIndex[block.patches[l]]].push_back({n, block.patchCounts[l]});
        }
    }
    std::size_t total = 0;
    for (std::size_t p = 0; p < mesh.patches.size(); ++p) {
        mesh.patches[p].firstTriangle = total;
        const LabelPair pair{mesh.patches[p].a, mesh.patches[p].b};
        for (const auto& user : users[p]) {
            const BlockMesh& block = blocks[user.first];
            const std::size_t l = std::size_t(std::find(block.patches.begin(),
                block.patches.end(), pair) - block.patches.begin());
            start[user.first][l] = total;
            total += user.second;
        }
        mesh.patches[p].triangleCount = total - mesh.patches[p].firstTriangle;
    }

    mesh.triangles.resize(total);
    forEachIndex(origins.size(), options.threaded, interrupt, [&](std::size_t n) {
        const BlockMesh& block = blocks[n];
        std::vector<std::size_t>& next = start[n];
        for (std::size_t t = 0; t < block.patchOf.size(); ++t) {
            const std::size_t at = next[block.patchOf[t]]++;
            mesh.triangles[at] = openvdb::Vec3I(block.global[block.corners[3 * t]],
                block.global[block.corners[3 * t + 1]], block.global[block.corners[3 * t + 2]]);
        }
    });
    interrupt.throwIfStopped("extraction");

    // 5. Points: a key k is at coarse index k / 2s; voxel centres sit at integer indices in
    //    OpenVDB, so the cube of voxel c spans [c - 0.5, c + 0.5] there.
    mesh.points.resize(vertexOffset.back());
    mesh.pointKeys.resize(vertexOffset.back());
    const openvdb::math::Transform& xform = labels.coarse->transform();
    forEachIndex(origins.size(), options.threaded, interrupt, [&](std::size_t n) {
        const BlockMesh& block = blocks[n];
        for (std::size_t i = 0; i < block.owned.size(); ++i) {
            const VertexKey& k = block.owned[i];
            const openvdb::Vec3d index(double(k[0]) / double(K) - 0.5,
                double(k[1]) / double(K) - 0.5, double(k[2]) / double(K) - 0.5);
            mesh.points[vertexOffset[n] + i] = xform.indexToWorld(index);
            mesh.pointKeys[vertexOffset[n] + i] = k;
        }
    });
    interrupt.throwIfStopped("extraction");
    return mesh;
}

} // namespace vdbi
