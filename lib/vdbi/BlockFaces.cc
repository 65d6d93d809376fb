// SPDX-License-Identifier: Apache-2.0

#include <vdbi/BlockFaces.h>

#include <algorithm>
#include <type_traits>

namespace vdbi {
namespace extraction {

namespace {

using openvdb::Coord;

/// @brief Open-addressing map from the keys of one block to their indices.
/// @details Keys inside the block (every component strictly between its min and max faces)
/// are numbered 0, 1, ... in order of first use, keys on its faces FACE_KEY + 0, 1, ..., so
/// that the block stores its inside keys first (BlockMesh::keys) without a renumbering table.
/// A slot holds its key tagged with the block's epoch in the 8 bits a key leaves free: slots of
/// earlier blocks count as empty, so starting a block clears nothing.
class KeyIndex
{
public:
    static constexpr std::uint32_t FACE_KEY = std::uint32_t(1) << 31;

    /// @param limit  the local key component of the block's max faces (8 * 2s)
    explicit KeyIndex(int limit)
        : mInsideMax(LocalKey(limit - 1))
    {
        resize(std::size_t(1) << 12);
        reset();   // epoch 1: the cleared slots (epoch 0) are empty from the start
    }

    /// Starts a block: forgets the keys of the previous one.
    void reset()
    {
        mInsideCount = mFaceCount = 0;
        if (++mEpoch == EPOCH_END) {
            // Tags of 255 blocks ago would look current again.
            std::fill(mSlots.begin(), mSlots.end(), Slot{0, 0});
            mEpoch = 1;
        }
        mTag = mEpoch << 24;
    }

    std::uint32_t insert(LocalKey k)
    {
        const LocalKey tag = k | mTag;
        std::size_t h = std::uint32_t(k * 0x9E3779B1u) >> mShift; // Fibonacci hashing
        while (mSlots[h].tag != tag) {
            if ((mSlots[h].tag ^ mTag) >> 24 != 0) return add(tag, h);
            h = (h + 1) & (mSlots.size() - 1);
        }
        return mSlots[h].index;
    }

    const LocalKey* insideKeys() const { return mInsideKeys.data(); }
    std::uint32_t insideCount() const { return mInsideCount; }
    const LocalKey* faceKeys() const { return mFaceKeys.data(); }
    std::uint32_t faceCount() const { return mFaceCount; }

private:
    struct Slot
    {
        LocalKey tag; ///< key | epoch << 24
        std::uint32_t index;
    };
    static constexpr LocalKey EPOCH_END = 256;

    /// Numbers new key tag @a tag, to go in empty slot @a h.
    std::uint32_t add(LocalKey tag, std::size_t h)
    {
        const LocalKey k = tag & 0xFFFFFFu;
        std::uint32_t index;
        if (isInside(k)) {
            index = mInsideCount;
            mInsideKeys[mInsideCount++] = k;
        } else {
            index = FACE_KEY + mFaceCount;
            mFaceKeys[mFaceCount++] = k;
        }
        mSlots[h] = Slot{tag, index};
        if (2 * std::size_t(mInsideCount + mFaceCount) > mSlots.size()) grow();
        return index;
    }

    bool isInside(LocalKey k) const
    {
        return (((k >> 16) - 1u < mInsideMax) & (((k >> 8) & 0xFFu) - 1u < mInsideMax)
            & ((k & 0xFFu) - 1u < mInsideMax)) != 0;
    }

    /// Makes the table @a slots long, and the key lists long enough for all the keys it
    /// holds before it grows again.
    void resize(std::size_t slots)
    {
        mSlots.assign(slots, Slot{0, 0});
        mShift = 32 - int(openvdb::util::FindLowestOn(std::uint32_t(slots)));
        mInsideKeys.resize(slots / 2 + 1);
        mFaceKeys.resize(slots / 2 + 1);
    }

