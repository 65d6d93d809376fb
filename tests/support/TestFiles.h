// SPDX-License-Identifier: Apache-2.0
/// @file support/TestFiles.h
/// @brief Files in tests: a temporary folder per test, whole-file reads and writes, and the
/// check that a reader's error names the file and the problem.

#ifndef VDBI_TEST_TEST_FILES_HAS_BEEN_INCLUDED
#define VDBI_TEST_TEST_FILES_HAS_BEEN_INCLUDED

#include <gtest/gtest.h>

#include <exception>
#include <filesystem>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

namespace vdbi_test {

using Bytes = std::vector<unsigned char>;

Bytes readBytes(const std::string& path);
/// The whole file as a string (empty when it cannot be read).
std::string readText(const std::string& path);
void writeBytes(const std::string& path, const Bytes& bytes);
void writeText(const std::string& path, const std::string& text);

/// True if @a part occurs in @a text.
bool contains(const std::string& text, const std::string& part);

/// @a arg in single quotes for /bin/sh, embedded quotes escaped.
std::string shellQuote(const std::string& arg);

/// The paths below @a dir (recursively), relative to it, sorted.
std::vector<std::string> listFolder(const std::filesystem::path& dir);

/// A fresh folder under the test temporary folder, named after the running test, removed
/// with everything in it when this object goes (a fixture member: one per test).
class TempFolder
{
public:
    TempFolder();
    ~TempFolder();
    TempFolder(const TempFolder&) = delete;
    TempFolder& operator=(const TempFolder&) = delete;

    const std::filesystem::path& path() const { return mPath; }
    /// The path of @a name inside the folder.
    std::string file(const std::string& name) const { return (mPath / name).string(); }

private:
    std::filesystem::path mPath;
};

/// Runs @a read, which must throw @c E whose message, after the exception's type prefix
/// ("IoError: "), starts with @a path and contains every one of @a words.
template<typename E>
void
expectError(const std::function<void()>& read, const std::string& path,
            const std::vector<std::string>& words)
{
    try {
        read();
        ADD_FAILURE() << "no exception for " << path;
    } catch (const E& e) {
        const std::string message = e.what();
        const std::size_t start = message.find(": ");
        ASSERT_NE(start, std::string::npos) << message;
        EXPECT_EQ(message.compare(start + 2, path.size(), path), 0) << message;
        for (const std::string& word : words) {
            EXPECT_NE(message.find(word), std::string::npos)
                << message << " lacks '" << word << "'";
        }
    } catch (const std::exception& e) {
        ADD_FAILURE() << "wrong exception type: " << e.what();
    }
}

/// One word (a template, so that a braced list of words picks the overload above).
template<typename E, typename Word,
         typename = std::enable_if_t<std::is_convertible_v<const Word&, std::string>>>
void
expectError(const std::function<void()>& read, const std::string& path, const Word& word)
{
    expectError<E>(read, path, std::vector<std::string>{word});
}

} // namespace vdbi_test

#endif // VDBI_TEST_TEST_FILES_HAS_BEEN_INCLUDED
