// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/InterfaceMesh.h
/// @brief The flat result: points, triangles and the label pair of every triangle, grouped
/// into patches. Needs no mesh library (writers, the Houdini SOP).

#ifndef VDBI_INTERFACE_MESH_HAS_BEEN_INCLUDED
#define VDBI_INTERFACE_MESH_HAS_BEEN_INCLUDED

#include <vdbi/Types.h>

#include <openvdb/Types.h>

#include <array>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdbi {

/// Exact integer position of a vertex on the key grid, 2s points per coarse voxel: coarse
/// grid point v is 2s*v, fine grid point p is 2p, the centre of a coarse face is its corner
/// plus s along the two face axes. Equal keys are the same vertex, across patches and tiles.
using VertexKey = std::array<std::int64_t, 3>;

/// @brief std::allocator, except that resize(n) and vector(n) leave the new elements of a
/// trivial type uninitialized (default- instead of value-initialized).
/// @details The extraction sizes its output arrays (hundreds of MB on big volumes) and then
/// fills them in parallel: without zeroing first, their pages are first touched by the
/// threads that write them, not zeroed by one thread beforehand.
template<typename T>
struct DefaultInitAllocator : std::allocator<T>
{
    template<typename U>
    struct rebind { using other = DefaultInitAllocator<U>; };

    DefaultInitAllocator() = default;
    template<typename U>
    DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}

    template<typename U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value)
    {
        ::new (static_cast<void*>(p)) U;
    }
    template<typename U, typename... Args>
    void construct(U* p, Args&&... args)
    {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

/// Points of an InterfaceMesh: resize() leaves new points uninitialized.
using PointArray = std::vector<openvdb::Vec3d, DefaultInitAllocator<openvdb::Vec3d>>;
/// Triangles of an InterfaceMesh: resize() leaves new triangles uninitialized.
using TriangleArray = std::vector<openvdb::Vec3I, DefaultInitAllocator<openvdb::Vec3I>>;

/// The triangles [firstTriangle, firstTriangle + triangleCount) between labels a < b.
struct InterfacePatch
{
    Label a = 0, b = 0;
    std::size_t firstTriangle = 0;
    std::size_t triangleCount = 0;
};

/// @brief Interface triangles between every pair of adjacent labels.
/// @details Every triangle of patch (a, b) is oriented with its normal pointing from label a
/// into label b (counter-clockwise seen from b). Patches are sorted by (a, b); their triangles
/// are contiguous. Points are shared between patches along common boundary curves.
struct InterfaceMesh
{
    PointArray points;                            ///< world space
    TriangleArray triangles;                      ///< indices into points
    std::vector<InterfacePatch> patches;          ///< sorted by (a, b)
    /// Exact key of every point; empty unless asked for (ExtractionOptions::pointKeys) and
    /// after remeshing moved points off the key grid.
    std::vector<VertexKey> pointKeys;
    int keyScale = 0;                             ///< key units per coarse voxel (2s)

    std::size_t triangleCount() const { return triangles.size(); }
    std::size_t pointCount() const { return points.size(); }
    /// The label pair (a, b) of every triangle, in triangle order.
    std::vector<std::array<Label, 2>> triangleLabels() const;
};

/// Triangles per patch of @a mesh.
std::vector<std::size_t> patchSizes(const InterfaceMesh& mesh);

/// The index of the patch of every triangle of @a mesh.
std::vector<std::uint32_t> trianglePatches(const InterfaceMesh& mesh);

/// @brief The triangles around every point of @a mesh: around[first[v] .. first[v + 1]),
/// ascending; those flagged in @a skip (one flag per triangle), if given, left out.
void trianglesAroundPoints(const InterfaceMesh& mesh, std::vector<std::uint32_t>& first,
                           std::vector<std::uint32_t>& around,
                           const std::vector<char>* skip = nullptr);

/// @brief The triangle across edge (@a u, @a v) of triangle @a f if the edge is inner to f's
/// patch: the only other triangle with that edge, of the same patch (@a patchOf, from
/// trianglePatches()), running along it the other way. -1 for a feature curve segment (in
/// several patches) or a patch boundary. @a first and @a around: trianglesAroundPoints().
std::int64_t triangleAcross(const InterfaceMesh& mesh, const std::vector<std::uint32_t>& first,
                            const std::vector<std::uint32_t>& around,
                            const std::vector<std::uint32_t>& patchOf, std::uint32_t f,
                            std::uint32_t u, std::uint32_t v);

} // namespace vdbi

#endif // VDBI_INTERFACE_MESH_HAS_BEEN_INCLUDED