    /// Out of line: rare, and it keeps add() small enough to inline.
    [[gnu::noinline]] void grow()
    {
        resize(mSlots.size() * 2);
        auto place = [this](LocalKey k, std::uint32_t index) {
            std::size_t h = std::uint32_t(k * 0x9E3779B1u) >> mShift;
            while (mSlots[h].tag >> 24 == mEpoch) h = (h + 1) & (mSlots.size() - 1);
            mSlots[h] = Slot{k | mTag, index};
        };
        for (std::uint32_t i = 0; i < mInsideCount; ++i) place(mInsideKeys[i], i);
        for (std::uint32_t i = 0; i < mFaceCount; ++i) place(mFaceKeys[i], FACE_KEY + i);
    }

    const LocalKey mInsideMax; ///< the largest component of a key inside the block, minus 1
    std::vector<Slot> mSlots;
    int mShift;
    LocalKey mEpoch = 0, mTag = 0;
    std::vector<LocalKey> mInsideKeys, mFaceKeys; ///< [0, count) are used
    std::uint32_t mInsideCount = 0, mFaceCount = 0;
};

/// The local key with components @a ka along axis @a a and kb, kc along the next two (cyclic).
LocalKey
keyOf(int a, int ka, int kb, int kc)
{
    return LocalKey(ka * KEY_UNIT[a] + kb * KEY_UNIT[(a + 1) % 3] + kc * KEY_UNIT[(a + 2) % 3]);
}

/// A fine face's labels (lower, upper) in one word, to compare pairs in one step.
std::uint64_t
packPair(Label lower, Label upper)
{
    return (std::uint64_t(std::uint32_t(lower)) << 32) | std::uint32_t(upper);
}
Label lowerOf(std::uint64_t pair) { return Label(std::uint32_t(pair >> 32)); }
Label upperOf(std::uint64_t pair) { return Label(std::uint32_t(pair)); }
bool isDegenerate(std::uint64_t pair) { return lowerOf(pair) == upperOf(pair); }

/// Bit k of the result: lower[k] != upper[k], for k < BLOCK_DIM.
/// @details Written so that GCC vectorizes it: ORing in `flag ? bit[k] : 0` becomes compares,
/// ands and an OR reduction, where `unsigned(flag) << k` needs a shift count per lane (not in
/// SSE2). Out of line on purpose: inlined into a loop over the axes, the comparisons are
/// unrolled before they can be vectorized, and scalar they cost three times as much.
[[gnu::noinline]] unsigned
differingVoxels(const Label* lower, const Label* upper)
{
    static constexpr unsigned BIT[BLOCK_DIM] = {1, 2, 4, 8, 16, 32, 64, 128};
    unsigned bits = 0;
    for (int k = 0; k < BLOCK_DIM; ++k) bits |= lower[k] != upper[k] ? BIT[k] : 0u;
    return bits;
}

/// Emits the faces owned by the voxels of one block (face (v, a) is owned by voxel v).
/// Probes use global coordinates, keys the block's local ones.
class FaceWalker
{
public:
    explicit FaceWalker(const RefinedLabels& labels)
        : mS(labels.subdivision)
        , mFine(labels.fine->tree())
        , mFacePairs(std::size_t(mS) * mS)
        , mIndex(BLOCK_DIM * 2 * mS)
    {
        std::fill(std::begin(mFineSlot), std::end(mFineSlot), -1);
    }

