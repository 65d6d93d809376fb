// SPDX-License-Identifier: Apache-2.0

#include <vdbi/MetaImageReader.h>

#include <openvdb/Exceptions.h>
#include <openvdb/math/Maps.h>
#include <openvdb/math/Transform.h>

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <istream>
#include <limits>
#include <memory>
#include <vector>

namespace vdbi {

namespace fs = std::filesystem;

namespace {

/// A header line longer than this is not text: the file is not a MetaImage header.
constexpr std::size_t MAX_HEADER_LINE = 65536;
/// Bytes of elements decoded at a time: a bounded buffer, however large a slice is.
constexpr std::size_t BLOCK_BYTES = std::size_t(1) << 20;
/// Compressed bytes read from the file at a time.
constexpr std::size_t INFLATE_INPUT_BYTES = std::size_t(1) << 18;
/// The most a deflate stream can expand (258 bytes per code of at least 2 bits, zlib's FAQ).
constexpr std::uint64_t MAX_DEFLATE_RATIO = 1032;

std::string
toLower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(),
        [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

std::string
trim(const std::string& s)
{
    const auto isSpace = [](unsigned char c) { return std::isspace(c) != 0; };
    auto first = std::find_if_not(s.begin(), s.end(), isSpace);
    auto last = std::find_if_not(s.rbegin(), s.rend(), isSpace).base();
    return first < last ? std::string(first, last) : std::string();
}

std::vector<std::string>
splitWords(const std::string& s)
{
    std::vector<std::string> words;
    std::size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
        std::size_t j = i;
        while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
        if (j > i) words.push_back(s.substr(i, j - i));
        i = j;
    }
    return words;
}

/// Reads the "Key = Value" lines of a header and turns their values into numbers, with every
/// error naming the file, the line and the key.
class HeaderParser
{
public:
    HeaderParser(std::istream& in, const std::string& name): mIn(in), mName(name) {}

    MetaImageHeader parse();

private:
    bool readLine(std::string& line);
    [[noreturn]] void fail(const std::string& problem) const;

    template<typename T> T parseNumber(const std::string& word) const;
    template<typename T> std::vector<T> parseNumbers(std::size_t count) const;
    bool parseBool() const;

