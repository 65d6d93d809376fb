// SPDX-License-Identifier: Apache-2.0

#include <vdbi/TriangleCrossing.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace vdbi {

namespace {

using Point = TriMesh::Point;

/// Cosine of the turn beyond which two triangles sharing an edge lie folded onto each other.
constexpr double FOLD_COS = -0.99619469809174553;   // cos(175 degrees)

/// The corner after corner k of a triangle, and the one before it: (k + 1) % 3 and
/// (k + 2) % 3 by table (the crossing tests look them up tens of millions of times).
constexpr int NEXT_CORNER[3] = {1, 2, 0}, PREVIOUS_CORNER[3] = {2, 0, 1};

/// Six times the signed volume of tetrahedron (a, b, c, d).
inline double
orient(const Point& a, const Point& b, const Point& c, const Point& d)
{
    return ((b - a) % (c - a)) | (d - a);
}

/// How many corners @a s and @a t have in common.
inline int
sharedCorners(const CornerTriangle& s, const CornerTriangle& t)
{
    return s.hasCorner(t.id[0]) + s.hasCorner(t.id[1]) + s.hasCorner(t.id[2]);
}

/// Are @a a and @a b strictly on opposite sides of zero?
inline bool
opposite(double a, double b)
{
    return (a > 0.0 && b < 0.0) || (a < 0.0 && b > 0.0);
}

/// Are all three strictly on one side of zero?
inline bool
oneSide(const double (&h)[3])
{
    return (h[0] > 0.0 && h[1] > 0.0 && h[2] > 0.0) || (h[0] < 0.0 && h[1] < 0.0 && h[2] < 0.0);
}

/// Are all three on one side of zero, zero included?
inline bool
closedOneSide(const double (&h)[3])
{
    return (h[0] >= 0.0 && h[1] >= 0.0 && h[2] >= 0.0)
        || (h[0] <= 0.0 && h[1] <= 0.0 && h[2] <= 0.0);
}

/// Does segment pq, whose ends lie @a dp and @a dq above the plane of @a t (in units of its
/// normal), pass through the inside of @a t (touching does not count)?
inline bool
segmentCrossesTriangle(const Point& p, const Point& q, double dp, double dq,
                       const CornerTriangle& t)
{
    if (!opposite(dp, dq)) return false;
    const double o[3] = {orient(p, q, t.p[0], t.p[1]), orient(p, q, t.p[1], t.p[2]),
                         orient(p, q, t.p[2], t.p[0])};
    return oneSide(o);
}

/// Does segment pq, not in the plane of @a t, meet @a t, its edges and corners included?
inline bool
segmentMeetsTriangle(const Point& p, const Point& q, double dp, double dq,
                     const CornerTriangle& t)
{
    if ((dp > 0.0 && dq > 0.0) || (dp < 0.0 && dq < 0.0) || (dp == 0.0 && dq == 0.0)) {
        return false;
    }
    const double o[3] = {orient(p, q, t.p[0], t.p[1]), orient(p, q, t.p[1], t.p[2]),
                         orient(p, q, t.p[2], t.p[0])};
    return closedOneSide(o);
}

/// > 0 when x is to the left of a -> b seen from the tip of @a n (in a plane normal to n).
inline double
side(const Point& n, const Point& a, const Point& b, const Point& x)
{
    return ((b - a) % (x - a)) | n;
}

/// Is x strictly inside triangle t of the plane normal to @a n (either orientation)?
inline bool
insideInPlane(const Point& n, const CornerTriangle& t, const Point& x)
{
    const double d[3] = {side(n, t.p[0], t.p[1], x), side(n, t.p[1], t.p[2], x),
                         side(n, t.p[2], t.p[0], x)};
    return oneSide(d);
}

/// Do segments ab and cd of the plane normal to @a n cross at a point inside both?
inline bool
segmentsCrossInPlane(const Point& n, const Point& a, const Point& b, const Point& c,
                     const Point& d)
{
    return opposite(side(n, a, b, c), side(n, a, b, d))
        && opposite(side(n, c, d, a), side(n, c, d, b));
}

/// Is direction x strictly inside the angle from u to w, turning counter-clockwise about @a n
/// (an angle under 180 degrees)?
inline bool
insideAngle(const Point& n, const Point& u, const Point& w, const Point& x)
{
    return ((u % x) | n) > 0.0 && ((x % w) | n) > 0.0;
}

/// Do @a s and @a t, one plane, sharing corner s.p[si] = t.p[ti], overlap near it?
bool
anglesOverlap(const CornerTriangle& s, int si, const CornerTriangle& t, int ti)
{
    // s turns counter-clockwise about its normal from b to c; t from e to f, or from f to e
    // if it faces the other way.
    const Point& a = s.p[si];
    const Point b = s.p[NEXT_CORNER[si]] - a, c = s.p[PREVIOUS_CORNER[si]] - a;
    const Point e = t.p[NEXT_CORNER[ti]] - a, f = t.p[PREVIOUS_CORNER[ti]] - a;
    const Point& n = s.normal;
    const bool same = (t.normal | n) > 0.0;
    const Point u = same ? e : f, w = same ? f : e;
    const Point bisectorS = b.normalized() + c.normalized();
    const Point bisectorT = u.normalized() + w.normalized();
    return insideAngle(n, b, c, u) || insideAngle(n, b, c, w) || insideAngle(n, u, w, b)
        || insideAngle(n, u, w, c) || insideAngle(n, b, c, bisectorT)
        || insideAngle(n, u, w, bisectorS);
}

/// Do @a s and @a t, one plane, sharing no corner, overlap?
bool
trianglesOverlapInPlane(const CornerTriangle& s, const CornerTriangle& t)
{
    const Point& n = s.normal;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (segmentsCrossInPlane(n, s.p[i], s.p[(i + 1) % 3], t.p[j], t.p[(j + 1) % 3])) {
                return true;
            }
        }
    }
    // No edges cross: one inside the other, or both the same (then a centroid is inside).
    const Point cs = (s.p[0] + s.p[1] + s.p[2]) / 3.0, ct = (t.p[0] + t.p[1] + t.p[2]) / 3.0;
    for (const Point& x : {t.p[0], t.p[1], t.p[2], ct}) {
        if (insideInPlane(n, s, x)) return true;
    }
    for (const Point& x : {s.p[0], s.p[1], s.p[2], cs}) {
        if (insideInPlane(n, t, x)) return true;
    }
    return false;
}

