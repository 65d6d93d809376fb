// SPDX-License-Identifier: Apache-2.0

#include <vdbi/HugePages.h>

#include <cstdio>
#include <cstdlib> // defines __GLIBC__ where the C library is glibc
#include <fstream>
#include <string>

#if defined(__linux__) && defined(__GLIBC__)
#include <gnu/libc-version.h> // for gnu_get_libc_version
#include <unistd.h>           // for execv
#if __has_include(<valgrind/valgrind.h>)
#include <valgrind/valgrind.h>
#endif
#endif

namespace vdbi {

#if defined(__linux__) && defined(__GLIBC__)

namespace {

constexpr const char* TUNABLE = "glibc.malloc.hugetlb";

/// Set with the huge pages unless the user named them (HugePages.h says why): the heap grows
/// by 64 MiB more than asked. Setting that stops glibc from raising its mmap and trim
/// thresholds as a program frees large blocks, so they are set to where that rule takes them
/// on 64-bit systems: without, every block over 128 KiB would be new, zeroed pages each time.
constexpr const char* HEAP_TUNABLES[][2] = {{"glibc.malloc.top_pad", "67108864"},
    {"glibc.malloc.mmap_threshold", "33554432"}, {"glibc.malloc.trim_threshold", "67108864"}};

/// The kernel's transparent huge page mode, the bracketed word of
/// "always [madvise] never"; empty if unknown.
std::string
kernelHugePageMode()
{
    std::ifstream file("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string line;
    std::getline(file, line);
    const std::size_t open = line.find('['), close = line.find(']');
    if (open == std::string::npos || close == std::string::npos || close < open) return {};
    return line.substr(open + 1, close - open - 1);
}

/// glibc.malloc.hugetlb exists from glibc 2.35 on.
bool
glibcHasHugePageTunable()
{
    int major = 0, minor = 0;
    return std::sscanf(gnu_get_libc_version(), "%d.%d", &major, &minor) == 2
        && (major > 2 || (major == 2 && minor >= 35));
}

bool
runningOnValgrind()
{
#ifdef RUNNING_ON_VALGRIND
    return RUNNING_ON_VALGRIND != 0;
#else
    return false;
#endif
}

} // namespace

void
restartWithHugePages(char** argv)
{
    const char* current = std::getenv("GLIBC_TUNABLES");
    const std::string tunables = current ? current : "";
    if (tunables.find(TUNABLE) != std::string::npos || runningOnValgrind()
        || kernelHugePageMode() != "madvise" || !glibcHasHugePageTunable()) {
        return;
    }
    std::string value = (tunables.empty() ? "" : tunables + ":") + TUNABLE + "=1";
    for (const auto& [name, bytes] : HEAP_TUNABLES) {
        if (tunables.find(name) != std::string::npos) continue;
        value += std::string(":") + name + "=" + bytes;
    }
    if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
    execv("/proc/self/exe", argv);
    // Not restarted (no /proc, say): go on as we are, without the tunable in the environment
    // of the programs this one might start.
    if (current) setenv("GLIBC_TUNABLES", tunables.c_str(), 1);
    else unsetenv("GLIBC_TUNABLES");
}

#else

void restartWithHugePages(char**) {}

#endif

} // namespace vdbi
