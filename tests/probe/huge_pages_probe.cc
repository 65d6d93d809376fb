// SPDX-License-Identifier: Apache-2.0
/// @file probe/huge_pages_probe.cc
/// @brief Calls vdbi::restartWithHugePages() as a program's main() does, then touches 64 MiB
/// of heap and prints what TestHugePages checks: the tunables it runs with and how many kB of
/// that heap the kernel backed with huge pages.

#include <vdbi/HugePages.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

namespace {

/// AnonHugePages of this process in kB (-1 if /proc tells nothing).
long
anonHugePagesKb()
{
    std::ifstream file("/proc/self/smaps_rollup");
    std::string key;
    long kb = -1;
    while (file >> key) {
        if (key == "AnonHugePages:") {
            file >> kb;
            break;
        }
    }
    return kb;
}

} // namespace

int
main(int, char** argv)
{
    vdbi::restartWithHugePages(argv);
    const long before = anonHugePagesKb();
    constexpr std::size_t BYTES = std::size_t(64) << 20;
    auto* heap = static_cast<char*>(std::malloc(BYTES));
    if (!heap) return 1;
    std::memset(heap, 1, BYTES);
    const long after = anonHugePagesKb();
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    // Printing a byte of the heap keeps the compiler from dropping the allocation.
    std::printf("tunables=%s\nhuge_kb=%ld\nbyte=%d\n", tunables ? tunables : "",
                after - before, int(heap[BYTES / 2]));
    std::free(heap);
    return 0;
}