/// Do segments ab and cd of the plane normal to @a n have a common point (ends included)?
bool
segmentsMeetInPlane(const Point& n, const Point& a, const Point& b, const Point& c,
                    const Point& d)
{
    const double c1 = side(n, a, b, c), d1 = side(n, a, b, d);
    if (c1 == 0.0 && d1 == 0.0) {
        // On one line: do their extents along it overlap?
        const Point ab = b - a;
        const double tc = (c - a) | ab, td = (d - a) | ab, tb = ab | ab;
        return std::max(0.0, std::min(tc, td)) <= std::min(tb, std::max(tc, td));
    }
    const double a1 = side(n, c, d, a), b1 = side(n, c, d, b);
    return !((c1 > 0.0 && d1 > 0.0) || (c1 < 0.0 && d1 < 0.0))
        && !((a1 > 0.0 && b1 > 0.0) || (a1 < 0.0 && b1 < 0.0));
}

/// Is x inside triangle t of the plane normal to @a n or on its edges (either orientation)?
inline bool
onOrInsideInPlane(const Point& n, const CornerTriangle& t, const Point& x)
{
    const double d[3] = {side(n, t.p[0], t.p[1], x), side(n, t.p[1], t.p[2], x),
                         side(n, t.p[2], t.p[0], x)};
    return closedOneSide(d);
}

/// Do @a s and @a t, one plane, sharing no corner, have a common point?
bool
trianglesMeetInPlane(const CornerTriangle& s, const CornerTriangle& t)
{
    const Point& n = s.normal;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (segmentsMeetInPlane(n, s.p[i], s.p[NEXT_CORNER[i]], t.p[j], t.p[NEXT_CORNER[j]])) {
                return true;
            }
        }
    }
    return onOrInsideInPlane(n, s, t.p[0]) || onOrInsideInPlane(n, t, s.p[0]);
}