    std::istream& mIn;
    const std::string& mName;
    std::uint64_t mBytes = 0;    // consumed so far
    int mLineNumber = 0;
    std::string mKey, mValue;    // of the current line, as written
};

void
HeaderParser::fail(const std::string& problem) const
{
    OPENVDB_THROW(openvdb::IoError, mName << ": header line " << mLineNumber << " ("
        << mKey << "): " << problem);
}

bool
HeaderParser::readLine(std::string& line)
{
    line.clear();
    std::streambuf* buffer = mIn.rdbuf();
    if (buffer == nullptr) return false;
    bool any = false;
    for (;;) {
        const int c = buffer->sbumpc();
        if (c == std::char_traits<char>::eof()) break;
        any = true;
        ++mBytes;
        if (c == '\n') break;
        if (c == '\0') {
            OPENVDB_THROW(openvdb::IoError, mName << ": binary data in the header at line "
                << (mLineNumber + 1) << " before any ElementDataFile line"
                " (not a MetaImage header?)");
        }
        if (line.size() >= MAX_HEADER_LINE) {
            OPENVDB_THROW(openvdb::IoError, mName << ": header line " << (mLineNumber + 1)
                << " is longer than " << MAX_HEADER_LINE << " characters"
                " (not a MetaImage header?)");
        }
        line.push_back(char(c));
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (any) ++mLineNumber;
    return any;
}

template<typename T>
T
HeaderParser::parseNumber(const std::string& word) const
{
    // from_chars: no locale (a decimal comma would break strtod), no partial matches.
    const char* first = word.data();
    const char* last = word.data() + word.size();
    if (first != last && *first == '+') ++first;
    T value{};
    const auto [end, error] = std::from_chars(first, last, value);
    if (error == std::errc::result_out_of_range) {
        OPENVDB_THROW(openvdb::ValueError, mName << ": header line " << mLineNumber << " ("
            << mKey << "): the number " << word << " is out of range");
    }
    if (error != std::errc() || end != last || first == last) {
        this->fail("'" + word + "' is not a number");
    }
    if constexpr (std::is_floating_point<T>::value) {
        if (!std::isfinite(value)) this->fail("'" + word + "' is not a finite number");
    }
    return value;
}

template<typename T>
std::vector<T>
HeaderParser::parseNumbers(std::size_t count) const
{
    const std::vector<std::string> words = splitWords(mValue);
    if (words.size() != count) {
        this->fail("expects " + std::to_string(count) + " values, found "
            + std::to_string(words.size()) + " in '" + mValue + "'");
    }
    std::vector<T> values;
    for (const std::string& word : words) values.push_back(this->parseNumber<T>(word));
    return values;
}

bool
HeaderParser::parseBool() const
{
    const std::string value = toLower(mValue);
    if (value == "true" || value == "1") return true;
    if (value == "false" || value == "0") return false;
    this->fail("'" + mValue + "' is not True or False");
}

bool
parseElementType(const std::string& name, MetaElementType& type)
{
    static const MetaElementType ALL[] = {MetaElementType::UChar, MetaElementType::Char,
        MetaElementType::UShort, MetaElementType::Short, MetaElementType::UInt,
        MetaElementType::Int};
    const std::string lower = toLower(name);
    for (MetaElementType candidate : ALL) {
        if (lower == toLower(metaElementTypeName(candidate))) {
            type = candidate;
            return true;
        }
    }
    return false;
}

/// "name%03d.raw first last step": one file per slice. A single name may hold spaces.
bool
isFilePattern(const std::string& value)
{
    const std::vector<std::string> words = splitWords(value);
    if (words.size() != 4) return false;
    for (std::size_t i = 1; i < 4; ++i) {
        const std::string& word = words[i];
        const std::size_t digits = (word[0] == '-' || word[0] == '+') ? 1 : 0;
        if (word.size() == digits
            || word.find_first_not_of("0123456789", digits) != std::string::npos) {
            return false;
        }
    }
    return true;
}

bool
multiplyChecked(std::uint64_t a, std::uint64_t b, std::uint64_t& product)
{
    if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a) return false;
    product = a * b;
    return true;
}

MetaImageHeader
HeaderParser::parse()
{
    MetaImageHeader header;
    bool hasDimSize = false, hasElementType = false, hasDataFile = false;
    bool hasSpacing = false, hasElementSize = false;
    std::array<double, 3> elementSize{{1.0, 1.0, 1.0}};
    int nDims = 3;

    std::string line;
    while (!hasDataFile && this->readLine(line)) {
        if (trim(line).empty()) continue;
        const std::size_t equals = line.find('=');
        if (equals == std::string::npos) {
            OPENVDB_THROW(openvdb::IoError, mName << ": header line " << mLineNumber
                << " is not of the form 'Key = Value': '" << line.substr(0, 80) << "'");
        }
        mKey = trim(line.substr(0, equals));
        mValue = trim(line.substr(equals + 1));
        const std::string key = toLower(mKey);

        if (key == "objecttype") {
            if (toLower(mValue) != "image") this->fail("ObjectType " + mValue + " is not Image");
        } else if (key == "ndims") {
            nDims = this->parseNumber<int>(mValue);
            if (nDims != 3) {
                this->fail("NDims = " + mValue + ": only 3D images (NDims = 3) are supported");
            }
        } else if (key == "dimsize") {
            const std::vector<std::int64_t> sizes = this->parseNumbers<std::int64_t>(3);
            for (int axis = 0; axis < 3; ++axis) {
                const std::int64_t size = sizes[axis];
                if (size < 1) this->fail("DimSize " + std::to_string(size) + " is not positive");
                if (size > std::numeric_limits<std::int32_t>::max()) {
                    OPENVDB_THROW(openvdb::ValueError, mName << ": DimSize " << size
                        << " is beyond the int32 index range of a grid");
                }
                header.dimSize[axis] = std::int32_t(size);
            }
            hasDimSize = true;
        } else if (key == "elementtype") {
            if (!parseElementType(mValue, header.elementType)) {
                OPENVDB_THROW(openvdb::TypeError, mName << ": element type " << mValue
                    << " is not supported (expects MET_UCHAR, MET_CHAR, MET_USHORT, MET_SHORT,"
                    " MET_UINT or MET_INT: integer labels)");
            }
            hasElementType = true;
        } else if (key == "elementspacing" || key == "elementsize") {
            const std::vector<double> values = this->parseNumbers<double>(3);
            for (const double v : values) {
                if (!(v > 0.0)) this->fail("the voxel size must be positive");
            }
            std::array<double, 3>& target = key == "elementspacing" ? header.spacing : elementSize;
            std::copy(values.begin(), values.end(), target.begin());
            (key == "elementspacing" ? hasSpacing : hasElementSize) = true;
        } else if (key == "offset" || key == "position" || key == "origin") {
            const std::vector<double> values = this->parseNumbers<double>(3);
            std::copy(values.begin(), values.end(), header.offset.begin());
        } else if (key == "transformmatrix" || key == "rotation" || key == "orientation") {
            const std::vector<double> m = this->parseNumbers<double>(9);
            for (int i = 0; i < 9; ++i) {
                const double identity = (i % 4 == 0) ? 1.0 : 0.0;
                if (std::abs(m[i] - identity) > 1e-9) {
                    this->fail("'" + mValue + "' is not the identity: rotated or flipped"
                        " images are not supported");
                }
            }
        } else if (key == "binarydatabyteordermsb" || key == "elementbyteordermsb") {
            header.isMSB = this->parseBool();
        } else if (key == "binarydata") {
            if (!this->parseBool()) this->fail("ASCII data (BinaryData = False) are not supported");
        } else if (key == "compresseddata") {
            header.isCompressed = this->parseBool();
        } else if (key == "compresseddatasize") {
            header.compressedDataSize = this->parseNumber<std::int64_t>(mValue);
            if (header.compressedDataSize < 0) this->fail("negative CompressedDataSize");
        } else if (key == "headersize") {
            header.headerSize = this->parseNumber<std::int64_t>(mValue);
            if (header.headerSize < -1) this->fail("HeaderSize must be -1 or more");
        } else if (key == "elementnumberofchannels") {
            if (this->parseNumber<int>(mValue) != 1) {
                this->fail("ElementNumberOfChannels = " + mValue + ": labels have one channel");
            }
        } else if (key == "elementdatafile") {
            // The last key: the data (LOCAL) start on the next byte.
            header.elementDataFile = mValue;
            hasDataFile = true;
        }
        // Other keys (CenterOfRotation, AnatomicalOrientation, Comment, ...) do not matter.
    }
    header.headerBytes = mBytes;

    if (!hasDataFile) {
        OPENVDB_THROW(openvdb::IoError, mName << ": no ElementDataFile line"
            << (mLineNumber == 0 ? std::string(" (empty header)")
                                 : " (truncated header, or not a MetaImage file)"));
    }
    if (!hasDimSize) OPENVDB_THROW(openvdb::IoError, mName << ": missing DimSize in the header");
    if (!hasElementType) {
        OPENVDB_THROW(openvdb::IoError, mName << ": missing ElementType in the header");
    }
    if (!hasSpacing && hasElementSize) header.spacing = elementSize;

    const std::string dataFile = toLower(header.elementDataFile);
    if (dataFile.empty()) {
        OPENVDB_THROW(openvdb::IoError, mName << ": ElementDataFile names no file");
    }
    if (dataFile == "list" || dataFile.compare(0, 5, "list ") == 0) {
        OPENVDB_THROW(openvdb::IoError, mName << ": ElementDataFile = LIST (one file per slice)"
            " is not supported");
    }
    if (dataFile != "local" && isFilePattern(dataFile)) {
        OPENVDB_THROW(openvdb::IoError, mName << ": ElementDataFile = "
            << header.elementDataFile << ": file name patterns are not supported");
    }

    std::uint64_t voxels = 0, bytes = 0;
    if (!multiplyChecked(std::uint64_t(header.dimSize[0]), std::uint64_t(header.dimSize[1]),
            voxels)
        || !multiplyChecked(voxels, std::uint64_t(header.dimSize[2]), voxels)
        || !multiplyChecked(voxels, std::uint64_t(metaElementBytes(header.elementType)), bytes))
    {
        OPENVDB_THROW(openvdb::ValueError, mName << ": DimSize " << header.dimSize[0] << " x "
            << header.dimSize[1] << " x " << header.dimSize[2] << " of "
            << metaElementTypeName(header.elementType) << " overflows 64-bit byte counts");
    }
    if (header.isCompressed && header.headerSize == -1 && header.compressedDataSize < 0) {
        OPENVDB_THROW(openvdb::IoError, mName << ": HeaderSize = -1 with compressed data needs"
            " CompressedDataSize to find the data");
    }
    return header;
}

//////////////////////////////////////// element sources

/// Delivers exactly the requested number of element bytes, or throws.
class ElementSource
{
public:
    virtual ~ElementSource() = default;
    virtual void read(unsigned char* buffer, std::size_t bytes) = 0;
    /// Called after the last element: checks what follows them, where the format can.
    virtual void finish() {}
};

class RawSource : public ElementSource
{
public:
    RawSource(std::ifstream& in, const std::string& name, std::uint64_t expected)
        : mIn(in), mName(name), mExpected(expected) {}

