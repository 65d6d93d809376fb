// SPDX-License-Identifier: Apache-2.0

#include <vdbi/VdbReader.h>

#include <openvdb/Exceptions.h>
#include <openvdb/io/Stream.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <fstream>
#include <ios>
#include <limits>
#include <memory>
#include <sstream>
#include <type_traits>

#include <unistd.h> // for sysconf

namespace vdbi {

namespace {

/// The value type, but "mask" for a MaskGrid (whose value type is bool, as a BoolGrid's).
std::string
typeName(const openvdb::GridBase& grid)
{
    return grid.isType<openvdb::MaskGrid>() ? std::string("mask") : grid.valueType();
}

/// "'name' (type), ..." for every grid of the file, for messages.
std::string
describeGrids(const openvdb::GridPtrVec& grids)
{
    std::ostringstream os;
    for (std::size_t i = 0; i < grids.size(); ++i) {
        if (i > 0) os << ", ";
        os << "'" << grids[i]->getName() << "' (" << typeName(*grids[i]) << ")";
    }
    if (grids.empty()) os << "no grids";
    return os.str();
}

bool
isConvertible(const openvdb::GridBase& grid)
{
    return grid.isType<openvdb::Int32Grid>() || grid.isType<openvdb::Int64Grid>()
        || grid.isType<openvdb::BoolGrid>() || grid.isType<openvdb::FloatGrid>()
        || grid.isType<openvdb::DoubleGrid>();
}

template<typename ValueT>
bool
isExactInt32(const ValueT& value)
{
    if constexpr (std::is_same<ValueT, bool>::value) {
        return true;
    } else if constexpr (std::is_integral<ValueT>::value) {
        return value >= std::numeric_limits<std::int32_t>::min()
            && value <= std::numeric_limits<std::int32_t>::max();
    } else {
        // NaN fails every comparison; the range test keeps the cast below defined.
        return value >= -2147483648.0 && value <= 2147483647.0 && std::trunc(value) == value;
    }
}

/// A deep copy of @a grid with int32 values, after checking that the cast changes none.
template<typename GridT>
openvdb::Int32Grid::Ptr
convertExactly(const GridT& grid, const std::string& path)
{
    const auto fail = [&](const auto& value, const std::string& where) {
        OPENVDB_THROW(openvdb::TypeError, path << ": grid '" << grid.getName() << "' ("
            << grid.valueType() << ") holds the value " << value << " " << where
            << ", which is not an exact int32 label");
    };
    if (!isExactInt32(grid.background())) fail(grid.background(), "as its background");
    // Every value: voxels and tiles, active or not, at every level of the tree.
    for (auto it = grid.tree().cbeginValueAll(); it; ++it) {
        if (!isExactInt32(*it)) {
            std::ostringstream where;
            where << (it.isVoxelValue() ? "at voxel " : "in the tile at ") << it.getCoord();
            fail(*it, where.str());
        }
    }
    openvdb::Int32Tree::Ptr tree(new openvdb::Int32Tree(grid.tree()));
    openvdb::Int32Grid::Ptr result = openvdb::Int32Grid::create(tree);
    result->setTransform(grid.transform().copy());
    result->setName(grid.getName());
    return result;
}

openvdb::Int32Grid::Ptr
toInt32Grid(const openvdb::GridBase::Ptr& grid, const std::string& path)
{
    if (auto g = openvdb::gridPtrCast<openvdb::Int32Grid>(grid)) return g;
    if (auto g = openvdb::gridPtrCast<openvdb::Int64Grid>(grid)) return convertExactly(*g, path);
    if (auto g = openvdb::gridPtrCast<openvdb::BoolGrid>(grid)) return convertExactly(*g, path);
    if (auto g = openvdb::gridPtrCast<openvdb::FloatGrid>(grid)) return convertExactly(*g, path);
    if (auto g = openvdb::gridPtrCast<openvdb::DoubleGrid>(grid)) return convertExactly(*g, path);
    OPENVDB_THROW(openvdb::TypeError, path << ": grid '" << grid->getName() << "' is of type "
        << typeName(*grid) << ", not an integer-valued type");
}

/// @brief Refuses a grid whose tiles the pipeline could not hold as voxels.
/// @details The stages read leaf voxels, so tiles of a non-background value are filled with
/// voxels first (4 bytes each at least). A few root tiles in a tiny file can stand for
/// terabytes: better a message naming the size now than an allocation failure later.
void
checkTilesFitInMemory(const openvdb::Int32Grid& grid, const std::string& path)
{
    // A double: the tiles of a tree may hold more than 2^64 voxels.
    double voxels = 0.0;
    openvdb::Int32Tree::ValueAllCIter it = grid.tree().cbeginValueAll();
    it.setMaxDepth(openvdb::Int32Tree::ValueAllCIter::LEAF_DEPTH - 1);
    for (; it; ++it) {
        if (*it != grid.background()) voxels += double(it.getBoundingBox().volume());
    }
    const double GIB = 1024.0 * 1024.0 * 1024.0;
    const double bytes = voxels * double(sizeof(openvdb::Int32));
    const double memory = double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGE_SIZE));
    if (memory > 0.0 && bytes > memory) {
        OPENVDB_THROW(openvdb::ValueError, path << ": grid '" << grid.getName() << "' has tiles"
            " of " << std::fixed << std::setprecision(0) << voxels << " voxels, which the"
            " extraction turns into voxels: at least " << std::setprecision(1) << bytes / GIB
            << " GiB, more than this machine's memory (" << memory / GIB << " GiB)");
    }
}

} // namespace

