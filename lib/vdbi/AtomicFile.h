// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/AtomicFile.h
/// @brief Writes a file through a temporary sibling that is renamed into place only once
/// everything was written, so a failed write never leaves a partial or truncated file.

#ifndef VDBI_ATOMIC_FILE_HAS_BEEN_INCLUDED
#define VDBI_ATOMIC_FILE_HAS_BEEN_INCLUDED

#include <fstream>
#include <functional>
#include <string>

namespace vdbi {

/// @brief An output file that appears under its name only when commit() succeeds.
/// @details The data goes to "<path>.tmp-<pid>" in the same folder (so the final
/// std::rename stays on one file system and replaces an existing file atomically). The
/// destructor removes the temporary file unless commit() succeeded, so an exception thrown
/// while writing cleans up by itself. All errors are openvdb::IoError with a message of the
/// form "<path>: <problem>".
class AtomicFile
{
public:
    /// @brief Creates the temporary file.
    /// @param path    the final name, as the user gave it (used in error messages)
    /// @param binary  open in binary mode (no effect on POSIX, kept for clarity)
    /// @throw openvdb::IoError if the temporary file cannot be created
    explicit AtomicFile(const std::string& path, bool binary = true);
    /// Removes the temporary file if commit() was not reached.
    ~AtomicFile();

    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    /// The stream to write to.
    std::ostream& stream() { return mStream; }

    /// @brief Flushes, closes and checks the stream (a full disk shows here), then renames
    /// the temporary file to path().
    /// @throw openvdb::IoError on any failure; the temporary file is removed
    void commit();

    /// Removes the temporary file; the target is left as it was. Never throws.
    void discard() noexcept;

    /// @brief Discards and throws openvdb::IoError "<path>: <problem>".
    [[noreturn]] void fail(const std::string& problem);

    const std::string& path() const { return mPath; }
    const std::string& tempPath() const { return mTempPath; }
    bool isCommitted() const { return mCommitted; }

private:
    std::string mPath;
    std::string mTempPath;
    std::ofstream mStream;
    bool mCommitted = false;
    bool mDiscarded = false;
};

/// @brief Writes @a path atomically: opens an AtomicFile, calls @a body with its stream,
/// then commits. If @a body throws, the temporary file is removed and the exception
/// propagates unchanged.
/// @throw openvdb::IoError as AtomicFile, or whatever @a body throws
void writeFileAtomically(const std::string& path,
                         const std::function<void(std::ostream&)>& body,
                         bool binary = true);

/// @brief Removes the temporary files of every AtomicFile alive in this process.
/// @details For a program's termination path, e.g. a thread that waits for SIGINT: the
/// objects are left as they are, so call it only right before exiting. Thread-safe; a
/// commit() that is renaming finishes first (its output is then complete), and AtomicFile
/// objects created afterwards throw openvdb::IoError instead of creating a file.
void removeAllTemporaryFiles() noexcept;

/// @brief "<path>: <problem>: <strerror(errnum)>", or without the last part when errnum is 0.
std::string ioErrorMessage(const std::string& path, const std::string& problem, int errnum);

} // namespace vdbi

#endif // VDBI_ATOMIC_FILE_HAS_BEEN_INCLUDED
