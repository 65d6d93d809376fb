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
    const std::string value = (tunables.empty() ? "" : tunables + ":") + TUNABLE + "=1";
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
