// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/MetaImageReader.h
/// @brief Reads MetaImage label volumes (.mhd header + raw data file, or single-file .mha)
/// into an Int32Grid, streamed slice by slice.

#ifndef VDBI_META_IMAGE_READER_HAS_BEEN_INCLUDED
#define VDBI_META_IMAGE_READER_HAS_BEEN_INCLUDED

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <iosfwd>
#include <string>

namespace vdbi {

/// The integer element types a label volume may have.
enum class MetaElementType { UChar, Char, UShort, Short, UInt, Int };

/// Bytes per element of @a type.
int metaElementBytes(MetaElementType type);
/// The MetaImage name of @a type ("MET_UCHAR", ...).
const char* metaElementTypeName(MetaElementType type);

/// @brief What a MetaImage header says, checked for consistency but not against the data.
struct MetaImageHeader
{
    std::array<std::int32_t, 3> dimSize{{0, 0, 0}};   ///< voxels along x (fastest), y, z
    MetaElementType elementType = MetaElementType::UChar;
    std::array<double, 3> spacing{{1.0, 1.0, 1.0}};   ///< ElementSpacing (or ElementSize)
    std::array<double, 3> offset{{0.0, 0.0, 0.0}};    ///< Offset, Position or Origin
    bool isMSB = false;              ///< BinaryDataByteOrderMSB / ElementByteOrderMSB
    bool isCompressed = false;       ///< CompressedData: a zlib (or gzip) stream
    std::int64_t compressedDataSize = -1; ///< CompressedDataSize; -1 when not given
    /// HeaderSize: bytes to skip at the start of the data file (LOCAL: after the header);
    /// -1: the data are the last bytes of the file.
    std::int64_t headerSize = 0;
    /// ElementDataFile as written: "LOCAL" (any case) or a file name, relative to the header.
    std::string elementDataFile;
    /// Where the header ended in the stream: for LOCAL data, the first data byte.
    std::uint64_t headerBytes = 0;

    bool isLocal() const;
    /// dimSize[0] * dimSize[1] * dimSize[2] (cannot overflow: checked by the parser).
    std::uint64_t voxelCount() const;
    /// voxelCount() times the element size (cannot overflow either).
    std::uint64_t dataBytes() const;
};

/// @brief Parses a MetaImage header from @a in, up to and including its ElementDataFile line.
/// @details Lines are "Key = Value"; keys are matched without regard to case. NDims must be
/// 3, ElementNumberOfChannels 1, TransformMatrix the identity, BinaryData true. Unknown keys
/// are ignored. The stream is left at the first byte after the header, where LOCAL data begin.
/// @param in             the header text (a .mhd file, or the start of a .mha file)
/// @param nameForErrors  leads every error message (usually the file's path)
/// @throw openvdb::IoError    malformed header, missing key, unsupported feature
///                            (ElementDataFile LIST or a file pattern, ASCII data, a rotation)
/// @throw openvdb::TypeError  an element type other than the six integer types
/// @throw openvdb::ValueError DimSize beyond the int32 index range or overflowing in product
MetaImageHeader parseMetaImageHeader(std::istream& in, const std::string& nameForErrors);

/// @brief The label volume of MetaImage file @a path (.mhd with a separate data file, or .mha
/// with ElementDataFile = LOCAL).
/// @details Elements are streamed, one z slice after the other, into the tree: no dense copy
/// of the volume is ever made, and elements equal to 0 (the background) are not stored. The
/// transform is a scale by the spacing followed by a translation by the offset, so that
/// indexToWorld(ijk) = Offset + ijk * ElementSpacing (the voxel centre, as in OpenVDB).
/// Compressed data are a zlib stream read to DimSize's worth of elements; CompressedDataSize
/// is not trusted (files in the wild get it wrong) and bytes after the stream are ignored.
/// @throw openvdb::IoError    missing, empty, truncated or malformed file (the message starts
///                            with @a path)
/// @throw openvdb::TypeError  unsupported element type
/// @throw openvdb::ValueError DimSize too large; a MET_UINT element beyond the int32 range
openvdb::Int32Grid::Ptr readMetaImage(const std::string& path);

} // namespace vdbi

#endif // VDBI_META_IMAGE_READER_HAS_BEEN_INCLUDED
