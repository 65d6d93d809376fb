// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/BlockFaces.h
/// @brief The first stage of the extraction: the interface faces owned by the voxels of one
/// block, triangulated on block-local vertex keys; extractInterfacePatches() then numbers the
/// keys of all blocks globally and assembles the patches.

#ifndef VDBI_BLOCK_FACES_HAS_BEEN_INCLUDED
#define VDBI_BLOCK_FACES_HAS_BEEN_INCLUDED

#include <vdbi/InterfaceMesh.h> // for DefaultInitAllocator
#include <vdbi/LabelWindow.h>
#include <vdbi/RefinedLabels.h>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace vdbi {
namespace extraction {

using LabelPair = std::array<Label, 2>;

/// A vertex key relative to the block that emits it: the key minus 2s * (block origin). Its
/// components lie in [0, 8 * 2s] (at most 112 for s = 7), packed 8 bits each as
/// x << 16 | y << 8 | z, so the keys of one block compare and sort like their global keys.
using LocalKey = std::uint32_t;

/// The largest subdivision whose local keys fit in 8 bits per axis (8 * 2s <= 255).
constexpr int MAX_SUBDIVISION = 15;

/// What one key unit along x, y, z adds to a LocalKey.
constexpr std::int32_t KEY_UNIT[3] = {1 << 16, 1 << 8, 1};

/// Component @a axis of @a k.
inline int
keyComponent(LocalKey k, int axis)
{
    return int((k >> (16 - 8 * axis)) & 0xFFu);
}

/// A vector whose resize() leaves new elements uninitialized: for the arrays of a block that
/// are sized and then written in full, where zeroing them first is wasted work.
template<typename T>
using UninitializedVector = std::vector<T, DefaultInitAllocator<T>>;

/// Consecutive triangles of a block in one patch.
struct PatchRun
{
    std::uint32_t patch; ///< index into BlockMesh::patches
    std::uint32_t count;
};

/// Triangles of one block, before vertices are numbered globally.
struct BlockMesh
{
    /// Distinct corner keys: first those inside the block, which no other block emits, then
    /// those on its faces; each part in order of first use.
    std::vector<LocalKey> keys;
    /// How many keys are inside: the block numbers them 0, 1, ... in this order.
    std::uint32_t insideCount = 0;
    /// 3 per triangle: indices into keys, in 16 bits when there are at most 2^16 keys (nearly
    /// every block: half the memory), else in 32; the other vector is empty.
    UninitializedVector<std::uint16_t> corners16;
    UninitializedVector<std::uint32_t> corners32;
    std::vector<LabelPair> patches;         ///< distinct label pairs, in order of first use
    std::vector<PatchRun> runs;             ///< the triangles in order, patch by patch
    std::vector<std::size_t> patchCounts;   ///< triangles per entry of patches
    /// A key on the block's max faces is numbered by the neighbour at origin + 8d, where bit a
    /// of d says the key is on the max face along a; the others (d = 0) by the block itself.
    /// byOwner[d] holds the indices into keys of the face keys numbered by the block at
    /// origin + 8d, byOwner[0] those on its min faces only.
    std::array<std::vector<std::uint32_t>, 8> byOwner;
    /// Per face key (index into keys minus insideCount): its number at its owner (set by the
    /// owner).
    UninitializedVector<std::uint32_t> rank;
    /// The face keys this block numbers, after its inside keys: those on its min faces (its
    /// own and its neighbours'), sorted.
    std::vector<LocalKey> faceKeys;

    std::size_t triangleCount() const { return (corners16.size() + corners32.size()) / 3; }
    /// How many vertices the block numbers.
    std::size_t ownedCount() const { return insideCount + faceKeys.size(); }
};

/// @brief Emits the faces owned by the voxels of one block after another (face (v, a) is
/// owned by voxel v) into BlockMesh keys, corners, patches, patch counts and runs (ALGORITHM.md
/// §4): coarse faces as two triangles or, with a split edge, a fan from their centre; faces
/// next to a subdivided voxel as their fine faces, merged into rectangles per label pair.
/// @details Keeps its buffers from block to block; one per thread.
class BlockFaceWalker
{
public:
    explicit BlockFaceWalker(const RefinedLabels& labels);
    ~BlockFaceWalker();
    BlockFaceWalker(const BlockFaceWalker&) = delete;
    BlockFaceWalker& operator=(const BlockFaceWalker&) = delete;

    /// The faces of the block of window @a w (subdivided voxels in @a mask, null if none near)
    /// whose owner lies in @a owners (all when empty), into @a out.
    void walk(const LabelWindow& w, const MaskWindow* mask, const openvdb::CoordBBox& owners,
              BlockMesh& out);

private:
    class Impl;
    std::unique_ptr<Impl> mImpl;
};

} // namespace extraction
} // namespace vdbi

#endif // VDBI_BLOCK_FACES_HAS_BEEN_INCLUDED
