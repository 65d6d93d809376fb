// SPDX-License-Identifier: Apache-2.0

#include "support/HandMadeGrids.h"

#include <openvdb/Exceptions.h>

namespace vdbi_test {

using openvdb::Coord;
using vdbi::Label;

openvdb::Int32Grid::Ptr
gridFromDense(int nx, int ny, int nz, const std::vector<Label>& labels, const Coord& origin,
              Label background)
{
    if (nx < 0 || ny < 0 || nz < 0
        || labels.size() != std::size_t(nx) * std::size_t(ny) * std::size_t(nz)) {
        OPENVDB_THROW(openvdb::ValueError, "gridFromDense: " << labels.size()
            << " labels for " << nx << " x " << ny << " x " << nz << " voxels");
    }
    openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(background);
    auto acc = grid->getAccessor();
    std::size_t n = 0;
    for (int z = 0; z < nz; ++z) {
        for (int y = 0; y < ny; ++y) {
            for (int x = 0; x < nx; ++x, ++n) {
                if (labels[n] != background) {
                    acc.setValueOn(origin + Coord(x, y, z), labels[n]);
                }
            }
        }
    }
    return grid;
}

namespace {

openvdb::Int32Grid::Ptr
gridFromVoxels(const std::vector<std::pair<Coord, Label>>& voxels)
{
    openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(0);
    auto acc = grid->getAccessor();
    for (const auto& v : voxels) acc.setValueOn(v.first, v.second);
    return grid;
}

} // namespace

openvdb::Int32Grid::Ptr
singleVoxel()
{
    return gridFromVoxels({{Coord(0, 0, 0), 1}});
}

openvdb::Int32Grid::Ptr
twoVoxelsSharingEdge()
{
    return gridFromVoxels({{Coord(0, 0, 0), 1}, {Coord(1, 1, 0), 1}});
}

openvdb::Int32Grid::Ptr
twoVoxelsSharingVertex()
{
    return gridFromVoxels({{Coord(0, 0, 0), 1}, {Coord(1, 1, 1), 1}});
}

openvdb::Int32Grid::Ptr
antipodalPair2x2x2()
{
    return gridFromVoxels({{Coord(1, 0, 0), 1}, {Coord(0, 1, 1), 1}});
}

openvdb::Int32Grid::Ptr
antipodalSix()
{
    // x fastest: (0,0,0) and (1,1,1) are entries 0 and 7.
    return gridFromDense(2, 2, 2, {0, 1, 1, 1, 1, 1, 1, 0});
}

openvdb::Int32Grid::Ptr
checkerboard2x2()
{
    return gridFromDense(2, 2, 1, {1, 2, 2, 1});
}

namespace {

openvdb::Int32Grid::Ptr
shell(Label holeLabel)
{
    std::vector<Label> labels(125, 1);
    for (int z = 1; z <= 3; ++z) {
        for (int y = 1; y <= 3; ++y) {
            for (int x = 1; x <= 3; ++x) labels[x + 5 * (y + 5 * z)] = holeLabel;
        }
    }
    return gridFromDense(5, 5, 5, labels);
}

} // namespace

openvdb::Int32Grid::Ptr
hollowShell()
{
    return shell(0);
}

openvdb::Int32Grid::Ptr
hollowShellFilled()
{
    return shell(2);
}

openvdb::Int32Grid::Ptr
torusRing()
{
    return gridFromDense(3, 3, 1, {1, 1, 1, 1, 0, 1, 1, 1, 1});
}

openvdb::Int32Grid::Ptr
tJunction3()
{
    // Per z layer (x fastest): (0,0)=1 (1,0)=2 (0,1)=3 (1,1)=3.
    return gridFromDense(2, 2, 2, {1, 2, 3, 3, 1, 2, 3, 3});
}

openvdb::Int32Grid::Ptr
corner4()
{
    // Per z layer (x fastest): (0,0)=1 (1,0)=2 (0,1)=4 (1,1)=3.
    return gridFromDense(2, 2, 2, {1, 2, 4, 3, 1, 2, 4, 3});
}

openvdb::Int32Grid::Ptr
activeTileGrid()
{
    openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(0);
    // Level 1 is the lowest internal node: its tiles are leaf-sized, 8^3 voxels.
    grid->tree().addTile(/*level=*/1, Coord(0, 0, 0), 3, /*active=*/true);
    grid->tree().setValueOn(Coord(8, 8, 0), 5);
    return grid;
}

std::vector<HandMadeCase>
handMadeCases()
{
    using Pair = std::pair<Label, Label>;
    std::vector<HandMadeCase> cases;
    auto add = [&](const std::string& name, openvdb::Int32Grid::Ptr grid, std::size_t edges,
                   std::size_t vertices, std::size_t singular, Label dominant,
                   std::map<Pair, std::size_t> faces) {
        HandMadeCase c;
        c.name = name;
        c.grid = grid;
        c.criticalEdges = edges;
        c.criticalVertices = vertices;
        c.singularVertices = singular;
        c.dominant = dominant;
        c.faces = std::move(faces);
        cases.push_back(std::move(c));
    };
    add("singleVoxel", singleVoxel(), 0, 0, 0, 0, {{{0, 1}, 6}});
    add("twoVoxelsSharingEdge", twoVoxelsSharingEdge(), 1, 2, 0, 0, {{{0, 1}, 12}});
    add("twoVoxelsSharingVertex", twoVoxelsSharingVertex(), 0, 1, 1, 0, {{{0, 1}, 12}});
    add("antipodalPair2x2x2", antipodalPair2x2x2(), 0, 1, 1, 0, {{{0, 1}, 12}});
    add("antipodalSix", antipodalSix(), 0, 1, 1, 0, {{{0, 1}, 24}});
    add("checkerboard2x2", checkerboard2x2(), 1, 2, 0, 1,
        {{{0, 1}, 8}, {{0, 2}, 8}, {{1, 2}, 4}});
    add("hollowShell", hollowShell(), 0, 0, 0, 0, {{{0, 1}, 204}});
    add("hollowShellFilled", hollowShellFilled(), 0, 0, 0, 0, {{{0, 1}, 150}, {{1, 2}, 54}});
    add("torusRing", torusRing(), 0, 0, 0, 0, {{{0, 1}, 32}});
    add("tJunction3", tJunction3(), 0, 0, 0, 0,
        {{{0, 1}, 6}, {{0, 2}, 6}, {{0, 3}, 12}, {{1, 2}, 2}, {{1, 3}, 2}, {{2, 3}, 2}});
    add("corner4", corner4(), 0, 0, 0, 0,
        {{{0, 1}, 6}, {{0, 2}, 6}, {{0, 3}, 6}, {{0, 4}, 6},
         {{1, 2}, 2}, {{1, 4}, 2}, {{2, 3}, 2}, {{3, 4}, 2}});
    add("activeTileGrid", activeTileGrid(), 1, 2, 0, 0, {{{0, 3}, 384}, {{0, 5}, 6}});
    return cases;
}

} // namespace vdbi_test
