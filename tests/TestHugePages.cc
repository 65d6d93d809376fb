// SPDX-License-Identifier: Apache-2.0
/// @file TestHugePages.cc
/// @brief restartWithHugePages(): the restarted program's heap gets huge pages and grows in
/// large steps, and a choice the user made in GLIBC_TUNABLES is kept. Runs
/// tests/probe/huge_pages_probe.

#include "support/TestFiles.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#if defined(VDBI_HUGE_PAGES_PROBE_PATH) && defined(__GLIBC__)
#include <gnu/libc-version.h>

namespace {

/// What the restart adds after the huge pages: the heap's pad and the thresholds it freezes.
const std::string PAD = "glibc.malloc.top_pad=67108864",
    THRESHOLDS = "glibc.malloc.mmap_threshold=33554432:glibc.malloc.trim_threshold=67108864",
    HEAP_TUNABLES = PAD + ":" + THRESHOLDS;

struct ProbeResult
{
    std::string tunables;
    long hugeKb = -1;
    long threadHeapKb = -1;   ///< writable kB of a new thread's heap after its first malloc
};

/// Runs the probe with GLIBC_TUNABLES set to @a tunables (unset if empty).
ProbeResult
runProbe(const std::string& tunables)
{
    const std::string command = (tunables.empty() ? std::string("env -u GLIBC_TUNABLES ")
        : "env GLIBC_TUNABLES=" + vdbi_test::shellQuote(tunables) + " ")
        + vdbi_test::shellQuote(VDBI_HUGE_PAGES_PROBE_PATH);
    ProbeResult result;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return result;
    char line[512];
    while (std::fgets(line, sizeof line, pipe)) {
        std::string text(line);
        if (!text.empty() && text.back() == '\n') text.pop_back();
        if (text.rfind("tunables=", 0) == 0) result.tunables = text.substr(9);
        if (text.rfind("huge_kb=", 0) == 0) result.hugeKb = std::stol(text.substr(8));
        if (text.rfind("thread_heap_kb=", 0) == 0) {
            result.threadHeapKb = std::stol(text.substr(15));
        }
    }
    EXPECT_EQ(pclose(pipe), 0) << command;
    return result;
}

/// Why the restart cannot work on this machine (empty: it can).
std::string
unsupportedBecause()
{
#if defined(VDBI_SANITIZED)
    return "the sanitizers bring their own allocator";
#endif
    std::ifstream file("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string modes;
    std::getline(file, modes);
    if (modes.find("[madvise]") == std::string::npos) {
        return "the kernel's transparent huge page mode is not madvise: '" + modes + "'";
    }
    int major = 0, minor = 0;
    std::sscanf(gnu_get_libc_version(), "%d.%d", &major, &minor);
    if (major < 2 || (major == 2 && minor < 35)) return "glibc older than 2.35";
    return {};
}

} // namespace

class TestHugePages : public ::testing::Test
{
protected:
    void SetUp() override
    {
        const std::string reason = unsupportedBecause();
        if (!reason.empty()) GTEST_SKIP() << reason;
    }
};

TEST_F(TestHugePages, testRestartGivesTheHeapHugePages)
{
    const ProbeResult r = runProbe("");
    EXPECT_EQ(r.tunables, "glibc.malloc.hugetlb=1:" + HEAP_TUNABLES);
    // 64 MiB touched: at least one 2 MiB page, where the kernel had one to give (it usually
    // backs nearly all of it).
    EXPECT_GE(r.hugeKb, 2048);
    // The pad: a thread's heap is made writable in one step (glibc's thread heaps are at
    // most 64 MiB), not a few pages per growth.
    EXPECT_GE(r.threadHeapKb, 32 * 1024);
}

TEST_F(TestHugePages, testUsersChoiceIsKept)
{
    // Opting out: no restart, and the heap keeps 4 KiB pages.
    const ProbeResult off = runProbe("glibc.malloc.hugetlb=0");
    EXPECT_EQ(off.tunables, "glibc.malloc.hugetlb=0");
    EXPECT_EQ(off.hugeKb, 0);
    // Other tunables stay, the huge page one is added after them.
    const ProbeResult other = runProbe("glibc.malloc.check=0");
    EXPECT_EQ(other.tunables, "glibc.malloc.check=0:glibc.malloc.hugetlb=1:" + HEAP_TUNABLES);
    EXPECT_GE(other.hugeKb, 2048);
    // A pad the user chose stays: with none, a thread's heap is writable a few pages at a
    // time (what the test above tells apart).
    const ProbeResult noPad = runProbe("glibc.malloc.top_pad=0");
    EXPECT_EQ(noPad.tunables, "glibc.malloc.top_pad=0:glibc.malloc.hugetlb=1:" + THRESHOLDS);
    EXPECT_GE(noPad.hugeKb, 2048);
    EXPECT_GE(noPad.threadHeapKb, 0);
    EXPECT_LT(noPad.threadHeapKb, 1024);
}

#endif // VDBI_HUGE_PAGES_PROBE_PATH && __GLIBC__