    void walk(const LabelWindow& w, const MaskWindow* mask, const openvdb::CoordBBox& owners,
              BlockMesh& out)
    {
        mOut = &out;
        mPatchPair = 0;
        mIndex.reset();
        mCornerCount = 0;
        mRuns.clear();
        forgetFineVoxels();
        const Coord& o = w.origin();
        const bool clipped = !owners.empty();
        for (int i = 0; i < BLOCK_DIM; ++i) {
            for (int j = 0; j < BLOCK_DIM; ++j) {
                // The voxels (i, j, 0 .. 7) and their lower neighbours lie in these rows.
                const int rows[3] = {LabelWindow::index(i + 1, j + 1, 0),
                    LabelWindow::index(i, j + 1, 0), LabelWindow::index(i + 1, j, 0)};
                if (!mask || !mask->anyOnNear(i + 1, j + 1)) {
                    coarseRow(w, i, j, owners);
                    continue;
                }
                if (w.isUniform(rows, 3) && !mask->anyOn(rows, 3)) continue;
                for (int k = 0; k < BLOCK_DIM; ++k) {
                    const Coord v = o.offsetBy(i, j, k);
                    if (clipped && !owners.isInside(v)) continue;
                    const Coord local(i, j, k);
                    const int flat = LabelWindow::index(i + 1, j + 1, k + 1);
                    const Label upper = w.data()[flat];
                    const bool upperSub = mask && mask->at(flat);
                    const FineVoxel upperFine = upperSub ? fineVoxel(v, flat, upper)
                                                         : FineVoxel{upper, nullptr};
                    if (upperFine.labels) interiorFaces(local, upperFine.labels);
                    for (int a = 0; a < 3; ++a) {
                        const int lowerFlat = flat - LabelWindow::STRIDE[a];
                        const Label lower = w.data()[lowerFlat];
                        const bool lowerSub = mask && mask->at(lowerFlat);
                        if (upperSub || lowerSub) {
                            Coord u = v;
                            u[a] -= 1;
                            splitFace(local, a, lowerSub ? fineVoxel(u, lowerFlat, lower)
                                                         : FineVoxel{lower, nullptr}, upperFine);
                        } else if (lower != upper) {
                            coarseFace(local, a, lower, upper, flat, mask);
                        }
                    }
                }
            }
        }
        // Exact sizes: the blocks keep these until the end of the extraction.
        storeKeysInsideFirst(out);
        closeRun();
        out.runs.assign(mRuns.begin(), mRuns.end());
        for (const PatchRun& run : mRuns) out.patchCounts[run.patch] += run.count;
    }

private:
    /// The faces owned by the voxels (i, j, 0 .. 7) of the block when no subdivided voxel
    /// touches them: coarse faces, found for the whole row at once (differingVoxels(); most
    /// voxels of a row own no face).
    void coarseRow(const LabelWindow& w, int i, int j, const openvdb::CoordBBox& owners)
    {
        const int first = LabelWindow::index(i + 1, j + 1, 1);
        const Label* upper = w.data() + first;
        unsigned faces[3]; // bit k: voxel k owns a face along the axis
        for (int a = 0; a < 3; ++a) {
            faces[a] = differingVoxels(upper - LabelWindow::STRIDE[a], upper);
        }
        for (unsigned any = faces[0] | faces[1] | faces[2]; any != 0; any &= any - 1) {
            const int k = int(openvdb::util::FindLowestOn(any));
            if (!owners.empty() && !owners.isInside(w.origin().offsetBy(i, j, k))) continue;
            for (int a = 0; a < 3; ++a) {
                if (!((faces[a] >> k) & 1u)) continue;
                coarseFace(Coord(i, j, k), a, upper[k - LabelWindow::STRIDE[a]], upper[k],
                           first + k, nullptr);
            }
        }
    }

    /// Stores the keys in @a out, those inside the block first, and the corners with the
    /// face keys' indices moved after the inside ones.
    void storeKeysInsideFirst(BlockMesh& out)
    {
        const LocalKey* inside = mIndex.insideKeys();
        const LocalKey* face = mIndex.faceKeys();
        out.insideCount = mIndex.insideCount();
        out.keys.reserve(mIndex.insideCount() + mIndex.faceCount());
        out.keys.assign(inside, inside + mIndex.insideCount());
        out.keys.insert(out.keys.end(), face, face + mIndex.faceCount());
        // FACE_KEY + i becomes insideCount + i.
        const std::uint32_t shift = KeyIndex::FACE_KEY - out.insideCount;
        auto renumber = [&](auto& corners) {
            using Index = typename std::decay_t<decltype(corners)>::value_type;
            corners.resize(mCornerCount);
            for (std::size_t c = 0; c < mCornerCount; ++c) {
                corners[c] = Index(mCorners[c] - (mCorners[c] >> 31) * shift);
            }
        };
        if (out.keys.size() <= (std::size_t(1) << 16)) {
            renumber(out.corners16);
        } else {
            renumber(out.corners32);
        }
    }

