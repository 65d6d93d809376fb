// SPDX-License-Identifier: Apache-2.0

#include <vdbi/LabelVolumeReader.h>

#include <vdbi/MetaImageReader.h>
#include <vdbi/VdbReader.h>
#include <vdbi/VoxReader.h>

#include <openvdb/Exceptions.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace vdbi {

openvdb::Int32Grid::Ptr
readLabelVolume(const std::string& path, const ReadOptions& options)
{
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
        [](unsigned char c) { return char(std::tolower(c)); });

    if (extension == ".vdb") return readVdb(path, options.gridName);

    // A grid name that would be silently ignored hides a user's mistake.
    if (!options.gridName.empty()) {
        OPENVDB_THROW(openvdb::ValueError, path << ": a grid name ('" << options.gridName
            << "') applies to .vdb files only");
    }
    if (extension == ".vox") return readVox(path);
    if (extension == ".mhd" || extension == ".mha") return readMetaImage(path);
    OPENVDB_THROW(openvdb::ValueError, path << ": unknown extension"
        << (extension.empty() ? std::string(" (none)") : " '" + extension + "'")
        << "; label volumes are .vdb, .vox, .mhd or .mha");
}

} // namespace vdbi
