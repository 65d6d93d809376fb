// SPDX-License-Identifier: Apache-2.0

#include <vdbi/FoldGuard.h>

#include <cmath>

namespace vdbi {

namespace {

/// Cosines of the turn between neighbouring triangles' normals beyond which an operation's
/// result is tested for crossings (folds need one). A sharp turn, over 120 degrees, is
/// enough for moves, for the first round's collapses of the staircase towards halved targets
/// (it turns by right angles at every step) and for operations at the patch boundary.
/// Elsewhere a collapse or flip at a right-angled crease can fold its fan through the faces
/// beyond the crease with no turn over 120 degrees: creases are tested from 60 degrees on
/// (menger at 4 voxels: 44 pairs of its one patch crossing with 120, none with 60). At the
/// boundary 60 refuses collapses that leave slivers along a curve for separation (frog at 4
/// voxels: 2 pairs of patches crossing there, none with 120).
const double SHARP_TURN_COS = std::cos(120.0 * M_PI / 180.0);
const double CREASE_TURN_COS = std::cos(60.0 * M_PI / 180.0);

} // namespace

CornerTriangle
FoldGuard::cornerTriangle(FaceHandle f) const
{
    auto it = mMesh.cfv_iter(f);
    const VertexHandle a = *it, b = *++it, c = *++it;
    return {mMesh.point(a), mMesh.point(b), mMesh.point(c), a.idx(), b.idx(), c.idx()};
}

CornerTriangle
FoldGuard::cornerTriangle(FaceHandle f, const std::vector<Point>& at) const
{
    auto it = mMesh.cfv_iter(f);
    const int a = (*it).idx(), b = (*++it).idx(), c = (*++it).idx();
    return {at[a], at[b], at[c], a, b, c};
}

void
FoldGuard::clear()
{
    mNewTriangles.clear();
    mNeighbours.clear();
    mNeighbourOf.clear();
}

bool
FoldGuard::touchesBoundary() const
{
    for (const CornerTriangle& t : mNewTriangles) {
        for (const int id : t.id) {
            if (id >= 0 && mMesh.is_boundary(VertexHandle(id))) return true;
        }
    }
    return false;
}

void
FoldGuard::addAcross(FaceHandle f, VertexHandle a, VertexHandle b)
{
    for (const auto g : mMesh.fh_range(f)) {
        const VertexHandle from = mMesh.from_vertex_handle(g), to = mMesh.to_vertex_handle(g);
        if (from == a || from == b || to == a || to == b) continue;
        const FaceHandle o = mMesh.opposite_face_handle(g);
        if (o.is_valid()) addNeighbour(o, int(mNewTriangles.size()) - 1);
        return;
    }
}

void
FoldGuard::addNeighbour(FaceHandle f, int k)
{
    mNeighbours.push_back(cornerTriangle(f));
    mNeighbourOf.push_back(k);
}

template<typename Vertices>
void
FoldGuard::collectAroundAll(const Vertices& near, const std::vector<FaceHandle>& skip)
{
    if (mFaceMark.size() < mMesh.n_faces()) mFaceMark.resize(mMesh.n_faces(), 0);
    ++mMark;
    for (const FaceHandle f : skip) mFaceMark[f.idx()] = mMark;
    mAroundFaces.clear();
    auto addFacesAt = [&](VertexHandle w) {
        for (const FaceHandle f : mMesh.vf_range(w)) {
            if (mFaceMark[f.idx()] == mMark) continue;
            mFaceMark[f.idx()] = mMark;
            mAroundFaces.push_back(f);
        }
    };
    for (const VertexHandle v : near) {
        addFacesAt(v);
        for (const VertexHandle w : mMesh.vv_range(v)) addFacesAt(w);
    }
    mAroundTriangles.clear();
    for (const FaceHandle f : mAroundFaces) mAroundTriangles.push_back(cornerTriangle(f));
}

void
FoldGuard::collectAround(std::initializer_list<VertexHandle> near,
                         const std::vector<FaceHandle>& skip)
{
    collectAroundAll(near, skip);
}

bool
FoldGuard::foldsMore(std::initializer_list<VertexHandle> near,
                     const std::vector<FaceHandle>& replaced, int centre, bool neighboursOnly)
{
    bool embedded = false;
    const double turnCos =
        neighboursOnly || touchesBoundary() ? SHARP_TURN_COS : CREASE_TURN_COS;
    if (looksUnfolded(mNewTriangles, mNeighbours, mNeighbourOf, centre, turnCos, mSuspect,
                      &embedded)) {
        return false;
    }
    if (!neighboursOnly) {
        collectAround(near, replaced);
    }
    const std::vector<CornerTriangle>& around = neighboursOnly ? mNeighbours : mAroundTriangles;
    const int after = countCrossings(mNewTriangles, around, &mSuspect, embedded);
    if (after == 0) return false;
    mOldTriangles.clear();
    for (const FaceHandle f : replaced) mOldTriangles.push_back(cornerTriangle(f));
    return after > countCrossings(mOldTriangles, around);
}

bool
FoldGuard::movedIntoFold(VertexHandle v, const std::vector<Point>& before)
{
    mFan.assign(mMesh.cvf_begin(v), mMesh.cvf_end(v));
    clear();
    for (const FaceHandle f : mFan) {
        addNew(cornerTriangle(f));
        addAcross(f, v, v);
    }
    bool embedded = false;
    if (looksUnfolded(mNewTriangles, mNeighbours, mNeighbourOf, v.idx(), SHARP_TURN_COS,
                      mSuspect, &embedded)) {
        return false;
    }
    collectAround({v}, mFan);
    const int after = countCrossings(mNewTriangles, mAroundTriangles, &mSuspect, embedded);
    if (after == 0) return false;
    // The same triangles where they were.
    mOldTriangles.clear();
    for (const FaceHandle f : mFan) mOldTriangles.push_back(cornerTriangle(f, before));
    mAroundTriangles.clear();
    for (const FaceHandle f : mAroundFaces) mAroundTriangles.push_back(cornerTriangle(f, before));
    return after > countCrossings(mOldTriangles, mAroundTriangles);
}

int
FoldGuard::fanCrossings(VertexHandle v)
{
    mFan.assign(mMesh.cvf_begin(v), mMesh.cvf_end(v));
    mNewTriangles.clear();
    for (const FaceHandle f : mFan) mNewTriangles.push_back(cornerTriangle(f));
    mRing.assign(mMesh.cvv_begin(v), mMesh.cvv_end(v));
    collectAroundAll(mRing, mFan);
    // Touching counts, as in separation: a fan laid onto a face is no better than through it.
    int count = 0;
    for (std::size_t i = 0; i < mNewTriangles.size(); ++i) {
        for (const CornerTriangle& t : mAroundTriangles) {
            count += trianglesTouch(mNewTriangles[i], t);
        }
        for (std::size_t j = i + 1; j < mNewTriangles.size(); ++j) {
            count += trianglesTouch(mNewTriangles[i], mNewTriangles[j]);
        }
    }
    return count;
}

} // namespace vdbi
