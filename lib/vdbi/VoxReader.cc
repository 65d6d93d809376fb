// SPDX-License-Identifier: Apache-2.0

#include <vdbi/VoxReader.h>

#include <openvdb/Exceptions.h>

#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace vdbi {

namespace {

constexpr std::size_t HEADER_BYTES = 8;        // "VOX " + int32 version
constexpr std::size_t CHUNK_HEADER_BYTES = 12; // id + content size + children size

/// A chunk whose header has been checked: its content and children lie inside its parent.
struct Chunk
{
    std::string id;            ///< printable form of the four id bytes
    std::size_t offset = 0;    ///< of the chunk header in the file
    std::size_t content = 0;   ///< offset of the content
    std::size_t contentSize = 0;
    std::size_t children = 0;  ///< offset of the first child
    std::size_t end = 0;       ///< one past the last byte of the children
};

/// Chunk ids are four ASCII letters in valid files; anything else is shown escaped so that a
/// damaged file gives a readable message.
std::string
printableId(const unsigned char* bytes)
{
    std::ostringstream os;
    for (int i = 0; i < 4; ++i) {
        if (std::isprint(bytes[i])) {
            os << char(bytes[i]);
        } else {
            static const char* const HEX = "0123456789abcdef";
            os << "\\x" << HEX[bytes[i] >> 4] << HEX[bytes[i] & 15];
        }
    }
    return os.str();
}

class VoxParser
{
public:
    VoxParser(const unsigned char* data, std::size_t size, const std::string& name)
        : mData(data), mSize(size), mName(name) {}

    openvdb::Int32Grid::Ptr parse()
    {
        this->checkHeader();
        if (mSize - HEADER_BYTES < CHUNK_HEADER_BYTES) {
            OPENVDB_THROW(openvdb::IoError, mName << ": truncated: no MAIN chunk after the "
                "header (" << mSize << " bytes in the file)");
        }
        const Chunk main = this->readChunkHeader(HEADER_BYTES, mSize, "");
        if (main.id != "MAIN") {
            OPENVDB_THROW(openvdb::IoError, mName << ": expects the MAIN chunk after the "
                "header, found '" << main.id << "'");
        }
        // Bytes after MAIN are ignored, as MagicaVoxel does.
        for (std::size_t offset = main.children; offset < main.end;) {
            const Chunk chunk = this->readChunkHeader(offset, main.end, "MAIN");
            this->readChunk(chunk);
            offset = chunk.end;
        }
        if (!mHasSize) {
            OPENVDB_THROW(openvdb::IoError, mName << ": no SIZE chunk (the file holds no model)");
        }
        if (!mHasVoxels) {
            OPENVDB_THROW(openvdb::IoError, mName << ": no XYZI chunk after the SIZE chunk");
        }
        return mGrid;
    }

private:
    std::int32_t int32At(std::size_t offset) const
    {
        // Little-endian whatever the host is; the callers have checked the bounds.
        const unsigned char* p = mData + offset;
        const std::uint32_t u = std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8)
            | (std::uint32_t(p[2]) << 16) | (std::uint32_t(p[3]) << 24);
        std::int32_t value;
        std::memcpy(&value, &u, sizeof(value));
        return value;
    }

    void checkHeader() const
    {
        if (mSize == 0) OPENVDB_THROW(openvdb::IoError, mName << ": is empty");
        if (mSize < HEADER_BYTES) {
            OPENVDB_THROW(openvdb::IoError, mName << ": truncated: " << mSize
                << " bytes are too few for a .vox header");
        }
        if (std::memcmp(mData, "VOX ", 4) != 0) {
            OPENVDB_THROW(openvdb::IoError, mName << ": bad magic '" << printableId(mData)
                << "': not a MagicaVoxel .vox file (expects 'VOX ')");
        }
        const std::int32_t version = this->int32At(4);
        if (version != 150 && version != 200) {
            OPENVDB_THROW(openvdb::IoError, mName << ": unsupported .vox version " << version
                << " (expects 150 or 200)");
        }
    }

