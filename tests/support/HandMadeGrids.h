// SPDX-License-Identifier: Apache-2.0
/// @file support/HandMadeGrids.h
/// @brief Small label grids (background 0) whose critical elements and interface faces can be
/// counted by hand. The numbers below are asserted by the tests, against the independent
/// reference (ReferenceFattening.h) and against the library.
/// @details Conventions (ALGORITHM.md §1-§2): voxel c is the cube [c, c+1]; an edge is a grid
/// point plus an axis; the 2x2x2 block of grid point v is the voxels v-1..v. The background 0
/// is a label. "Critical edges/vertices" count distinct elements (each element once, with its
/// dominant label, the smallest label for which it is critical). "Singular" vertices are those
/// critical by the antipodal rule (§2 rule 2) for some label. Interface faces are coarse faces
/// whose two voxels differ, listed per label pair (a < b).
///
/// | grid                   | crit. edges | crit. vertices | singular | faces per pair          |
/// |------------------------|-------------|----------------|----------|-------------------------|
/// | singleVoxel            | 0           | 0              | 0        | (0,1): 6                |
/// | twoVoxelsSharingEdge   | 1 (dom. 0)  | 2 (dom. 0)     | 0        | (0,1): 12               |
/// | twoVoxelsSharingVertex | 0           | 1 (dom. 0)     | 1        | (0,1): 12               |
/// | antipodalPair2x2x2     | 0           | 1 (dom. 0)     | 1        | (0,1): 12               |
/// | antipodalSix           | 0           | 1 (dom. 0)     | 1        | (0,1): 24               |
/// | checkerboard2x2        | 1 (dom. 1)  | 2 (dom. 1)     | 0        | (0,1) 8, (0,2) 8, (1,2) 4 |
/// | hollowShell            | 0           | 0              | 0        | (0,1): 150 + 54 = 204   |
/// | hollowShellFilled      | 0           | 0              | 0        | (0,1): 150, (1,2): 54   |
/// | torusRing              | 0           | 0              | 0        | (0,1): 32               |
/// | tJunction3             | 0           | 0              | 0        | see below (30 faces)    |
/// | corner4                | 0           | 0              | 0        | see below (32 faces)    |
/// | activeTileGrid         | 1 (dom. 0)  | 2 (dom. 0)     | 0        | (0,3) 384, (0,5) 6      |
///
/// Each builder's comment derives its row.

#pragma once

#include <vdbi/Types.h>

