// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/Remeshing.h
/// @brief Boundary-aware isotropic remeshing of the interface patches (Botsch & Kobbelt 2004).

#ifndef VDBI_REMESHING_HAS_BEEN_INCLUDED
#define VDBI_REMESHING_HAS_BEEN_INCLUDED

#include <vdbi/InterfaceMesh.h>

#include <openvdb/Types.h>
#include <openvdb/util/NullInterrupter.h>

namespace vdbi {

/// Settings of remeshPatches().
struct RemeshOptions
{
    /// Target edge length in world units, > 0.
    double edgeLength = 1.0;
    /// Split/collapse/flip/relax/project rounds. Five: more change little (frog, 5 against 10
    /// rounds at 1, 2 and 4 voxels: edges in range 99.86 / 97.33 / 77.40 against 99.87 /
    /// 97.38 / 77.50 %, the same 1st-percentile smallest angles) and cost 20-45 % more time.
    int iterations = 5;
    /// World size of one voxel along x, y and z (an axis-aligned transform): the unit of the
    /// smoothing bounds, so curves and reference surfaces stay within a fraction of a voxel of
    /// the staircase along every axis. Zeros: derived from the mesh's point keys (to 12
    /// significant digits, so a size written in decimal comes out as the grid's own and the
    /// result is the same as with it), or the edge length when there are no keys.
    openvdb::Vec3d voxelSize = openvdb::Vec3d(0.0);
    /// Patches in parallel with TBB; the result is the same either way.
    bool threaded = true;
    /// Polled between stages and between patches; may be null.
    openvdb::util::NullInterrupter* interrupter = nullptr;
};

/// @brief Seconds of the steps of the rounds of one or more patches (remeshIsotropically()),
/// for benchmarks: where the time of a patch goes.
struct RemeshStepSeconds
{
    double split = 0.0;       ///< moving off the chords (first round), splits
    double collapse = 0.0;    ///< collapses (the first round's from the staircase included)
    double flip = 0.0;        ///< flips towards valence 6, and of caps
    double relax = 0.0;       ///< tangential relaxation
    double project = 0.0;     ///< projection onto the reference, with its step-backs
    double sharpFans = 0.0;   ///< after the last round: sharp triangles flipped, fans smoothed

