// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/HugePages.h
/// @brief Lets a program's heap use transparent huge pages, for the executables built on the
/// library (the CLI, the benchmarks).
/// @details The pipeline touches hundreds of MB of new memory (the fine grid, the block
/// meshes, the output arrays), one 4 KiB page fault at a time with glibc's default malloc.
/// Where faults are expensive (virtual machines: ~15 us each was measured on the project's
/// build machines) they took about 40 % of a frog CLI run; with 2 MiB pages there are about
/// 7 times fewer faults and fewer TLB misses. Where the kernel offers transparent huge pages
/// only on request ("madvise", the common default), glibc >= 2.35 makes that request for its
/// heap when the tunable glibc.malloc.hugetlb=1 is set, and tunables are read only when a
/// process starts: hence a restart of the program with it set.
/// The restart also sets glibc.malloc.top_pad to 64 MiB: how much more than asked the heap
/// grows by. A thread's heap (each thread that allocates gets one of its own) otherwise grows
/// a few pages at a time, one mprotect() per growth, and the kernel backs a fault with a huge
/// page only where the 2 MiB around it are already writable. A frog CLI run without
/// remeshing on 2 threads made 5 230 such calls, with the pad 56; its fattening took 0.08 s
/// instead of 0.02 s, the whole run 0.67 s instead of 0.53 s (medians of 5). The pad is
/// address space, not memory: pages count only once touched (that run's peak stays 350 MiB;
/// with remeshing at 2 voxels it went from 1.01-1.04 to 1.08 GiB).
/// Setting it freezes glibc's mmap and trim thresholds, so the restart sets them too, to the
/// values glibc's own rule raises them to (32 and 64 MiB).

#ifndef VDBI_HUGE_PAGES_HAS_BEEN_INCLUDED
#define VDBI_HUGE_PAGES_HAS_BEEN_INCLUDED

namespace vdbi {

/// @brief Restarts the program (same process, same arguments) with glibc's heap on
/// transparent huge pages, where that helps; otherwise returns and the program goes on.
/// @details Call it first thing in main(): before the program blocks signals (the mask
/// survives the restart) or writes to a buffered stream (what is still buffered is lost).
/// Threads started by static initialisers do no harm: the restart ends them. It returns
/// without restarting when GLIBC_TUNABLES already names glibc.malloc.hugetlb (the user's
/// choice, or the restart already happened: set glibc.malloc.hugetlb=0 to opt out; a pad or
/// threshold the user set is kept too), when the program runs under valgrind (whose tools
/// would not follow the restart), when the kernel's mode is not "madvise" (always: nothing
/// to gain; never: nothing to have), when glibc is older than 2.35, or when the restart
/// fails.
/// It changes nothing off Linux and glibc, and not the memory a run needs: the page size of
/// the heap changes, and how it grows.
/// @param argv  main()'s argv, passed on unchanged
void restartWithHugePages(char** argv);

} // namespace vdbi

#endif // VDBI_HUGE_PAGES_HAS_BEEN_INCLUDED