openvdb::Int32Grid::Ptr
readVdb(const std::string& path, const std::string& gridName)
{
    namespace fs = std::filesystem;
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    if (!fs::exists(status)) OPENVDB_THROW(openvdb::IoError, path << ": no such file");
    if (fs::is_directory(status)) {
        OPENVDB_THROW(openvdb::IoError, path << ": is a directory, not a file");
    }
    if (fs::file_size(path, error) == 0 && !error) {
        OPENVDB_THROW(openvdb::IoError, path << ": is empty");
    }

    openvdb::initialize();
    // io::Stream rather than io::File: OpenVDB does not check its reads, so a truncated file
    // would give a partial grid silently. A stream that throws on a short read catches that,
    // and io::Stream keeps the grids in file order (io::File lists them by name).
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        OPENVDB_THROW(openvdb::IoError, path << ": cannot open for reading ("
            << std::strerror(errno) << ")");
    }
    in.exceptions(std::ios::failbit | std::ios::badbit);
    openvdb::GridPtrVecPtr grids;
    try {
        openvdb::io::Stream stream(in, /*delayLoad=*/false);
        grids = stream.getGrids();
    } catch (const std::ios_base::failure&) {
        OPENVDB_THROW(openvdb::IoError, path << ": cannot read: truncated or unreadable .vdb"
            " file (a read failed or ran past its end)");
    } catch (const openvdb::Exception& e) {
        // what() reads "IoError: not a VDB file": the type name means nothing to a user.
        const std::string message = e.what();
        const std::size_t colon = message.find(": ");
        OPENVDB_THROW(openvdb::IoError, path << ": cannot read as a .vdb file: "
            << (colon == std::string::npos ? message : message.substr(colon + 2)));
    } catch (const std::exception& e) {
        OPENVDB_THROW(openvdb::IoError, path << ": cannot read as a .vdb file: " << e.what());
    }
    if (!grids) grids = std::make_shared<openvdb::GridPtrVec>();

    openvdb::GridBase::Ptr grid;
    if (!gridName.empty()) {
        for (const auto& candidate : *grids) {
            if (candidate->getName() == gridName) { grid = candidate; break; }
        }
        if (!grid) {
            OPENVDB_THROW(openvdb::ValueError, path << ": no grid named '" << gridName
                << "'; the file holds " << describeGrids(*grids));
        }
        if (!isConvertible(*grid)) {
            OPENVDB_THROW(openvdb::TypeError, path << ": grid '" << gridName << "' is of type "
                << typeName(*grid) << "; labels need int32 (or int64, bool, float, double"
                " with exact int32 values)");
        }
    } else {
        for (const auto& candidate : *grids) {
            if (candidate->isType<openvdb::Int32Grid>()) { grid = candidate; break; }
        }
        for (auto it = grids->begin(); !grid && it != grids->end(); ++it) {
            if (isConvertible(**it)) grid = *it;
        }
        if (!grid) {
            OPENVDB_THROW(openvdb::TypeError, path << ": no grid of an integer-valued type"
                " (int32, or int64, bool, float, double with exact int32 values); the file"
                " holds " << describeGrids(*grids));
        }
    }
    const openvdb::Int32Grid::Ptr labels = toInt32Grid(grid, path);
    checkTilesFitInMemory(*labels, path);
    return labels;
}

} // namespace vdbi