    void read(unsigned char* buffer, std::size_t bytes) override
    {
        mIn.read(reinterpret_cast<char*>(buffer), std::streamsize(bytes));
        if (std::size_t(mIn.gcount()) != bytes) {
            // The size was checked up front: the file changed, or a read error.
            OPENVDB_THROW(openvdb::IoError, mName << ": truncated raw data (read error after "
                << (mDone + std::uint64_t(mIn.gcount())) << " of " << mExpected << " bytes)");
        }
        mDone += bytes;
    }

private:
    std::ifstream& mIn;
    const std::string& mName;
    std::uint64_t mExpected;
    std::uint64_t mDone = 0;
};

/// Inflates a zlib (or gzip) stream as it is read: only two small buffers are held.
class InflateSource : public ElementSource
{
public:
    InflateSource(std::ifstream& in, const std::string& name, std::uint64_t expected)
        : mIn(in), mName(name), mExpected(expected), mInput(INFLATE_INPUT_BYTES)
    {
        std::memset(&mStream, 0, sizeof(mStream));
        // 15 + 32: the largest window, and a zlib or gzip header detected automatically.
        if (inflateInit2(&mStream, 15 + 32) != Z_OK) {
            OPENVDB_THROW(openvdb::IoError, mName << ": cannot start zlib decompression");
        }
    }
    ~InflateSource() override { inflateEnd(&mStream); }

