// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/VdbReader.h
/// @brief Reads the label grid of a .vdb file, converting integer-valued grids exactly.

#ifndef VDBI_VDB_READER_HAS_BEEN_INCLUDED
#define VDBI_VDB_READER_HAS_BEEN_INCLUDED

#include <openvdb/openvdb.h>

#include <string>

namespace vdbi {

/// @brief The label grid of the OpenVDB file @a path.
/// @details Without @a gridName, the first Int32Grid of the file (in file order); if there is
/// none, the first grid of another integer-valued type. A grid of another type is converted
/// only where no value changes: an Int64Grid whose values all fit int32, a BoolGrid (false 0,
/// true 1), a FloatGrid or DoubleGrid whose every value (active and inactive voxels, tiles,
/// background) is an exact integer in the int32 range. Tiles, active states, the background
/// value, the transform and the name are kept. An Int32Grid is returned as read, with its metadata.
/// Every grid of the file is read (no delayed loading), so that a truncated file fails here
/// and not in a later stage. Calls openvdb::initialize().
/// @param path      the .vdb file
/// @param gridName  the grid to read; empty: the first usable one. Several grids of the same
///                  name: the first of them.
/// @throw openvdb::IoError    missing, empty, truncated or malformed file (the message starts
///                            with @a path; OpenVDB's own errors are rethrown this way)
/// @throw openvdb::TypeError  no grid of a usable type (the message lists the names and types
///                            found), or a value that is not an exact int32 (the message
///                            names the grid and the first such value)
/// @throw openvdb::ValueError no grid named @a gridName (the message lists the grids found);
///                            tiles that as voxels (4 bytes each) would exceed the machine's
///                            memory (the message names the voxel count)
openvdb::Int32Grid::Ptr readVdb(const std::string& path,
                                const std::string& gridName = std::string());

} // namespace vdbi

#endif // VDBI_VDB_READER_HAS_BEEN_INCLUDED