    /// @param parent  id of the enclosing chunk, empty for the file itself
    Chunk readChunkHeader(std::size_t offset, std::size_t parentEnd,
                          const std::string& parent) const
    {
        const std::size_t left = parentEnd - offset;
        if (left < CHUNK_HEADER_BYTES) {
            OPENVDB_THROW(openvdb::IoError, mName << ": truncated chunk header at byte " << offset
                << " (needs " << CHUNK_HEADER_BYTES << " bytes, " << left << " left in "
                << (parent.empty() ? std::string("the file") : "chunk " + parent) << ")");
        }
        Chunk chunk;
        chunk.id = printableId(mData + offset);
        chunk.offset = offset;
        const std::int32_t contentSize = this->int32At(offset + 4);
        const std::int32_t childrenSize = this->int32At(offset + 8);
        if (contentSize < 0 || childrenSize < 0) {
            OPENVDB_THROW(openvdb::IoError, mName << ": chunk '" << chunk.id << "' at byte "
                << offset << " has a negative size (content " << contentSize << ", children "
                << childrenSize << ")");
        }
        // Sums in 64 bits: two int32 sizes cannot overflow them.
        const std::uint64_t needed = std::uint64_t(contentSize) + std::uint64_t(childrenSize);
        if (needed > left - CHUNK_HEADER_BYTES) {
            if (parent.empty()) {
                OPENVDB_THROW(openvdb::IoError, mName << ": truncated: chunk '" << chunk.id
                    << "' at byte " << offset << " declares " << needed << " bytes of content"
                    " and children, " << (left - CHUNK_HEADER_BYTES) << " left in the file");
            }
            OPENVDB_THROW(openvdb::IoError, mName << ": chunk '" << chunk.id << "' at byte "
                << offset << " declares " << needed << " bytes of content and children, "
                << (left - CHUNK_HEADER_BYTES) << " left in its parent chunk " << parent
                << " (bad chunk size or truncated file)");
        }
        chunk.content = offset + CHUNK_HEADER_BYTES;
        chunk.contentSize = std::size_t(contentSize);
        chunk.children = chunk.content + chunk.contentSize;
        chunk.end = chunk.children + std::size_t(childrenSize);
        return chunk;
    }

    void requireContent(const Chunk& chunk, std::size_t bytes) const
    {
        if (chunk.contentSize < bytes) {
            OPENVDB_THROW(openvdb::IoError, mName << ": truncated " << chunk.id << " chunk at byte "
                << chunk.offset << " (expects " << bytes << " bytes of content, holds "
                << chunk.contentSize << ")");
        }
    }

    void readChunk(const Chunk& chunk)
    {
        if (chunk.id == "PACK") {
            this->requireContent(chunk, 4);
            const std::int32_t models = this->int32At(chunk.content);
            if (models < 1) {
                OPENVDB_THROW(openvdb::IoError, mName << ": PACK chunk at byte " << chunk.offset
                    << " declares " << models << " models");
            }
        } else if (chunk.id == "SIZE") {
            if (mHasVoxels) return; // a later model: only the first one is read
            if (mHasSize) {
                OPENVDB_THROW(openvdb::IoError, mName << ": SIZE chunk at byte " << chunk.offset
                    << " follows another SIZE chunk without an XYZI chunk between them");
            }
            this->requireContent(chunk, 12);
            for (int axis = 0; axis < 3; ++axis) {
                mModelSize[axis] = this->int32At(chunk.content + 4 * axis);
            }
            if (mModelSize[0] < 1 || mModelSize[1] < 1 || mModelSize[2] < 1) {
                OPENVDB_THROW(openvdb::IoError, mName << ": SIZE chunk at byte " << chunk.offset
                    << " gives a model size " << mModelSize[0] << " x " << mModelSize[1]
                    << " x " << mModelSize[2] << " (every size must be positive)");
            }
            mHasSize = true;
        } else if (chunk.id == "XYZI") {
            if (mHasVoxels) return;
            if (!mHasSize) {
                OPENVDB_THROW(openvdb::IoError, mName << ": XYZI chunk at byte " << chunk.offset
                    << " comes before any SIZE chunk");
            }
            this->readVoxels(chunk);
            mHasVoxels = true;
        }
        // RGBA, MATL, MATT, nTRN, nGRP, nSHP, LAYR, rOBJ, rCAM, NOTE, IMAP and unknown ids:
        // nothing a label volume needs.
    }

