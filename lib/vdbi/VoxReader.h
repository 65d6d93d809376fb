// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/VoxReader.h
/// @brief Reads MagicaVoxel .vox files (format versions 150 and 200) into an Int32Grid.

#ifndef VDBI_VOX_READER_HAS_BEEN_INCLUDED
#define VDBI_VOX_READER_HAS_BEEN_INCLUDED

#include <openvdb/openvdb.h>

#include <cstddef>
#include <string>

namespace vdbi {

/// @brief The first model of the MagicaVoxel file @a path as labels.
/// @details Every voxel of the model becomes an active voxel whose value is its palette index
/// (1..255); empty space is the background 0 and is not stored. The file's x, y, z (z up)
/// are the grid's x, y, z; the transform is the identity (unit voxels). Only the first
/// SIZE/XYZI pair is read: files with several models (a PACK chunk, or the scene graph of
/// newer files) give their first model. The palette (RGBA), materials, the scene graph and
/// unknown chunks are skipped by their sizes.
/// @throw openvdb::IoError  missing, empty, truncated or malformed file; the message starts
///                          with @a path
openvdb::Int32Grid::Ptr readVox(const std::string& path);

/// @brief readVox() on the bytes of a file already in memory (for fuzzing and embedding).
/// @param data           the whole file
/// @param size           number of bytes at @a data
/// @param nameForErrors  leads every error message (usually the file's path)
/// @throw openvdb::IoError  truncated or malformed data
openvdb::Int32Grid::Ptr readVoxBuffer(const unsigned char* data, std::size_t size,
                                      const std::string& nameForErrors);

} // namespace vdbi

#endif // VDBI_VOX_READER_HAS_BEEN_INCLUDED