    /// Makes (lower, upper) the patch of the next triangles; +axis points lower -> upper.
    void setPatch(Label lower, Label upper)
    {
        // Most faces continue the patch and orientation of the face before.
        const std::uint64_t pair = packPair(lower, upper);
        if (pair == mPatchPair) return;
        mPatchPair = pair;
        startPatch(lower, upper);
    }

    /// setPatch() for another pair than the last one (out of line: it is rarely needed).
    [[gnu::noinline]] void startPatch(Label lower, Label upper)
    {
        // Patch (a, b) with a < b has its normal from a into b.
        mUp = lower < upper;
        const LabelPair pair = mUp ? LabelPair{lower, upper} : LabelPair{upper, lower};
        // Element by element: std::array's == calls memcmp.
        auto isPair = [&pair](const LabelPair& p) { return p[0] == pair[0] && p[1] == pair[1]; };
        if (!mRuns.empty() && isPair(mOut->patches[mRuns.back().patch])) return;
        const auto it = std::find_if(mOut->patches.begin(), mOut->patches.end(), isPair);
        const auto patch = std::uint32_t(it - mOut->patches.begin());
        if (it == mOut->patches.end()) {
            mOut->patches.push_back(pair);
            mOut->patchCounts.push_back(0);
        }
        closeRun();
        mRuns.push_back(PatchRun{patch, 0});
        mRunFirstCorner = mCornerCount;
    }

    /// Sets the triangle count of the last run, if any: runs are counted when they end, not
    /// triangle by triangle.
    void closeRun()
    {
        if (!mRuns.empty()) {
            mRuns.back().count = std::uint32_t((mCornerCount - mRunFirstCorner) / 3);
        }
    }

    /// Makes room for @a n more triangles, so that triangle() needs no check.
    void reserveTriangles(std::size_t n)
    {
        if (mCornerCount + 3 * n > mCorners.size()) {
            mCorners.resize(std::max(2 * mCorners.size(), mCornerCount + 3 * n));
        }
    }

    /// Appends a triangle given counter-clockwise seen from +axis, by key indices (room
    /// made by reserveTriangles()).
    void triangle(std::uint32_t p, std::uint32_t q, std::uint32_t r)
    {
        std::uint32_t* c = mCorners.data() + mCornerCount;
        c[0] = p;
        c[1] = mUp ? q : r;
        c[2] = mUp ? r : q;
        mCornerCount += 3;
    }

    /// Two triangles of a quad given counter-clockwise seen from +axis.
    void quad(LocalKey c0, LocalKey c1, LocalKey c2, LocalKey c3)
    {
        const std::uint32_t i0 = mIndex.insert(c0), i2 = mIndex.insert(c2);
        reserveTriangles(2);
        triangle(i0, mIndex.insert(c1), i2);
        triangle(i0, i2, mIndex.insert(c3));
    }

    /// A fan from @a centre around the boundary that starts at @a start and takes pieces[side]
    /// steps of step[side] along each of its four sides (counter-clockwise seen from +axis).
    void fan(LocalKey centre, LocalKey start, const int (&pieces)[4],
             const std::int32_t (&step)[4])
    {
        const std::uint32_t c = mIndex.insert(centre);
        reserveTriangles(std::size_t(pieces[0] + pieces[1] + pieces[2] + pieces[3]));
        LocalKey p = start;
        std::uint32_t ip = mIndex.insert(p);
        for (int side = 0; side < 4; ++side) {
            for (int n = 0; n < pieces[side]; ++n) {
                p = LocalKey(std::int32_t(p) + step[side]);
                const std::uint32_t iq = mIndex.insert(p);
                triangle(c, ip, iq);
                ip = iq;
            }
        }
    }

