// SPDX-License-Identifier: Apache-2.0

#include <vdbi/FoldGuard.h>

#include <gtest/gtest.h>

#include <vector>

class TestFoldGuard : public ::testing::Test {};

namespace {

using vdbi::CornerTriangle;
using vdbi::TriMesh;
using Point = TriMesh::Point;
using VertexHandle = TriMesh::VertexHandle;
using FaceHandle = TriMesh::FaceHandle;

/// The flat 3 x 3 grid of points (x, y, 0), point y * 3 + x, each square cut along its
/// diagonal from (x, y) to (x + 1, y + 1): point 4 is the centre of a fan of six triangles.
struct Grid
{
    TriMesh mesh;
    std::vector<FaceHandle> faces;   ///< in the order they were added

    Grid()
    {
        for (int y = 0; y < 3; ++y) {
            for (int x = 0; x < 3; ++x) mesh.add_vertex(Point(x, y, 0));
        }
        for (int y = 0; y < 2; ++y) {
            for (int x = 0; x < 2; ++x) {
                const VertexHandle a(y * 3 + x), b(a.idx() + 1), c(a.idx() + 4), d(a.idx() + 3);
                faces.push_back(mesh.add_face(a, b, c));
                faces.push_back(mesh.add_face(a, c, d));
            }
        }
    }
    std::vector<Point> points() const
    {
        std::vector<Point> p;
        for (const VertexHandle v : mesh.vertices()) p.push_back(mesh.point(v));
        return p;
    }
    /// The fold guard's verdict on flipping the diagonal from point 4 to point 8 (faces 6
    /// and 7: (4, 5, 8) and (4, 8, 7) become (4, 5, 7) and (5, 8, 7)).
    bool flipFolds()
    {
        vdbi::FoldGuard guard(mesh);
        guard.clear();
        auto p = [&](int i) { return mesh.point(VertexHandle(i)); };
        guard.addNew(CornerTriangle(p(4), p(5), p(7), 4, 5, 7));
        guard.addNew(CornerTriangle(p(5), p(8), p(7), 5, 8, 7));
        guard.addNeighbour(faces[3], 0);   // (1, 5, 4) across side 4-5
        guard.addNeighbour(faces[4], 0);   // (3, 4, 7) across side 7-4
        return guard.foldsMore({VertexHandle(4), VertexHandle(5), VertexHandle(8),
                                VertexHandle(7)}, {faces[6], faces[7]}, -1, false);
    }
};

} // namespace


TEST_F(TestFoldGuard, testMovedIntoFold)
{
    const VertexHandle centre(4);
    Grid grid;
    const std::vector<Point> before = grid.points();
    vdbi::FoldGuard guard(grid.mesh);
    // Within its ring, in the plane or lifted out of it: no fold.
    grid.mesh.set_point(centre, Point(1.2, 0.9, 0.0));
    EXPECT_FALSE(guard.movedIntoFold(centre, before));
    grid.mesh.set_point(centre, Point(1.0, 1.0, 0.7));
    EXPECT_FALSE(guard.movedIntoFold(centre, before));
    // Past the edge of its ring: its fan folds over the face beyond, (1, 2, 5).
    grid.mesh.set_point(centre, Point(2.6, 0.8, 0.0));
    EXPECT_TRUE(guard.movedIntoFold(centre, before));
    // Where it was folded already, staying is not folding more.
    EXPECT_FALSE(guard.movedIntoFold(centre, grid.points()));
}

TEST_F(TestFoldGuard, testFanCrossings)
{
    const VertexHandle centre(4);
    Grid grid;
    vdbi::FoldGuard guard(grid.mesh);
    // Flat, or lifted out of the plane: nothing crosses.
    EXPECT_EQ(guard.fanCrossings(centre), 0);
    grid.mesh.set_point(centre, Point(1.0, 1.0, 0.7));
    EXPECT_EQ(guard.fanCrossings(centre), 0);
    // Past the edge of its ring, in the plane: its fan overlaps the face beyond, (1, 2, 5),
    // and its own triangles overlap each other.
    grid.mesh.set_point(centre, Point(2.6, 0.8, 0.0));
    EXPECT_GT(guard.fanCrossings(centre), 0);
    // Onto the corner (1, 0) of its ring: two of its triangles lose their area and touch the
    // others (touching counts).
    grid.mesh.set_point(centre, Point(1.0, 0.0, 0.0));
    EXPECT_GT(guard.fanCrossings(centre), 0);
    // A corner of the ring moved, not the centre: the faces around are read as they are now.
    grid.mesh.set_point(centre, Point(1.0, 1.0, 0.0));
    grid.mesh.set_point(VertexHandle(5), Point(0.5, 1.0, 0.0));
    EXPECT_GT(guard.fanCrossings(centre), 0);
}

TEST_F(TestFoldGuard, testFlip)
{
    // Flipping the diagonal of a convex square folds nothing; of a dart (point 8 pulled
    // inside triangle (4, 5, 7)), the new triangle (5, 8, 7) lies folded onto (4, 5, 7).
    Grid grid;
    EXPECT_FALSE(grid.flipFolds());
    grid.mesh.set_point(VertexHandle(8), Point(1.3, 1.3, 0.0));
    EXPECT_TRUE(grid.flipFolds());
}

TEST_F(TestFoldGuard, testCornerTriangle)
{
    Grid grid;
    vdbi::FoldGuard guard(grid.mesh);
    const CornerTriangle t = guard.cornerTriangle(grid.faces[6]);
    EXPECT_EQ(t.id[0], 4);
    EXPECT_EQ(t.id[1], 5);
    EXPECT_EQ(t.id[2], 8);
    EXPECT_EQ(t.p[2], Point(2, 2, 0));
    EXPECT_GT(t.normal[2], 0.0);
    std::vector<Point> at = grid.points();
    at[8] = Point(5, 6, 7);
    EXPECT_EQ(guard.cornerTriangle(grid.faces[6], at).p[2], Point(5, 6, 7));
}
