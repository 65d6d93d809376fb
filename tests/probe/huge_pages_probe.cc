// SPDX-License-Identifier: Apache-2.0
/// @file probe/huge_pages_probe.cc
/// @brief Calls vdbi::restartWithHugePages() as a program's main() does, then touches 64 MiB
/// of heap and prints what TestHugePages checks: the tunables it runs with, how many kB of
/// that heap the kernel backed with huge pages, and how many kB of a new thread's heap are
/// writable after its first small allocation.

#include <vdbi/HugePages.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

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

/// Size in kB of the mapping of this process that holds @a p and is writable (-1 if none).
long
writableMappingKb(const void* p)
{
    const auto address = reinterpret_cast<std::uintptr_t>(p);
    std::ifstream maps("/proc/self/maps");
    std::string line;
    while (std::getline(maps, line)) {
        std::istringstream fields(line);
        std::uintptr_t begin = 0, end = 0;
        char dash = 0;
        std::string permissions;
        fields >> std::hex >> begin >> dash >> end >> permissions;
        if (begin <= address && address < end) {
            return permissions.size() > 1 && permissions[1] == 'w' ? long((end - begin) >> 10)
                                                                   : -1;
        }
    }
    return -1;
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
    // A new thread's first allocation makes it a heap of its own (glibc's arenas).
    void* small = nullptr;
    std::thread([&small] { small = std::malloc(64); }).join();
    const long threadHeapKb = writableMappingKb(small);
    std::free(small);
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    // Printing a byte of the heap keeps the compiler from dropping the allocation.
    std::printf("tunables=%s\nhuge_kb=%ld\nthread_heap_kb=%ld\nbyte=%d\n",
                tunables ? tunables : "", after - before, threadHeapKb, int(heap[BYTES / 2]));
    std::free(heap);
    return 0;
}
