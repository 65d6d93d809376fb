// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/ChordOwners.h
/// @brief Which patch may join two curve samples by an inner edge (a chord): the one the
/// chord runs into, as every patch can tell alike while they are remeshed apart.

#ifndef VDBI_CHORD_OWNERS_HAS_BEEN_INCLUDED
#define VDBI_CHORD_OWNERS_HAS_BEEN_INCLUDED

#include <vdbi/FeatureCurves.h>
#include <vdbi/InterfaceMesh.h>

namespace vdbi {

/// @brief Fills FeatureCurves::sampleSides and junctionPatches: where every patch lies seen
/// from every inner sample, and the patches at every junction.
/// @details The side at a sample is measured on the extracted mesh: the direction from the
/// feature edge under the sample into the patch's triangle on it, across the edge. The
/// result depends only on the curves and the mesh, not on the number of threads.
/// @pre resampleFeatureCurves() ran on @a curves, made from @a mesh
void measureCurveSides(FeatureCurves& curves, const InterfaceMesh& mesh, bool threaded = true);

/// @brief The patch that may join samples @a u and @a v by an inner edge, or NO_PATCH.
/// @details A chord may belong to one patch only, or the surface of a label would hold the
/// edge four times; the patch it runs into needs it (inside a sharp bend of a curve, the
/// corner is else filled by sharp triangles or a vertex with short edges). Of the patches
/// that have both samples (those of their curves, or of the junction), the one whose sides
/// at the inner samples point the most toward the other sample; ties to the lowest. None
/// between two junctions (a single-segment curve elsewhere may join them). The first patch
/// of the curves owned every chord before: frog at 2 voxels, edges in range 97.71 -> 97.93 %,
/// 1st-percentile smallest angle 22.5 -> 23.2 degrees with this owner.
/// @pre measureCurveSides() ran
std::uint32_t chordOwner(const FeatureCurves& curves, std::uint32_t u, std::uint32_t v);

} // namespace vdbi

#endif // VDBI_CHORD_OWNERS_HAS_BEEN_INCLUDED