/// Do the bounding boxes of @a s and @a t overlap? Half the pairs the fold test counts do
/// not: tested inline, before the call.
inline bool
boxesOverlap(const CornerTriangle& s, const CornerTriangle& t)
{
    for (int k = 0; k < 3; ++k) {
        if (s.high[k] < t.low[k] || t.high[k] < s.low[k]) return false;
    }
    return true;
}

/// @brief trianglesCross() (@a Touching false) or trianglesTouch() (true) for boxes that
/// overlap; for trianglesTouch(), @a s has an area.
template<bool Touching>
bool
meetWithinBoxes(const CornerTriangle& s, const CornerTriangle& t)
{
    // Does segment pq, its ends dp and dq above the plane of @a x, pass through x (or touch
    // it)?
    auto passes = [](const Point& p, const Point& q, double dp, double dq,
                     const CornerTriangle& x) {
        return Touching ? segmentMeetsTriangle(p, q, dp, dq, x)
                        : segmentCrossesTriangle(p, q, dp, dq, x);
    };
    int shared = 0, si = -1, ti = -1;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (s.id[i] == t.id[j]) {
                ++shared;
                si = i;
                ti = j;
            }
        }
    }
    if (shared == 3) return true;
    if (shared == 2) {
        const double d = s.normal | t.normal;
        return d < 0.0 && d * d > FOLD_COS * FOLD_COS * s.normal.sqrnorm() * t.normal.sqrnorm();
    }
    if (shared == 1) {
        const Point &b = s.p[NEXT_CORNER[si]], &c = s.p[PREVIOUS_CORNER[si]];
        const Point &e = t.p[NEXT_CORNER[ti]], &f = t.p[PREVIOUS_CORNER[ti]];
        const double de = s.normal | (e - s.p[0]), df = s.normal | (f - s.p[0]);
        if (de == 0.0 && df == 0.0) return anglesOverlap(s, si, t, ti);
        // Both are convex and hold the shared corner: only the edges opposite it can meet the
        // other triangle elsewhere.
        return passes(e, f, de, df, s)
            || passes(b, c, t.normal | (b - t.p[0]), t.normal | (c - t.p[0]), t);
    }
    double o[3], r[3];   // heights of t's corners over s, and of s's over t
    for (int i = 0; i < 3; ++i) o[i] = s.normal | (t.p[i] - s.p[0]);
    if (oneSide(o)) return false;
    if (o[0] == 0.0 && o[1] == 0.0 && o[2] == 0.0) {
        return Touching ? trianglesMeetInPlane(s, t) : trianglesOverlapInPlane(s, t);
    }
    for (int i = 0; i < 3; ++i) r[i] = t.normal | (s.p[i] - t.p[0]);
    if (oneSide(r)) return false;
    for (int i = 0; i < 3; ++i) {
        const int j = NEXT_CORNER[i];
        if (passes(s.p[i], s.p[j], r[i], r[j], t) || passes(t.p[i], t.p[j], o[i], o[j], s)) {
            return true;
        }
    }
    return false;
}

/// trianglesCross() for boxes that overlap.
inline bool
crossesWithinBoxes(const CornerTriangle& s, const CornerTriangle& t)
{
    return meetWithinBoxes<false>(s, t);
}

/// Triangle @a t as trianglesTouch() takes it, turned around (two corners swapped) if @a flip.
CornerTriangle
cornerTriangle(const PointArray& points, const openvdb::Vec3I& t, bool flip)
{
    const int i = flip ? 2 : 1, j = flip ? 1 : 2;
    return CornerTriangle(toPoint(points[t[0]]), toPoint(points[t[i]]), toPoint(points[t[j]]),
                          int(t[0]), int(t[i]), int(t[j]));
}

