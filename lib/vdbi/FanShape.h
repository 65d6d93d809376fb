// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/FanShape.h
/// @brief How well shaped the triangles around a vertex are, as the moves that shape sharp
/// fans compare them.

#ifndef VDBI_FAN_SHAPE_HAS_BEEN_INCLUDED
#define VDBI_FAN_SHAPE_HAS_BEEN_INCLUDED

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace vdbi {

/// A triangle with an angle under this many degrees is sharp: what the result is judged by
/// (the target: fewer than 1 % of them).
constexpr double SHARP_TRIANGLE_DEGREES = 25.0;
/// A fan with an angle under this many degrees is worth a move.
constexpr double SHARP_FAN_DEGREES = 30.0;

/// How good a fan is: how many sharp triangles it has, then the cosine of its smallest angle.
struct FanShape
{
    int sharp = 0;
    double smallestCos = -1.0;

    /// Adds a triangle, by the cosine of its smallest angle.
    void add(double triangleCos)
    {
        static const double sharpCos = std::cos(SHARP_TRIANGLE_DEGREES * M_PI / 180.0);
        sharp += triangleCos > sharpCos;
        smallestCos = std::max(smallestCos, triangleCos);
    }
    /// Has the fan an angle under SHARP_FAN_DEGREES?
    bool isSharp() const
    {
        static const double fanCos = std::cos(SHARP_FAN_DEGREES * M_PI / 180.0);
        return smallestCos > fanCos;
    }
    /// Fewer sharp triangles, or as many and a smallest angle larger by more than rounding.
    bool isBetterThan(const FanShape& o) const
    {
        return sharp != o.sharp ? sharp < o.sharp : smallestCos < o.smallestCos - 1e-6;
    }
    /// A strict weak order for sorting, best first (exact, without the rounding margin).
    bool operator<(const FanShape& o) const
    {
        return sharp != o.sharp ? sharp < o.sharp : smallestCos < o.smallestCos;
    }
};

/// @brief The cosine of the smallest angle of the triangle with corners @a p0, @a p1, @a p2
/// (openvdb vectors), as FanShape::add() takes it; 1 at a corner with an edge without length.
template<typename Vec>
double
smallestAngleCosOf(const Vec& p0, const Vec& p1, const Vec& p2)
{
    const Vec* p[3] = {&p0, &p1, &p2};
    double largestCos = -1.0;
    for (int k = 0; k < 3; ++k) {
        const Vec a = *p[(k + 1) % 3] - *p[k], b = *p[(k + 2) % 3] - *p[k];
        const double ab = std::sqrt(a.lengthSqr() * b.lengthSqr());
        largestCos = std::max(largestCos, ab > 0.0 ? a.dot(b) / ab : 1.0);
    }
    return largestCos;
}

/// Of the steps aside forEachStepAside() makes, how many the dear guards check: the best.
constexpr std::size_t STEPS_ASIDE_TRIED = 6;

/// @brief Calls @a body(offset) for the pattern of steps aside that shape a sharp fan: 8
/// directions in the plane of unit vectors @a e1 and @a e2 (the first along @a e1), at 0.3,
/// 0.15 and 0.07 times @a reach (the mean distance to the neighbours), the longest first.
template<typename Vec, typename Body>
void
forEachStepAside(const Vec& e1, const Vec& e2, double reach, const Body& body)
{
    static constexpr double STEPS[] = {0.3, 0.15, 0.07};
    constexpr int DIRECTIONS = 8;
    for (const double step : STEPS) {
        for (int k = 0; k < DIRECTIONS; ++k) {
            const double a = 2.0 * M_PI * k / DIRECTIONS;
            body((e1 * std::cos(a) + e2 * std::sin(a)) * (step * reach));
        }
    }
}

} // namespace vdbi

#endif // VDBI_FAN_SHAPE_HAS_BEEN_INCLUDED