    RemeshStepSeconds& operator+=(const RemeshStepSeconds& other)
    {
        split += other.split;
        collapse += other.collapse;
        flip += other.flip;
        relax += other.relax;
        project += other.project;
        sharpFans += other.sharpFans;
        return *this;
    }
};

/// @brief Wall seconds of the stages of one remeshPatches() run.
/// @details A patch is remeshed right after its reference surface is built, in one parallel
/// pass over the patches: that pass's wall time is shared between referenceSeconds and
/// remeshingSeconds as the patches' summed times for the two are.
struct RemeshStatistics
{
    double curveSeconds = 0.0;       ///< feature curves found, smoothed and resampled
    double referenceSeconds = 0.0;   ///< the reference surfaces of all patches
    double remeshingSeconds = 0.0;   ///< boundaries attached, rounds, output assembled
    double separationSeconds = 0.0;  ///< separation: moves, splits, flips and collapses
    /// The rounds' steps of all patches: CPU seconds, summed over the patches (several
    /// threads make them add up to more than remeshingSeconds).
    RemeshStepSeconds roundSteps;
    /// The parts of separationSeconds (wall): the cycles of separation, splits and flips;
    /// the pulls towards the voxel faces and their centres; the shaping of sharp fans across
    /// patches; the collapses of meeting and short edges; the final counts below.
    double separationCycleSeconds = 0.0, pullSeconds = 0.0, fanShapingSeconds = 0.0,
           finalCollapseSeconds = 0.0, checkSeconds = 0.0;
    /// Pairs of output triangles that meet other than in shared corners and edges
    /// (findMeetingPairs(), searched afresh at the end): 0 unless separation failed somewhere.
    std::size_t meetingPairs = 0;
    /// Voxel face centres of the raw patches farther than one voxel (along each axis) from
    /// their remeshed patch (findFarFaceCentres(), searched afresh at the end): 0 unless the
    /// pull towards them failed somewhere.
    std::size_t farFaceCentres = 0;
};

/// @brief Remeshes every patch to the target edge length, keeping every guarantee of the
/// extraction: each patch a consistently oriented 2-manifold, patches sharing their boundary
/// vertices exactly, the patches of every label a closed surface (ALGORITHM.md §5).
/// @details
/// 1. The feature curves (patch boundaries) are smoothed along themselves and resampled
///    once, the same samples for every patch on a curve; junctions stay where they are.
/// 2. Every patch (in parallel, independently) gets a reference surface: its triangles
///    smoothed within 0.45 voxel (per axis) of the staircase, its boundary on the smoothed
///    curves.
/// 3. The patch's boundary is replaced by the curve samples: a strip of triangles between
///    the extracted boundary and the sample polyline makes the samples the new boundary;
///    boundary vertices are locked from then on.
/// 4. Rounds of: split edges longer than 4/3 of the target (not where the midpoint would be
///    far from the reference surface and never allowed onto it), collapse edges shorter than 4/5
///    (to the midpoint on flat ground, onto the sharper end on a crease), flip edges towards
///    valence 6 (4 on the boundary), flip caps (non-Delaunay edges whose flip raises the
///    smallest angle), tangential relaxation, projection onto the reference surface. No
///    operation creates a non-manifold configuration, a folded triangle, an interior edge
///    between two boundary vertices that another patch may make too (only their
///    chordOwner(), the patch the edge runs into, may), or takes the surface more than 0.6 voxel away from a
///    point of the reference surface (off the curves; nor farther than it already was); no
///    relaxation move drags a vertex across a crease. So a patch never
///    loses its topology (every label keeps its Euler characteristic) and a patch on a
///    boundary loop of three samples keeps a fan around an inner vertex.
/// 5. Where triangles of two patches sharing a label cross near their common curve (each
///    patch was remeshed without seeing the other), separatePatches() moves their inner
///    vertices apart along the normals, at most 0.4 voxel.
/// 6. An inner edge of a triangle that still meets another is flipped where the other
///    diagonal of its two triangles meets fewer (flipMeetingEdges()).
/// 7. Where pairs are left, steps 5 and 6 run again with a bound of 0.5 voxel, then once
///    more with the inner curve samples moving too (junctions stay), then with a bound of
///    0.75 voxel, each kept only if it leaves fewer pairs.
/// 8. Free vertices of fans with an angle under 30 degrees step aside where their fans get
///    better and no pair of triangles of any patches comes to meet, within 0.8 voxel of the
///    voxel faces (shapeSharpFans(): the fans that step 4 left next to tight curves, where a
///    patch cannot see the others, and those the reference surface's guards kept).
/// 9. Voxel face centres left over 0.95 voxel from their patch (findFarFaceCentres(): step 4
///    keeps the surface near the smoothed staircase, not near the centres, and a thin tip
///    can end up a voxel away) each pull a free corner of the patch's nearest triangle
///    towards them where no guard of step 5 objects (pullTowardsFaceCentres()).
/// 10. Where pairs are still left, a free corner of a meeting triangle is collapsed into a
///    neighbour where that leaves fewer (collapseMeetingEdges(): knots of one patch).
/// 11. Edges under half the target with a free end are collapsed, every patch in sight: where
///    no edge over 1.5 x target, no fold, no meeting pair, no sharper fan results, the voxel
///    faces stay covered, and a new edge between two samples is their chordOwner()'s
///    (collapseMeetingAndShortEdges(): what step 4 left where a patch could not see the
///    others; a loop of three samples may become one triangle, in one of its patches).
/// 12. The output is searched afresh for what would break its promises: pairs of triangles
///    that meet (findMeetingPairs()) and voxel face centres farther than one voxel from their
///    patch (findFarFaceCentres()); their counts go into @a statistics.
/// The output has the samples first (shared), then the inner vertices patch by patch; the
/// patches keep their order, label pairs and orientation (normals from a into b). Point keys
/// are cleared (keyScale 0). The result is the same for any number of threads.
/// @throw openvdb::ValueError if the edge length is not a finite number > 0
/// @throw vdbi::TopologyError if the input is not a valid interface mesh
/// @throw vdbi::Interrupted if the interrupter asks to stop
/// @param statistics  if not null, receives the seconds per stage and step 12's counts
InterfaceMesh remeshPatches(const InterfaceMesh& raw, const RemeshOptions& options,
                            RemeshStatistics* statistics = nullptr);

} // namespace vdbi

#endif // VDBI_REMESHING_HAS_BEEN_INCLUDED