/// Does @a t run along an edge of @a s in the same direction as @a s?
bool
runsAlongSameWay(const openvdb::Vec3I& s, const openvdb::Vec3I& t)
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (s[i] == t[j] && s[(i + 1) % 3] == t[(j + 1) % 3]) return true;
        }
    }
    return false;
}

} // namespace

bool
trianglesCross(const CornerTriangle& s, const CornerTriangle& t)
{
    return boxesOverlap(s, t) && crossesWithinBoxes(s, t);
}

bool
trianglesTouch(const CornerTriangle& s, const CornerTriangle& t)
{
    if (!boxesOverlap(s, t)) return false;
    if (s.normal.sqrnorm() > 0.0) return meetWithinBoxes<true>(s, t);
    if (t.normal.sqrnorm() > 0.0) return meetWithinBoxes<true>(t, s);
    return crossesWithinBoxes(s, t);
}

int
countCrossings(const std::vector<CornerTriangle>& changed,
               const std::vector<CornerTriangle>& around, const std::vector<char>* suspect,
               bool embedded)
{
    int count = 0;
    for (std::size_t i = 0; i < changed.size(); ++i) {
        if (suspect && !(*suspect)[i]) continue;
        const CornerTriangle& s = changed[i];
        for (const CornerTriangle& t : around) {
            count += boxesOverlap(s, t) && crossesWithinBoxes(s, t);
        }
        // Each pair once: j < i only if j is not tested on its own.
        for (std::size_t j = 0; j < changed.size(); ++j) {
            if (j == i || (j < i && (!suspect || (*suspect)[j]))) continue;
            const CornerTriangle& t = changed[j];
            if (embedded && sharedCorners(s, t) < 2) continue;
            count += boxesOverlap(s, t) && crossesWithinBoxes(s, t);
        }
    }
    return count;
}

bool
looksUnfolded(const std::vector<CornerTriangle>& fan, const std::vector<CornerTriangle>& outer,
              const std::vector<int>& outerOf, int centre, double turnCos,
              std::vector<char>& suspect, bool* embedded)
{
    auto isSharp = [turnCos](const Point& n, const Point& m) {
        const double d = n | m, bound = turnCos * turnCos * n.sqrnorm() * m.sqrnorm();
        return turnCos >= 0.0 ? !(d > 0.0 && d * d > bound) : d < 0.0 && d * d >= bound;
    };
    const std::size_t count = fan.size();
    suspect.assign(count, 0);
    if (embedded) *embedded = false;
    bool unfolded = true;
    auto compare = [&](std::size_t i, std::size_t j) {
        if (!isSharp(fan[i].normal, fan[j].normal)) return;
        suspect[i] = suspect[j] = 1;
        unfolded = false;
    };
    // Corner k of triangle i is the centre; the triangle turns counter-clockwise from its
    // corner k + 1 to k + 2, and the one after it around the centre starts with k + 2.
    auto corner = [&](std::size_t i) {
        const CornerTriangle& t = fan[i];
        return t.id[0] == centre ? 0 : t.id[1] == centre ? 1 : 2;
    };
    auto startOf = [&](std::size_t i) { return fan[i].id[NEXT_CORNER[corner(i)]]; };
    auto endOf = [&](std::size_t i) { return fan[i].id[PREVIOUS_CORNER[corner(i)]]; };
    // The triangle that starts where @a i ends (or ends where it starts, if !forward): fans
    // come in the order of their circulation, so the neighbours in the list are tried first.
    auto find = [&](std::size_t i, bool forward) {
        const int id = forward ? endOf(i) : startOf(i);
        auto matches = [&](std::size_t j) {
            return j != i && (forward ? startOf(j) : endOf(j)) == id;
        };
        const std::size_t next = (i + 1) % count, previous = (i + count - 1) % count;
        if (matches(forward ? next : previous)) return forward ? next : previous;
        if (matches(forward ? previous : next)) return forward ? previous : next;
        for (std::size_t j = 0; j < count; ++j) {
            if (matches(j)) return j;
        }
        return count;
    };
    std::size_t first = 0;   // a triangle no other comes before (at a boundary, the first)
    if (centre >= 0) {
        // A fan around a vertex of a 2-manifold: at most one triangle after each.
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t j = find(i, true);
            if (j < count) compare(i, j);
            if (find(i, false) == count) first = i;
        }
    } else {
        for (std::size_t i = 0; i < count; ++i) {
            for (std::size_t j = i + 1; j < count; ++j) {
                if (sharedCorners(fan[i], fan[j]) >= 2) compare(i, j);
            }
        }
    }
    for (std::size_t k = 0; k < outer.size(); ++k) {
        if (isSharp(fan[outerOf[k]].normal, outer[k].normal)) {
            suspect[outerOf[k]] = 1;
            unfolded = false;
        }
    }
    if (centre < 0) return unfolded;
    // Seen from the way of their sum, the triangles all face up and turn counter-clockwise
    // around the centre; they go around it once if no other triangle's angle there holds
    // the first edge of the first one.
    Point up(0, 0, 0);
    for (const CornerTriangle& t : fan) up += t.normal;
    const int k0 = corner(first);
    const Point x = fan[first].p[NEXT_CORNER[k0]] - fan[first].p[k0];
    bool once = true;
    for (std::size_t i = 0; i < count && once; ++i) {
        const CornerTriangle& t = fan[i];
        if (!((t.normal | up) > 0.0)) once = false;
        if (i == first) continue;
        const int k = corner(i);
        const Point u = t.p[NEXT_CORNER[k]] - t.p[k], w = t.p[PREVIOUS_CORNER[k]] - t.p[k];
        // Holds x at its start too, not opposite it.
        const double ux = (u % x) | up;
        if ((ux > 0.0 || (ux == 0.0 && (u | x) > 0.0)) && ((x % w) | up) > 0.0) once = false;
    }
    if (once) {
        if (embedded) *embedded = true;
        return unfolded;
    }
    for (std::size_t i = 0; i < count; ++i) {
        if (fan[i].hasCorner(centre)) suspect[i] = 1;
    }
    return false;
}


