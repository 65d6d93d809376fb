// SPDX-License-Identifier: Apache-2.0
/// @file probe/huge_pages_probe.cc
/// @brief Calls vdbi::restartWithHugePages() as a program's main() does, then touches 64 MiB
/// of heap in one block and 64 MiB in small blocks from a second thread, and prints what
/// TestHugePages checks: the tunables it runs with and how many kB of each the kernel backed
/// with huge pages.

#include <vdbi/HugePages.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

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
    constexpr std::size_t BYTES = std::size_t(64) << 20, BLOCK_BYTES = std::size_t(16) << 10;
    auto* heap = static_cast<char*>(std::malloc(BYTES));
    if (!heap) return 1;
    std::memset(heap, 1, BYTES);
    const long after = anonHugePagesKb();
    // Blocks below the mmap threshold from another thread: glibc serves them from a heap of
    // that thread's own unless there is one arena only.
    std::vector<char*> blocks(BYTES / BLOCK_BYTES);
    std::thread([&blocks] {
        for (char*& block : blocks) {
            block = static_cast<char*>(std::malloc(BLOCK_BYTES));
            if (block) std::memset(block, 1, BLOCK_BYTES);
        }
    }).join();
    const long afterThread = anonHugePagesKb();
    int sum = int(heap[BYTES / 2]);
    for (char* block : blocks) sum += block ? block[BLOCK_BYTES / 2] : 0;
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    // Printing bytes of the heap keeps the compiler from dropping the allocations.
    std::printf("tunables=%s\nhuge_kb=%ld\nthread_huge_kb=%ld\nbytes=%d\n",
                tunables ? tunables : "", after - before, afterThread - after, sum);
    for (char* block : blocks) std::free(block);
    std::free(heap);
    return 0;
}
