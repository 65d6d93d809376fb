// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/Interfaces.h
/// @brief The whole pipeline in one call: the entry point of the CLI, the SOP and the tests.

#ifndef VDBI_INTERFACES_HAS_BEEN_INCLUDED
#define VDBI_INTERFACES_HAS_BEEN_INCLUDED

#include <vdbi/InterfaceMesh.h>
#include <vdbi/Types.h>

#include <openvdb/openvdb.h>

#include <string>
#include <utility>
#include <vector>

namespace vdbi {

/// Every setting of the pipeline.
struct Options
{
    RepairOptions repair;        ///< priority, constraints, threading, interrupter
    /// Remesh the patches towards edgeLength (smooth, shared curves; see Remeshing.h);
    /// false: the raw extraction, the voxel faces themselves, exact to the input.
    bool remesh = true;
    double edgeLength = 0.0;     ///< target edge length in world units (0: one voxel)
    int iterations = 5;          ///< remeshing iterations (see RemeshOptions)
    /// Extract only the faces owned by the voxels of this box (face (v, axis) belongs to
    /// voxel v), reading a halo of HALO voxels around it; empty: the whole grid. The raw
    /// patches of boxes that tile a grid stitch by their vertex keys into exactly the
    /// triangles of the whole grid (the base for splitting work across machines). Only with
    /// remesh = false: remeshed tiles would not stitch.
    openvdb::CoordBBox region;
    static constexpr int HALO = 3;
    /// Fill InterfaceMesh::pointKeys, the exact vertex keys that tiles stitch by (always on
    /// with a region); writing the mesh does not need them.
    bool pointKeys = true;
};

/// What a run found and how long its stages took.
struct Statistics
{
    std::size_t labelCount = 0;        ///< distinct labels, the background included
    std::size_t criticalFaces = 0;
    std::size_t criticalEdges = 0;
    std::size_t criticalVertices = 0;
    std::size_t singularVertices = 0;  ///< critical by the antipodal rule (§2 rule 2)
    std::size_t subdividedVoxels = 0;
    std::size_t relabelledSubvoxels = 0;
    int subdivision = 1;
    std::size_t patches = 0;
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    /// After remeshing: pairs of triangles that meet (cross or touch) other than in shared
    /// corners and edges. 0 is the promise; more says where remeshing could not keep it.
    std::size_t meetingPairs = 0;
    /// After remeshing: voxel face centres farther than one voxel from their patch. 0 is the
    /// promise, as above.
    std::size_t farFaceCentres = 0;
    /// Seconds per stage, in the order they ran.
    std::vector<std::pair<std::string, double>> stageSeconds;
};

struct Result
{
    InterfaceMesh mesh;
    Statistics statistics;
};

/// @brief Consistent, manifold interface patches between all labels of @a grid.
/// @details Finds the critical elements, fattens them on a sparse subdivided grid and extracts
/// the patches (Bischoff & Kobbelt 2006), then remeshes them unless Options::remesh is off.
/// Every patch is a 2-manifold; patches share their boundary vertices; the patches of every
/// label form a closed, oriented surface.
/// @param grid     labels; the background value is the label of everything not stored
/// @param options  see Options
/// @throw openvdb::ValueError for invalid options (a region with remeshing among them)
/// @throw vdbi::Interrupted if the interrupter asks to stop
/// @throw vdbi::TopologyError if a guarantee failed (a bug)
Result extractInterfaces(const openvdb::Int32Grid& grid, const Options& options = Options());

/// What a finished run should tell its user (the CLI on stderr, the SOP as a node warning),
/// or "" when nothing: triangles left crossing or touching after remeshing, and voxel face
/// centres left farther than one voxel from their patch.
std::string runWarning(const Statistics& statistics);

} // namespace vdbi

#endif // VDBI_INTERFACES_HAS_BEEN_INCLUDED