namespace {

/// Are the bounding boxes of triangles @a s and @a t apart? Then trianglesTouch() answers no
/// as well; most pairs of a cell of the candidate grid are answered so, without building the
/// two triangles (their normals, boxes and the corner order) first.
bool
boxesApart(const PointArray& points, const openvdb::Vec3I& s, const openvdb::Vec3I& t)
{
    for (int k = 0; k < 3; ++k) {
        const double sLow = std::min({points[s[0]][k], points[s[1]][k], points[s[2]][k]});
        const double tHigh = std::max({points[t[0]][k], points[t[1]][k], points[t[2]][k]});
        if (tHigh < sLow) return true;
        const double sHigh = std::max({points[s[0]][k], points[s[1]][k], points[s[2]][k]});
        const double tLow = std::min({points[t[0]][k], points[t[1]][k], points[t[2]][k]});
        if (sHigh < tLow) return true;
    }
    return false;
}

} // namespace

bool
trianglesMeet(const PointArray& points, const openvdb::Vec3I& s, const openvdb::Vec3I& t)
{
    if (boxesApart(points, s, t)) return false;
    // The tests take the first triangle's plane: in one order, whichever comes first, so
    // that a pair meets or not the same way for every caller (nearly coplanar pairs differed).
    const bool tFirst = std::lexicographical_compare(t.asPointer(), t.asPointer() + 3,
                                                     s.asPointer(), s.asPointer() + 3);
    const openvdb::Vec3I &u = tFirst ? t : s, &w = tFirst ? s : t;
    CornerTriangle first = cornerTriangle(points, u, false);
    CornerTriangle second = cornerTriangle(points, w, runsAlongSameWay(u, w));
    if (first.normal.sqrnorm() == 0.0) std::swap(first, second);
    return trianglesTouch(first, second);
}


bool
hasNoArea(const Point& a, const Point& b, const Point& c)
{
    const double longest2 = std::max({(b - a).sqrnorm(), (c - b).sqrnorm(), (a - c).sqrnorm()});
    return ((b - a) % (c - a)).sqrnorm() <= 1e-16 * longest2 * longest2;
}

} // namespace vdbi
