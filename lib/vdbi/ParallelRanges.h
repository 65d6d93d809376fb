// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/ParallelRanges.h
/// @brief The one parallel loop of the stages: ranges of indices, with TBB or in the calling
/// thread (every stage has a `threaded` switch, and its result must not depend on it).

#ifndef VDBI_PARALLEL_RANGES_HAS_BEEN_INCLUDED
#define VDBI_PARALLEL_RANGES_HAS_BEEN_INCLUDED

#include <cstddef>
#include <functional>

namespace vdbi {

/// @brief Calls @a body(begin, end) for ranges [begin, end) that together cover [0, count)
/// once: with TBB (tbb::parallel_for over a blocked_range of grain @a grain) when
/// @a threaded, else once for all of [0, count) in the calling thread.
/// @details A call per range, not per index: the body loops over its range itself, so the
/// type erasure costs nothing measurable, and this header needs no TBB.
void forEachRange(std::size_t count, std::size_t grain, bool threaded,
                  const std::function<void(std::size_t begin, std::size_t end)>& body);

} // namespace vdbi

#endif // VDBI_PARALLEL_RANGES_HAS_BEEN_INCLUDED
