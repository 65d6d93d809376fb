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

#ifndef VDBI_HUGE_PAGES_HAS_BEEN_INCLUDED
#define VDBI_HUGE_PAGES_HAS_BEEN_INCLUDED

namespace vdbi {

/// @brief Restarts the program (same process, same arguments) with glibc's heap on
/// transparent huge pages, where that helps; otherwise returns and the program goes on.
/// @details Call it first thing in main(): before the program blocks signals (the mask
/// survives the restart) or writes to a buffered stream (what is still buffered is lost).
/// Threads started by static initialisers do no harm: the restart ends them. It returns
/// without restarting when GLIBC_TUNABLES already names glibc.malloc.hugetlb (the user's
/// choice, or the restart already happened: set glibc.malloc.hugetlb=0 to opt out), when
/// the program runs under valgrind (whose tools would not follow the restart), when the
/// kernel's mode is not "madvise" (always: nothing to gain; never: nothing to have), when
/// glibc is older than 2.35, or when the restart fails.
/// It changes nothing off Linux and glibc. Memory use is the same: only the page size of
/// the heap changes.
/// @param argv  main()'s argv, passed on unchanged
void restartWithHugePages(char** argv);

} // namespace vdbi

#endif // VDBI_HUGE_PAGES_HAS_BEEN_INCLUDED