    void read(unsigned char* buffer, std::size_t bytes) override
    {
        mStream.next_out = buffer;
        mStream.avail_out = uInt(bytes); // bytes <= BLOCK_BYTES
        while (mStream.avail_out > 0) {
            if (this->inflateSome()) {
                if (mStream.avail_out > 0) this->failShort("the compressed stream ends early");
            }
        }
    }

    void finish() override
    {
        // Inflate on to the end of the stream, where zlib checks the Adler-32 sum: damaged
        // data must not pass as labels. More elements than DimSize are ignored; so that they
        // cost nothing, only a bounded amount of them is decoded.
        unsigned char scratch[4096];
        std::uint64_t extra = 0;
        while (!mHasEnded && extra < BLOCK_BYTES) {
            mStream.next_out = scratch;
            mStream.avail_out = uInt(sizeof(scratch));
            this->inflateSome();
            extra += sizeof(scratch) - mStream.avail_out;
        }
    }

private:
    /// One call of inflate(), reading more input first if needed; true at the stream's end.
    bool inflateSome()
    {
        if (mHasEnded) return true;
        if (mStream.avail_in == 0 && !mIsInputAtEnd) {
            mIn.read(reinterpret_cast<char*>(mInput.data()), std::streamsize(mInput.size()));
            const std::streamsize got = mIn.gcount();
            if (got <= 0) {
                mIsInputAtEnd = true;
            } else {
                mStream.next_in = mInput.data();
                mStream.avail_in = uInt(got);
            }
        }
        // Even without new input, zlib may still hold output: it says Z_BUF_ERROR if not.
        const int status = inflate(&mStream, Z_NO_FLUSH);
        if (status == Z_STREAM_END) {
            mHasEnded = true;
            return true;
        }
        if (status == Z_BUF_ERROR && mStream.avail_in == 0 && mIsInputAtEnd) {
            this->failShort("the compressed data end before the end of the stream");
        }
        if (status != Z_OK && status != Z_BUF_ERROR) {
            OPENVDB_THROW(openvdb::IoError, mName << ": corrupt compressed data after "
                << mStream.total_out << " bytes (zlib: "
                << (mStream.msg ? mStream.msg : zError(status)) << ")");
        }
        return false;
    }

