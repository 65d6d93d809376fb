// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/IsotropicRemeshing.h
/// @brief The rounds of isotropic remeshing of one patch with a locked boundary (Botsch &
/// Kobbelt 2004): split, collapse, flip, relax, project.

#ifndef VDBI_ISOTROPIC_REMESHING_HAS_BEEN_INCLUDED
#define VDBI_ISOTROPIC_REMESHING_HAS_BEEN_INCLUDED

#include <vdbi/Interruption.h>
#include <vdbi/PatchBoundary.h>
#include <vdbi/Remeshing.h>

#include <cmath>

namespace vdbi {

/// Numbers every round needs, derived once from RemeshOptions.
struct RemeshSettings
{
    double target = 1.0;
    double high2 = 0.0;            ///< (4/3 target)^2: longer edges are split
    /// The first round collapses towards target / 2^k, ..., target / 4, target / 2 first, for
    /// every target / 2^k no smaller than this (0: not at all).
    double finestCoarsening = 0.0;
    int iterations = 5;
    /// (Largest distance)^2 between a reference surface point (off the curves) and the
    /// surface after a collapse, flip or relaxation move, unless it was farther before: keeps
    /// tips and thin parts from being eaten.
    double deviation2 = 0.0;
    /// The same for the moves that smooth sharp fans after the last round (a tighter bound:
    /// they come on top of every other operation's).
    double smoothingDeviation2 = 0.0;
    /// A vertex whose reference normal differs from a neighbour's by more than this angle
    /// sits on a crease or corner: it is kept in place of a flat neighbour when collapsing.
    double flatCos = std::cos(20.0 * M_PI / 180.0);
    /// A relaxation move that turns the reference normal by more than this angle crosses a
    /// crease (it would cut the crease off): it is halved, else undone.
    double creaseCos = std::cos(30.0 * M_PI / 180.0);
};

/// @brief Rounds of: split edges longer than 4/3 of the target (but where the midpoint would
/// be far from the reference surface and never allowed onto it), collapse edges shorter than
/// 4/5 (to the midpoint on flat ground, onto the sharper end on a crease; in the first round
/// first towards halved targets, RemeshSettings::finestCoarsening, after moving free vertices
/// off the chords between curve samples), flip edges towards
/// valence 6 (4 on the boundary), flip caps (non-Delaunay edges whose flip raises the
/// smallest angle), tangential relaxation, projection onto the reference surface. After the
/// last round, edges of triangles under 25 degrees are flipped where that raises the smaller
/// smallest angle, before and after the free vertices of fans with an angle under 30 degrees
/// move (smoothSharpFans(), SharpFanSmoothing.h).
/// @details Locked (boundary) vertices never move. No operation creates a non-manifold
/// configuration, an inner edge between two locked vertices that another patch may make too
/// (RemeshingPatch::mayJoinLocked()), or takes the surface more than sqrt(deviation2) away
/// from a vertex of the reference surface off the curves (nor farther than it was: every
/// face keeps a list of the reference points nearest to it, so the bound holds against the
/// fixed reference, not the mesh of the step before); a collapse turns no triangle over
/// (against its own old normal), a flip or projection folds none against the reference
/// normals; no collapse, flip or move (relaxation with projection) makes the triangles it
/// changes cross each other or the faces around more often than the ones they replace did
/// (FoldGuard.h; only where neighbours turn sharply or a fan winds twice, and in the first
/// collapse pass, from the staircase, against the faces across the fan's edges only); no
/// relaxation move drags a vertex across a crease, and a vertex on a folded triangle relaxes
/// to the mean of its neighbours (unfolding what attaching the samples folded). So the patch
/// keeps its topology. Every loop runs in a fixed order (edge or vertex index): the result
/// depends on the patch alone.
/// @param seconds  if given, the steps' seconds are added to it
/// @return false if the interrupter asked to stop (the patch is then unfinished)
bool remeshIsotropically(RemeshingPatch& patch, const RemeshSettings& settings,
                         InterruptFlag& interrupt, RemeshStepSeconds* seconds = nullptr);

} // namespace vdbi

#endif // VDBI_ISOTROPIC_REMESHING_HAS_BEEN_INCLUDED