    /// A coarse face between two voxels that are not subdivided.
    void coarseFace(const Coord& local, int a, Label lower, Label upper, int flat,
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
        const int K = 2 * mS; // key units per coarse voxel
        const LocalKey corner = keyOf(a, K * local[a], K * local[b], K * local[c]);
        const std::int32_t ub = KEY_UNIT[b], uc = KEY_UNIT[c];
        setPatch(lower, upper);
        if (split[0] || split[1] || split[2] || split[3]) {
            // The paper's rule: a fan from the face centre to all boundary points, s + 1
            // of them along each split side.
            int pieces[4];
            std::int32_t step[4];
            const std::int32_t dir[4] = {2 * ub, 2 * uc, -2 * ub, -2 * uc};
            for (int side = 0; side < 4; ++side) {
                pieces[side] = split[side] ? mS : 1;
                step[side] = dir[side] * (split[side] ? 1 : mS);
            }
            fan(corner + LocalKey(mS * (ub + uc)), corner, pieces, step);
            return;
        }
        quad(corner, corner + LocalKey(K * ub), corner + LocalKey(K * (ub + uc)),
             corner + LocalKey(K * uc));
    }

    /// The fine labels of one side of a face: @a labels (s^3, see fineVoxel()), or null when
    /// all of them are @a label.
    struct FineVoxel
    {
        Label label;
        const Label* labels;
    };

    /// The fine labels of subdivided coarse voxel @a v at window index @a flat, labelled
    /// @a coarse, at ((x * s) + y) * s + z; read once per block from the leaf buffers. Labels
    /// are null where all s^3 are equal (about half of the subdivided voxels on real data):
    /// such a voxel has no inner face, and its faces are those of a coarse voxel, split.
    FineVoxel fineVoxel(const Coord& v, int flat, Label coarse)
    {
        if (mFineSlot[flat] < 0) {
            mFineSlot[flat] = int(mFineFlats.size());
            mFineFlats.push_back(flat);
            if (mFineStore.size() < mFineFlats.size()) {
                mFineStore.emplace_back(new Label[std::size_t(mS) * mS * mS]);
            }
            Label* labels = mFineStore[std::size_t(mFineSlot[flat])].get();
            mFineUniform[flat] = readFineVoxel(v, coarse, labels);
        }
        const Label* labels = mFineStore[std::size_t(mFineSlot[flat])].get();
        return mFineUniform[flat] ? FineVoxel{labels[0], nullptr} : FineVoxel{coarse, labels};
    }

    /// Starts a block: the window voxels change, the buffers are kept.
    void forgetFineVoxels()
    {
        for (const int flat : mFineFlats) mFineSlot[flat] = -1;
        mFineFlats.clear();
    }