    [[noreturn]] void failShort(const char* what) const
    {
        OPENVDB_THROW(openvdb::IoError, mName << ": truncated: " << what << " (after "
            << mStream.total_out << " of " << mExpected << " bytes of elements)");
    }

    std::ifstream& mIn;
    const std::string& mName;
    std::uint64_t mExpected;
    std::vector<unsigned char> mInput;
    z_stream mStream;
    bool mIsInputAtEnd = false;
    bool mHasEnded = false;
};

//////////////////////////////////////// decoding into the tree

bool
hostIsMSB()
{
    const std::uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    return first == 0;
}

template<typename T>
T
swapBytes(T value)
{
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    std::reverse(bytes, bytes + sizeof(T));
    std::memcpy(&value, bytes, sizeof(T));
    return value;
}

/// Stores the non-zero elements of one run along x, starting at voxel @a start.
template<typename T, bool SWAP>
void
storeRun(const unsigned char* bytes, std::int32_t count, const openvdb::Coord& start,
         openvdb::Int32Grid::Accessor& accessor, const std::string& name)
{
    constexpr std::int32_t PER_WORD = std::int32_t(sizeof(std::uint64_t) / sizeof(T));
    openvdb::Coord ijk = start;
    const std::int32_t x0 = start.x();
    for (std::int32_t i = 0; i < count;) {
        // Most of a label volume is background: skip it eight bytes at a time.
        if (count - i >= PER_WORD) {
            std::uint64_t word;
            std::memcpy(&word, bytes + std::size_t(i) * sizeof(T), sizeof(word));
            if (word == 0) {
                i += PER_WORD;
                continue;
            }
        }
        for (const std::int32_t end = std::min(count, i + PER_WORD); i < end; ++i) {
            T value;
            std::memcpy(&value, bytes + std::size_t(i) * sizeof(T), sizeof(T));
            if (value == 0) continue;
            if constexpr (SWAP) value = swapBytes(value);
            if constexpr (std::is_same<T, std::uint32_t>::value) {
                if (value > std::uint32_t(std::numeric_limits<std::int32_t>::max())) {
                    OPENVDB_THROW(openvdb::ValueError, name << ": MET_UINT element " << value
                        << " at (" << (x0 + i) << ", " << start.y() << ", " << start.z()
                        << ") is beyond the int32 range of labels");
                }
            }
            ijk.setX(x0 + i);
            accessor.setValue(ijk, std::int32_t(value));
        }
    }
}

using RunStorer = void (*)(const unsigned char*, std::int32_t, const openvdb::Coord&,
                           openvdb::Int32Grid::Accessor&, const std::string&);

template<bool SWAP>
RunStorer
runStorerFor(MetaElementType type)
{
    switch (type) {
        case MetaElementType::UChar:  return &storeRun<std::uint8_t, false>;
        case MetaElementType::Char:   return &storeRun<std::int8_t, false>;
        case MetaElementType::UShort: return &storeRun<std::uint16_t, SWAP>;
        case MetaElementType::Short:  return &storeRun<std::int16_t, SWAP>;
        case MetaElementType::UInt:   return &storeRun<std::uint32_t, SWAP>;
        case MetaElementType::Int:    return &storeRun<std::int32_t, SWAP>;
    }
    return nullptr;
}

/// Streams all elements in file order (x fastest, then y, then z) into @a grid through one
/// bounded buffer, so that memory does not grow with the volume.
void
streamElements(ElementSource& source, const MetaImageHeader& header,
               openvdb::Int32Grid& grid, const std::string& name)
{
    const bool swap = header.isMSB != hostIsMSB();
    const RunStorer storeRun =
        swap ? runStorerFor<true>(header.elementType) : runStorerFor<false>(header.elementType);
    const std::size_t elementBytes = std::size_t(metaElementBytes(header.elementType));
    const std::int32_t nx = header.dimSize[0], ny = header.dimSize[1];

    std::vector<unsigned char> block(BLOCK_BYTES);
    const std::uint64_t blockElements = BLOCK_BYTES / elementBytes;
    auto accessor = grid.getAccessor();
    std::uint64_t remaining = header.voxelCount();
    std::int32_t x = 0, y = 0, z = 0;
    while (remaining > 0) {
        const std::uint64_t elements = std::min(remaining, blockElements);
        source.read(block.data(), std::size_t(elements * elementBytes));
        const unsigned char* bytes = block.data();
        for (std::uint64_t left = elements; left > 0;) {
            // The part of the current row inside this block.
            const std::int32_t run = std::int32_t(std::min<std::uint64_t>(left, nx - x));
            storeRun(bytes, run, openvdb::Coord(x, y, z), accessor, name);
            bytes += std::size_t(run) * elementBytes;
            left -= std::uint64_t(run);
            x += run;
            if (x == nx) {
                x = 0;
                if (++y == ny) { y = 0; ++z; }
            }
        }
        remaining -= elements;
    }
    source.finish();
}

openvdb::math::Transform::Ptr
makeTransform(const MetaImageHeader& header)
{
    const openvdb::Vec3d spacing(header.spacing[0], header.spacing[1], header.spacing[2]);
    const openvdb::Vec3d offset(header.offset[0], header.offset[1], header.offset[2]);
    openvdb::math::MapBase::Ptr map;
    // A uniform map where possible: several OpenVDB tools need uniform voxels.
    if (spacing[0] == spacing[1] && spacing[1] == spacing[2]) {
        map.reset(new openvdb::math::UniformScaleTranslateMap(spacing[0], offset));
    } else {
        map.reset(new openvdb::math::ScaleTranslateMap(spacing, offset));
    }
    return openvdb::math::Transform::Ptr(new openvdb::math::Transform(map));
}

void
checkIsFile(const std::string& path, const std::string& messagePath, const std::string& role)
{
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    if (!fs::exists(status)) {
        OPENVDB_THROW(openvdb::IoError, messagePath << ": " << role << "no such file");
    }
    if (fs::is_directory(status)) {
        OPENVDB_THROW(openvdb::IoError, messagePath << ": " << role
            << "is a directory, not a file");
    }
}

} // namespace

//////////////////////////////////////// public

int
metaElementBytes(MetaElementType type)
{
    switch (type) {
        case MetaElementType::UChar: case MetaElementType::Char: return 1;
        case MetaElementType::UShort: case MetaElementType::Short: return 2;
        case MetaElementType::UInt: case MetaElementType::Int: return 4;
    }
    return 0;
}

const char*
metaElementTypeName(MetaElementType type)
{
    switch (type) {
        case MetaElementType::UChar: return "MET_UCHAR";
        case MetaElementType::Char: return "MET_CHAR";
        case MetaElementType::UShort: return "MET_USHORT";
        case MetaElementType::Short: return "MET_SHORT";
        case MetaElementType::UInt: return "MET_UINT";
        case MetaElementType::Int: return "MET_INT";
    }
    return "?";
}

bool
MetaImageHeader::isLocal() const
{
    return toLower(elementDataFile) == "local";
}

std::uint64_t
MetaImageHeader::voxelCount() const
{
    return std::uint64_t(dimSize[0]) * std::uint64_t(dimSize[1]) * std::uint64_t(dimSize[2]);
}

std::uint64_t
MetaImageHeader::dataBytes() const
{
    return this->voxelCount() * std::uint64_t(metaElementBytes(elementType));
}

MetaImageHeader
parseMetaImageHeader(std::istream& in, const std::string& nameForErrors)
{
    return HeaderParser(in, nameForErrors).parse();
}

openvdb::Int32Grid::Ptr
readMetaImage(const std::string& path)
{
    checkIsFile(path, path, "");
    std::ifstream headerIn(path, std::ios::binary);
    if (!headerIn) {
        OPENVDB_THROW(openvdb::IoError, path << ": cannot open for reading ("
            << std::strerror(errno) << ")");
    }
    std::error_code error;
    if (fs::file_size(path, error) == 0) OPENVDB_THROW(openvdb::IoError, path << ": is empty");
    const MetaImageHeader header = parseMetaImageHeader(headerIn, path);
    headerIn.close();

    // Where the elements are: after the header (LOCAL), or in a file next to the header.
    std::string dataPath = path;
    std::uint64_t dataStart = 0;
    std::string role;
    if (header.isLocal()) {
        dataStart = header.headerBytes;
    } else {
        fs::path file(header.elementDataFile);
        if (file.is_relative()) file = fs::path(path).parent_path() / file;
        dataPath = file.string();
        role = "data file " + dataPath + ": ";
        checkIsFile(dataPath, path, role);
    }
    const std::uint64_t fileBytes = fs::file_size(dataPath, error);
    if (error) {
        OPENVDB_THROW(openvdb::IoError, path << ": " << role << "cannot get the size ("
            << error.message() << ")");
    }
    const std::uint64_t needed = header.isCompressed
        ? std::uint64_t(std::max<std::int64_t>(header.compressedDataSize, 0))
        : header.dataBytes();
    if (header.headerSize == -1) {
        // The data are the last bytes of the file.
        if (needed > fileBytes) {
            OPENVDB_THROW(openvdb::IoError, path << ": " << role << "truncated: holds "
                << fileBytes << " bytes, the header says the data alone take " << needed);
        }
        dataStart = fileBytes - needed;
    } else {
        dataStart += std::uint64_t(header.headerSize);
    }
    if (!header.isCompressed && (dataStart > fileBytes || fileBytes - dataStart < needed)) {
        OPENVDB_THROW(openvdb::IoError, path << ": " << role << "truncated: "
            << (dataStart > fileBytes ? 0 : fileBytes - dataStart) << " bytes of raw data, the"
            " header says " << needed << " (DimSize " << header.dimSize[0] << " x "
            << header.dimSize[1] << " x " << header.dimSize[2] << " of "
            << metaElementTypeName(header.elementType) << ")");
    }
    if (header.isCompressed && dataStart >= fileBytes) {
        OPENVDB_THROW(openvdb::IoError, path << ": " << role << "truncated: no compressed data"
            " after byte " << dataStart);
    }
    // Deflate expands at most 1032 times (zlib's FAQ): an absurd DimSize that the bytes at
    // hand cannot hold is refused before anything is inflated.
    if (header.isCompressed
        && header.dataBytes() / MAX_DEFLATE_RATIO > fileBytes - dataStart)
    {
        OPENVDB_THROW(openvdb::IoError, path << ": " << role << "truncated: DimSize "
            << header.dimSize[0] << " x " << header.dimSize[1] << " x " << header.dimSize[2]
            << " of " << metaElementTypeName(header.elementType) << " needs "
            << header.dataBytes() << " bytes, more than the " << (fileBytes - dataStart)
            << " bytes of compressed data can hold (deflate expands at most "
            << MAX_DEFLATE_RATIO << " times)");
    }

    std::ifstream dataIn(dataPath, std::ios::binary);
    if (!dataIn) {
        OPENVDB_THROW(openvdb::IoError, path << ": " << role << "cannot open for reading ("
            << std::strerror(errno) << ")");
    }
    dataIn.seekg(std::streamoff(dataStart));

    openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(/*background=*/0);
    grid->setTransform(makeTransform(header));
    if (header.isCompressed) {
        InflateSource source(dataIn, path, header.dataBytes());
        streamElements(source, header, *grid, path);
    } else {
        RawSource source(dataIn, path, header.dataBytes());
        streamElements(source, header, *grid, path);
    }
    return grid;
}

} // namespace vdbi