    void readVoxels(const Chunk& chunk)
    {
        this->requireContent(chunk, 4);
        const std::int32_t count = this->int32At(chunk.content);
        if (count < 0) {
            OPENVDB_THROW(openvdb::IoError, mName << ": XYZI chunk at byte " << chunk.offset
                << " has a negative voxel count " << count);
        }
        const std::uint64_t bytes = 4 * std::uint64_t(count);
        if (bytes > chunk.contentSize - 4) {
            OPENVDB_THROW(openvdb::IoError, mName << ": truncated XYZI chunk at byte "
                << chunk.offset << ": voxel count " << count << " expects " << bytes
                << " bytes, " << (chunk.contentSize - 4) << " left in the chunk");
        }
        auto accessor = mGrid->getAccessor();
        const unsigned char* voxel = mData + chunk.content + 4;
        for (std::int32_t n = 0; n < count; ++n, voxel += 4) {
            const int x = voxel[0], y = voxel[1], z = voxel[2], colorIndex = voxel[3];
            if (x >= mModelSize[0] || y >= mModelSize[1] || z >= mModelSize[2]) {
                OPENVDB_THROW(openvdb::IoError, mName << ": voxel " << n << " of the XYZI chunk"
                    " at (" << x << ", " << y << ", " << z << ") lies outside the model SIZE "
                    << mModelSize[0] << " x " << mModelSize[1] << " x " << mModelSize[2]);
            }
            // Index 0 is "empty" in the format: the background, which is never stored.
            if (colorIndex != 0) accessor.setValue(openvdb::Coord(x, y, z), colorIndex);
        }
    }

    const unsigned char* mData;
    std::size_t mSize;
    const std::string& mName;
    bool mHasSize = false;
    bool mHasVoxels = false;
    std::int32_t mModelSize[3] = {0, 0, 0};
    openvdb::Int32Grid::Ptr mGrid = openvdb::Int32Grid::create(/*background=*/0);
};

} // namespace

openvdb::Int32Grid::Ptr
readVoxBuffer(const unsigned char* data, std::size_t size, const std::string& nameForErrors)
{
    if (data == nullptr && size != 0) {
        OPENVDB_THROW(openvdb::IoError, nameForErrors << ": no data (null buffer)");
    }
    return VoxParser(data, size, nameForErrors).parse();
}

openvdb::Int32Grid::Ptr
readVox(const std::string& path)
{
    namespace fs = std::filesystem;
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    if (!fs::exists(status)) OPENVDB_THROW(openvdb::IoError, path << ": no such file");
    if (fs::is_directory(status)) {
        OPENVDB_THROW(openvdb::IoError, path << ": is a directory, not a file");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        OPENVDB_THROW(openvdb::IoError, path << ": cannot open for reading ("
            << std::strerror(errno) << ")");
    }
    // The header first, so that a large file of another kind is not read whole.
    std::vector<unsigned char> bytes(HEADER_BYTES);
    in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
    bytes.resize(std::size_t(in.gcount()));
    if (bytes.size() < HEADER_BYTES || std::memcmp(bytes.data(), "VOX ", 4) != 0) {
        return readVoxBuffer(bytes.data(), bytes.size(), path); // throws
    }
    // Then the whole file: a .vox holds a few models of at most 4 bytes per voxel.
    bytes.insert(bytes.end(), std::istreambuf_iterator<char>(in),
                 std::istreambuf_iterator<char>());
    if (in.bad()) OPENVDB_THROW(openvdb::IoError, path << ": read error");
    return readVoxBuffer(bytes.data(), bytes.size(), path);
}

} // namespace vdbi
