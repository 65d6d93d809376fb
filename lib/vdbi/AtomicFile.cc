// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/AtomicFile.cc

#include <vdbi/AtomicFile.h>

#include <openvdb/Exceptions.h>

#include <cerrno>
#include <cstdio>   // for std::rename, std::remove
#include <cstring>  // for std::strerror
#include <mutex>
#include <set>
#include <unistd.h> // for getpid

namespace vdbi {

namespace {

/// The temporary files not yet renamed or removed, for removeAllTemporaryFiles().
struct Registry
{
    std::mutex mutex;
    std::set<std::string> paths;
    bool isClosed = false; ///< after removeAllTemporaryFiles(): no new files
};

Registry&
registry()
{
    static Registry instance; // never destroyed before the objects that use it
    return instance;
}

void
unregisterTemporary(const std::string& path) noexcept
{
    try {
        std::lock_guard<std::mutex> lock(registry().mutex);
        registry().paths.erase(path);
    } catch (...) {
    }
}

} // namespace

void
removeAllTemporaryFiles() noexcept
{
    try {
        std::lock_guard<std::mutex> lock(registry().mutex);
        for (const std::string& path : registry().paths) std::remove(path.c_str());
        registry().paths.clear();
        registry().isClosed = true;
    } catch (...) {
    }
}

std::string
ioErrorMessage(const std::string& path, const std::string& problem, int errnum)
{
    std::string message = path + ": " + problem;
    if (errnum != 0) message += std::string(": ") + std::strerror(errnum);
    return message;
}

AtomicFile::AtomicFile(const std::string& path, bool binary)
    : mPath(path)
    , mTempPath(path + ".tmp-" + std::to_string(static_cast<long>(::getpid())))
{
    std::ios::openmode mode = std::ios::out | std::ios::trunc;
    if (binary) mode |= std::ios::binary;
    {
        // Registered before it exists, so no moment has a file that nobody would remove.
        std::lock_guard<std::mutex> lock(registry().mutex);
        if (registry().isClosed) {
            mDiscarded = true;
            OPENVDB_THROW(openvdb::IoError, mPath << ": not written: the program is exiting");
        }
        registry().paths.insert(mTempPath);
    }
    errno = 0;
    mStream.open(mTempPath, mode);
    if (!mStream.is_open()) {
        const int err = errno;
        mDiscarded = true; // nothing was created
        unregisterTemporary(mTempPath);
        OPENVDB_THROW(openvdb::IoError, ioErrorMessage(mPath, "cannot open for writing", err));
    }
}

AtomicFile::~AtomicFile()
{
    if (!mCommitted) discard();
}

void
AtomicFile::discard() noexcept
{
    if (mDiscarded || mCommitted) return;
    mDiscarded = true;
    try {
        if (mStream.is_open()) mStream.close();
    } catch (...) {
    }
    std::remove(mTempPath.c_str());
    unregisterTemporary(mTempPath);
}

void
AtomicFile::fail(const std::string& problem)
{
    discard();
    OPENVDB_THROW(openvdb::IoError, mPath << ": " << problem);
}

void
AtomicFile::commit()
{
    if (mCommitted) return;
    if (mDiscarded) fail("write was abandoned");

    // A full disk or an I/O error may only show when the buffer is flushed or the file is
    // closed, so check the state after both.
    errno = 0;
    mStream.flush();
    bool good = mStream.good();
    int err = errno;
    mStream.close();
    if (good && mStream.fail()) {
        good = false;
        err = errno;
    }
    if (!good) {
        discard();
        OPENVDB_THROW(openvdb::IoError, ioErrorMessage(mPath, "write failed", err));
    }

    bool renamed;
    {
        // Under the registry's lock, so removeAllTemporaryFiles() waits for a rename.
        std::lock_guard<std::mutex> lock(registry().mutex);
        errno = 0;
        renamed = std::rename(mTempPath.c_str(), mPath.c_str()) == 0;
        err = errno;
        if (renamed) registry().paths.erase(mTempPath);
    }
    if (!renamed) {
        discard();
        OPENVDB_THROW(openvdb::IoError,
            ioErrorMessage(mPath, "cannot replace with the written file " + mTempPath, err));
    }
    mCommitted = true;
}

void
writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& body,
                    bool binary)
{
    AtomicFile file(path, binary);
    body(file.stream());
    // Check before commit so the message says the writing failed, not the renaming.
    if (!file.stream()) {
        const int err = errno;
        file.discard();
        OPENVDB_THROW(openvdb::IoError, ioErrorMessage(path, "write failed", err));
    }
    file.commit();
}

} // namespace vdbi
