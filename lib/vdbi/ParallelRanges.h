// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/ParallelRanges.h
/// @brief The parallel loops of the stages: ranges of indices, or pieces largest first, with
/// TBB or in the calling thread (every stage has a `threaded` switch, and its result must not
/// depend on it).

#ifndef VDBI_PARALLEL_RANGES_HAS_BEEN_INCLUDED
#define VDBI_PARALLEL_RANGES_HAS_BEEN_INCLUDED

#include <cstddef>
#include <functional>
#include <vector>

namespace vdbi {

/// @brief Calls @a body(begin, end) for ranges [begin, end) that together cover [0, count)
/// once: with TBB (tbb::parallel_for over a blocked_range of grain @a grain) when
/// @a threaded, else once for all of [0, count) in the calling thread.
/// @details A call per range, not per index: the body loops over its range itself, so the
/// type erasure costs nothing measurable, and this header needs no TBB.
void forEachRange(std::size_t count, std::size_t grain, bool threaded,
                  const std::function<void(std::size_t begin, std::size_t end)>& body);

/// @brief Calls @a body(i) for every i in [0, sizes.size()), with TBB when @a threaded: the
/// largest sizes[i] first, each thread taking the next when it is done with one.
/// @details For work in a few pieces of very different sizes (patches: the largest of the
/// frog holds a third of its triangles). The largest starts at once and the last to start
/// are the smallest, so the threads finish close together; a parallel_for over the sorted
/// pieces lets a thread steal the far, small end of the range first. A body that throws
/// cancels the rest: no thread takes a new piece, and the exception reaches the caller.
void forEachLargestFirst(const std::vector<std::size_t>& sizes, bool threaded,
                         const std::function<void(std::size_t i)>& body);

} // namespace vdbi

#endif // VDBI_PARALLEL_RANGES_HAS_BEEN_INCLUDED
