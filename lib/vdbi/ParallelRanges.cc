// SPDX-License-Identifier: Apache-2.0

#include <vdbi/ParallelRanges.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace vdbi {

void
forEachRange(std::size_t count, std::size_t grain, bool threaded,
             const std::function<void(std::size_t begin, std::size_t end)>& body)
{
    if (count == 0) return;
    if (!threaded) {
        body(0, count);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, grain),
                      [&body](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
}

} // namespace vdbi