    /// Fills @a out as fineVoxel() describes, leaf by leaf: a fine voxel that is not active
    /// keeps the coarse label. Returns whether all s^3 labels are equal.
    bool readFineVoxel(const Coord& v, Label coarse, Label* out)
    {
        using LeafT = openvdb::Int32Tree::LeafNodeType;
        const int s = mS;
        const Coord lo(s * v.x(), s * v.y(), s * v.z());
        // Per axis, where [lo, lo + s) crosses into the next leaf (at most 3 pieces, s <= 15).
        int cut[3][4], pieces[3];
        for (int a = 0; a < 3; ++a) {
            pieces[a] = 0;
            cut[a][0] = 0;
            for (int t = 0; t < s; ) {
                t = std::min(s, t + int(LeafT::DIM) - ((lo[a] + t) & int(LeafT::DIM - 1)));
                cut[a][++pieces[a]] = t;
            }
        }
        // Most fine voxels are not active: fill with the coarse label, then copy the others.
        std::fill_n(out, s * s * s, coarse);
        bool changed = false;
        for (int px = 0; px < pieces[0]; ++px) {
            for (int py = 0; py < pieces[1]; ++py) {
                for (int pz = 0; pz < pieces[2]; ++pz) {
                    const Coord first = lo.offsetBy(cut[0][px], cut[1][py], cut[2][pz]);
                    const LeafT* leaf = mFine.probeConstLeaf(first);
                    if (!leaf) {
                        if (!mFine.isValueOn(first)) continue;
                        const Label tile = mFine.getValue(first);
                        changed = changed || tile != coarse;
                        for (int x = cut[0][px]; x < cut[0][px + 1]; ++x) {
                            for (int y = cut[1][py]; y < cut[1][py + 1]; ++y) {
                                Label* dst = out + (x * s + y) * s;
                                std::fill(dst + cut[2][pz], dst + cut[2][pz + 1], tile);
                            }
                        }
                        continue;
                    }
                    // A slice across x of a leaf is one word of its value mask, and a row
                    // along z in it one byte: visit only the active voxels of a row, and
                    // skip slices without any.
                    const int z0 = cut[2][pz], zn = cut[2][pz + 1] - z0;
                    const int leafZ0 = (lo.z() + z0) & int(LeafT::DIM - 1);
                    const unsigned rowBits = (1u << zn) - 1u;
                    const Label* values = leaf->buffer().data();
                    for (int x = cut[0][px]; x < cut[0][px + 1]; ++x) {
                        const int leafX = (lo.x() + x) & int(LeafT::DIM - 1);
                        const std::uint64_t slice =
                            leaf->getValueMask().template getWord<std::uint64_t>(leafX);
                        if (slice == 0) continue;
                        for (int y = cut[1][py]; y < cut[1][py + 1]; ++y) {
                            const int row = leafX * int(LeafT::DIM)
                                + ((lo.y() + y) & int(LeafT::DIM - 1));
                            unsigned bits =
                                unsigned(slice >> (8 * (row & 7) + leafZ0)) & rowBits;
                            Label* dst = out + (x * s + y) * s + z0;
                            const Label* src = values + 8 * row + leafZ0;
                            for (; bits; bits &= bits - 1) {
                                const int t = int(openvdb::util::FindLowestOn(bits));
                                dst[t] = src[t];
                                changed = changed || src[t] != coarse;
                            }
                        }
                    }
                }
            }
        }
        return !changed || std::all_of(out + 1, out + s * s * s,
                                       [out](Label l) { return l == out[0]; });
    }

    /// A coarse face next to a subdivided voxel: its s x s fine faces, each on its own.
    void splitFace(const Coord& local, int a, const FineVoxel& lower, const FineVoxel& upper)
    {
        const Coord corner(mS * local.x(), mS * local.y(), mS * local.z());
        if (!lower.labels && !upper.labels) {
            // Both sides uniform: one pair over the whole grid (what fineFaceGrid() would
            // make of it).
            if (lower.label != upper.label) {
                rectangle(corner, a, 0, 0, mS, mS, packPair(lower.label, upper.label));
            }
            return;
        }
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const int s = mS;
        const int stride[3] = {s * s, s, 1};
        const int lowerPlane = (s - 1) * stride[a]; // the lower voxel's fine voxels at the face
        auto lowerAt = [&](int idx) { return lower.labels ? lower.labels[lowerPlane + idx]
                                                          : lower.label; };
        auto upperAt = [&](int idx) { return upper.labels ? upper.labels[idx] : upper.label; };
        if (!anyFace(stride[b], stride[c], lowerAt, upperAt)) return;
        for (int jb = 0; jb < s; ++jb) {
            for (int jc = 0; jc < s; ++jc) {
                const int idx = jb * stride[b] + jc * stride[c];
                mFacePairs[jb * s + jc] = packPair(lowerAt(idx), upperAt(idx));
            }
        }
        fineFaceGrid(corner, a);
    }

