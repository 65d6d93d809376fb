// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/LabelVolumeReader.h
/// @brief Reads a label volume file (.vdb, .vox, .mhd/.mha) into an Int32Grid.

#ifndef VDBI_LABEL_VOLUME_READER_HAS_BEEN_INCLUDED
#define VDBI_LABEL_VOLUME_READER_HAS_BEEN_INCLUDED

#include <openvdb/openvdb.h>

#include <string>

namespace vdbi {

struct ReadOptions
{
    /// .vdb only: the grid to read; empty reads the first Int32 grid.
    std::string gridName;
};

/// @brief Reads labels from @a path, the format chosen by its extension.
/// @details The result's background value is the label of everything not stored (0 for .vox
/// and MetaImage), its transform holds the file's spacing and origin (voxel centres, as in
/// OpenVDB). Dense inputs are streamed into the tree slice by slice; background voxels are
/// not stored.
/// @throw openvdb::IoError  unreadable, truncated or malformed file (the message names it)
/// @throw openvdb::TypeError  no grid of a usable type (the message lists the types found)
/// @throw openvdb::ValueError  sizes beyond what the machine can hold, unknown extension
openvdb::Int32Grid::Ptr readLabelVolume(const std::string& path,
                                        const ReadOptions& options = ReadOptions());

} // namespace vdbi

#endif // VDBI_LABEL_VOLUME_READER_HAS_BEEN_INCLUDED