#include <openvdb/openvdb.h>

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace vdbi_test {

/// @brief A grid with background 0 from a dense array of labels.
/// @param labels  nx*ny*nz labels, x fastest (index x + nx*(y + ny*z)); voxel (x,y,z) of the
///                array is grid voxel origin + (x,y,z). Labels equal to @a background are not
///                stored; all others become active voxels.
/// @throw openvdb::ValueError if labels.size() != nx*ny*nz
openvdb::Int32Grid::Ptr gridFromDense(int nx, int ny, int nz,
                                      const std::vector<vdbi::Label>& labels,
                                      const openvdb::Coord& origin = openvdb::Coord(0),
                                      vdbi::Label background = 0);

/// @brief One voxel of label 1 at the origin.
/// @details No edge has two diagonal voxels of one label and no block holds two antipodal
/// voxels of one label (each block has one 1 and seven 0s): nothing critical. 6 faces (0,1);
/// the extracted surface is a cube: 12 triangles, 8 vertices, Euler characteristic 2.
openvdb::Int32Grid::Ptr singleVoxel();

/// @brief Voxels (0,0,0) and (1,1,0) of label 1: they share the z-edge at grid point (1,1,0).
/// @details Around that edge the cyclic order is 1,0,1,0: critical for 1 and for 0, dominant
/// 0. Its end points (1,1,0) and (1,1,1) are critical (rule 1), dominant 0. No antipodal pair
/// (the two voxels differ in x and y only). Faces (0,1): 2 x 6 = 12.
openvdb::Int32Grid::Ptr twoVoxelsSharingEdge();

/// @brief Voxels (0,0,0) and (1,1,1) of label 1: they share only grid point (1,1,1).
/// @details The block of (1,1,1) holds two antipodal 1s and six 0s: critical for 1 (two
/// antipodal) and for 0 (six with two antipodal others), dominant 0, singular. No edge has
/// two diagonal 1s or two diagonal 0s (each of the 6 edges at (1,1,1) sees one 1 and three
/// 0s). Faces (0,1): 12.
openvdb::Int32Grid::Ptr twoVoxelsSharingVertex();

/// @brief Two antipodal voxels (1,0,0) and (0,1,1) of label 1 in the 2x2x2 block [0,1]^3,
/// the other six background. Same counts as twoVoxelsSharingVertex on the other diagonal.
openvdb::Int32Grid::Ptr antipodalPair2x2x2();

/// @brief The 2x2x2 block [0,1]^3 of label 1 except the antipodal voxels (0,0,0), (1,1,1).
/// @details Grid point (1,1,1): six 1s with two antipodal 0s (critical for 1) and two
/// antipodal 0s (critical for 0): dominant 0, singular. The 6 edges at (1,1,1) each see one 0
/// and three 1s; edges on the block's outer faces see two adjacent background voxels, so no
/// diagonal pair there: no critical edge. Faces (0,1): 6 voxels x 6 faces - 2 x 6 internal
/// adjacencies (12 block adjacencies minus the 3 + 3 of the two holes) = 24.
openvdb::Int32Grid::Ptr antipodalSix();

/// @brief The 2x2x1 layer (0,0,0)=1, (1,0,0)=2, (0,1,0)=2, (1,1,0)=1.
/// @details The z-edge at (1,1,0) is 1,2,1,2 around: critical for 1 and 2, dominant 1; its
/// end points (1,1,0), (1,1,1) are critical, dominant 1 (no edge at them is critical for 0:
/// the background voxels there are adjacent, never diagonal). Faces (0,1): 2 x 4 = 8,
/// (0,2): 8, (1,2): 4.
openvdb::Int32Grid::Ptr checkerboard2x2();

/// @brief The 5x5x5 cube [0,4]^3 of label 1 with the 3x3x3 hole [1,3]^3 of background 0.
/// @details Both sets are boxes or box complements: nothing critical. Faces (0,1): outer
/// 6 x 25 = 150 plus inner 6 x 9 = 54 = 204. Label 1's boundary is two spheres (Euler 4).
/// Extracted: 408 triangles, 152 + 56 = 208 vertices.
openvdb::Int32Grid::Ptr hollowShell();

/// @brief hollowShell whose hole holds label 2.
/// @details Nothing critical. Faces (0,1): 150, (1,2): 54. Volumes: label 1: 98, label 2: 27.
/// Extracted: patches (0,1) 300 triangles, (1,2) 108 triangles, 208 vertices; Euler
/// characteristic per label: 0: 2, 1: 4, 2: 2.
openvdb::Int32Grid::Ptr hollowShellFilled();

/// @brief The 3x3x1 square ring [0,2]^2 x {0} of label 1 without its centre (1,1,0).
/// @details The inner corners see three 1s around each z-edge; nothing critical. Faces
/// (0,1): top 8 + bottom 8 + outer sides 12 + inner sides 4 = 32. The surface is a torus:
/// 64 triangles, 32 vertices (the 4x4 grid points at z = 0 and at z = 1), Euler 0.
openvdb::Int32Grid::Ptr torusRing();

/// @brief Three labels meeting along the z-line x = y = 1: voxels (0,0,z)=1, (1,0,z)=2,
/// (0,1,z)=(1,1,z)=3 for z = 0, 1.
/// @details The z-edges at (1,1,z) are 1,2,3,3 around (no equal diagonal pair); every other
/// edge has two adjacent background voxels or two adjacent equal labels: nothing critical.
/// Faces: (0,1) 6, (0,2) 6, (0,3) 12, (1,2) 2, (1,3) 2, (2,3) 2 = 30. Extracted: 60
/// triangles, all 27 grid points of [0,2]^3 are vertices.
openvdb::Int32Grid::Ptr tJunction3();

/// @brief Four labels around the z-line x = y = 1: (0,0,z)=1, (1,0,z)=2, (1,1,z)=3,
/// (0,1,z)=4 for z = 0, 1.
/// @details Around the line the order is 1,2,3,4: nothing critical. Faces: (0,L) 6 for each
/// L = 1..4, (1,2) (2,3) (3,4) (1,4) 2 each = 32. Extracted: 64 triangles, 27 vertices.
openvdb::Int32Grid::Ptr corner4();

/// @brief An 8^3 active tile of label 3 over [0,7]^3 (tree.addTile at level 1, no leaf),
/// plus voxel (8,8,0) of label 5, which touches tile voxel (7,7,0) along the z-edge at (8,8,0).
/// @details That edge is 3,0,5,0 around: critical for 0 (diagonal 0s, others not 0),
/// dominant 0; its end points (8,8,0) and (8,8,1) are critical, dominant 0. Faces (0,3):
/// 6 x 64 = 384, (0,5): 6. Tests that tiles count as their voxels.
openvdb::Int32Grid::Ptr activeTileGrid();

/// @brief The hand-derived numbers of one hand-made grid (see the table above).
struct HandMadeCase
{
    std::string name;
    openvdb::Int32Grid::Ptr grid;
    std::size_t criticalEdges = 0;
    std::size_t criticalVertices = 0;
    std::size_t singularVertices = 0;
    /// Coarse interface faces per label pair (a < b).
    std::map<std::pair<vdbi::Label, vdbi::Label>, std::size_t> faces;
    /// Dominant label of every critical element (all equal in these grids; unused if none).
    vdbi::Label dominant = 0;
};

/// All grids above with their numbers, in the order of the table.
std::vector<HandMadeCase> handMadeCases();

} // namespace vdbi_test