    /// Whether the fine labels lowerAt(idx) and upperAt(idx) differ anywhere on an s x s grid
    /// of indices idx = jb * strideB + jc * strideC: most grids hold no face, and this is
    /// cheaper to learn than their label pairs.
    template<typename LowerAt, typename UpperAt>
    bool anyFace(int strideB, int strideC, const LowerAt& lowerAt, const UpperAt& upperAt) const
    {
        for (int jb = 0; jb < mS; ++jb) {
            for (int jc = 0; jc < mS; ++jc) {
                const int idx = jb * strideB + jc * strideC;
                if (lowerAt(idx) != upperAt(idx)) return true;
            }
        }
        return false;
    }

    /// Emits the s x s fine faces at local fine point @a corner with normal @a a, whose label
    /// pairs (packPair(lower, upper)) are in mFacePairs (index jb * s + jc along the next two
    /// axes).
    /// @details Faces with the same pair are merged greedily into rectangles, each a fan
    /// from its centre to all fine points on its boundary: the same surface in fewer
    /// triangles. No other face can use a point inside such a rectangle (it would need two
    /// different labels on one side of it), so this adds no T-junction.
    void fineFaceGrid(const Coord& corner, int a)
    {
        const int s = mS;
        const std::uint64_t* pairs = mFacePairs.data();
        if (std::all_of(pairs + 1, pairs + s * s, [&](std::uint64_t p) { return p == pairs[0]; })) {
            // One pair over the whole grid: the greedy merge makes it one rectangle.
            rectangle(corner, a, 0, 0, s, s, pairs[0]);
            return;
        }
        // Rows as bit masks over jc (s <= 15): cells still to place, and per rectangle the
        // cells of its pair, so that placed and empty cells cost nothing to skip.
        std::uint32_t open[MAX_SUBDIVISION];
        for (int jb = 0; jb < s; ++jb) {
            open[jb] = 0;
            for (int jc = 0; jc < s; ++jc) {
                open[jb] |= std::uint32_t(!isDegenerate(pairs[jb * s + jc])) << jc;
            }
        }
        auto openWith = [&](int jb, std::uint64_t pair) {
            std::uint32_t same = 0;
            for (int jc = 0; jc < s; ++jc) same |= std::uint32_t(pairs[jb * s + jc] == pair) << jc;
            return same & open[jb];
        };
        for (int jb = 0; jb < s; ++jb) {
            while (open[jb] != 0) {
                const int jc = int(openvdb::util::FindLowestOn(open[jb]));
                const std::uint64_t pair = pairs[jb * s + jc];
                // The run of open cells of this pair from jc on, then the rows below that
                // have all of it open.
                const int w = int(openvdb::util::FindLowestOn(~(openWith(jb, pair) >> jc)));
                const std::uint32_t run = ((std::uint32_t(1) << w) - 1) << jc;
                int h = 1;
                while (jb + h < s && (openWith(jb + h, pair) & run) == run) ++h;
                for (int x = jb; x < jb + h; ++x) open[x] &= ~run;
                rectangle(corner, a, jb, jc, h, w, pair);
            }
        }
    }

