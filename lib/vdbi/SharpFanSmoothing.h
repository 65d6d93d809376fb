// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/SharpFanSmoothing.h
/// @brief After the rounds of isotropic remeshing: free vertices of fans with a small angle
/// move where their fans get better shaped, within the remeshing's guards.

#ifndef VDBI_SHARP_FAN_SMOOTHING_HAS_BEEN_INCLUDED
#define VDBI_SHARP_FAN_SMOOTHING_HAS_BEEN_INCLUDED

#include <vdbi/FanShape.h>
#include <vdbi/IsotropicRemeshing.h>
#include <vdbi/ReferenceCoverage.h>

namespace vdbi {

/// @brief Moves the free vertices of fans with an angle under 30 degrees (onto the reference
/// surface) where that makes the fan better and passes the guards of a projection: no fold,
/// no crease crossed, every covered point within RemeshSettings::smoothingDeviation2.
/// @details Two passes. First toward the mean of the neighbours (whole or half way), when
/// that raises the fan's smallest angle. Then also to a short step aside, when that leaves
/// the fan fewer triangles under SHARP_TRIANGLE_DEGREES, or as many and a larger smallest
/// angle; fans next to a tight part of the boundary (a segment under half the target, or
/// where it touches itself) or crossing anything within two edges stay. Every loop
/// runs in vertex order: the result depends on the patch alone.
/// @param coverage  the reference points every face of @a patch covers, kept up to date
void smoothSharpFans(RemeshingPatch& patch, ReferenceCoverage& coverage,
                     const RemeshSettings& settings);

} // namespace vdbi

#endif // VDBI_SHARP_FAN_SMOOTHING_HAS_BEEN_INCLUDED