    /// Fine faces [jb, jb + h) x [jc, jc + w) of the grid at @a corner as one polygon.
    void rectangle(const Coord& corner, int a, int jb, int jc, int h, int w, std::uint64_t pair)
    {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const std::int32_t ub = KEY_UNIT[b], uc = KEY_UNIT[c];
        const LocalKey base = keyOf(a, 2 * corner[a], 2 * (corner[b] + jb),
                                    2 * (corner[c] + jc));
        setPatch(lowerOf(pair), upperOf(pair));
        if (w * h <= w + h) { // a fan would not be smaller than the quads
            for (int x = 0; x < h; ++x) {
                for (int y = 0; y < w; ++y) {
                    const LocalKey q = base + LocalKey(2 * x * ub + 2 * y * uc);
                    quad(q, q + LocalKey(2 * ub), q + LocalKey(2 * (ub + uc)),
                         q + LocalKey(2 * uc));
                }
            }
            return;
        }
        const int pieces[4] = {h, w, h, w};
        const std::int32_t step[4] = {2 * ub, 2 * uc, -2 * ub, -2 * uc};
        fan(base + LocalKey(h * ub + w * uc), base, pieces, step);
    }

    /// Fine faces inside a subdivided voxel at @a local between its own fine labels @a fine
    /// (see fineVoxel()).
    void interiorFaces(const Coord& local, const Label* fine)
    {
        const int s = mS;
        const int stride[3] = {s * s, s, 1};
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            // Planes t = 1 .. s-1 inside the voxel; t = 0 is the voxel's face: splitFace().
            for (int t = 1; t < s; ++t) {
                const Label* upper = fine + t * stride[a];
                const Label* lower = upper - stride[a];
                auto lowerAt = [lower](int idx) { return lower[idx]; };
                auto upperAt = [upper](int idx) { return upper[idx]; };
                if (!anyFace(stride[b], stride[c], lowerAt, upperAt)) continue;
                for (int jb = 0; jb < s; ++jb) {
                    for (int jc = 0; jc < s; ++jc) {
                        const int idx = jb * stride[b] + jc * stride[c];
                        mFacePairs[jb * s + jc] = packPair(lower[idx], upper[idx]);
                    }
                }
                Coord corner(s * local.x(), s * local.y(), s * local.z());
                corner[a] += t;
                fineFaceGrid(corner, a);
            }
        }
    }

    const int mS;
    openvdb::tree::ValueAccessor<const openvdb::Int32Tree, false> mFine;
    /// Per window voxel: index of its fine labels in mFineStore, or -1 (not read yet).
    int mFineSlot[LabelWindow::DIM * LabelWindow::DIM * LabelWindow::DIM];
    /// Per window voxel whose mFineSlot is set: whether its fine labels are all equal.
    bool mFineUniform[LabelWindow::DIM * LabelWindow::DIM * LabelWindow::DIM];
    std::vector<int> mFineFlats; ///< the window voxels whose mFineSlot is set
    /// Buffers of s^3 fine labels; they never move, so fineVoxel()'s pointers stay valid.
    std::vector<std::unique_ptr<Label[]>> mFineStore;
    std::vector<std::uint64_t> mFacePairs;
    KeyIndex mIndex;
    /// The block's corners and patch indices, grown here (reused from block to block) and
    /// copied to its BlockMesh at the end.
    std::vector<std::uint32_t> mCorners; ///< [0, mCornerCount) are used
    std::size_t mCornerCount = 0;
    std::vector<PatchRun> mRuns;
    BlockMesh* mOut = nullptr;
    bool mUp = true;
    /// packPair(lower, upper) of the last setPatch(), or 0 (equal labels: no face) when the
    /// block has no patch yet.
    std::uint64_t mPatchPair = 0;
    std::size_t mRunFirstCorner = 0; ///< mCornerCount when the last run began
};

} // namespace

class BlockFaceWalker::Impl : public FaceWalker
{
public:
    using FaceWalker::FaceWalker;
};

BlockFaceWalker::BlockFaceWalker(const RefinedLabels& labels)
    : mImpl(std::make_unique<Impl>(labels))
{}

BlockFaceWalker::~BlockFaceWalker() = default;

void
BlockFaceWalker::walk(const LabelWindow& w, const MaskWindow* mask,
                      const openvdb::CoordBBox& owners, BlockMesh& out)
{
    mImpl->walk(w, mask, owners, out);
}

} // namespace extraction
} // namespace vdbi
