// SPDX-License-Identifier: Apache-2.0

#include <vdbi/ParallelRanges.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <numeric>

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


void
forEachLargestFirst(const std::vector<std::size_t>& sizes, bool threaded,
                    const std::function<void(std::size_t i)>& body)
{
    const std::size_t count = sizes.size();
    std::vector<std::size_t> order(count);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t x, std::size_t y) { return sizes[x] > sizes[y]; });
    std::atomic<std::size_t> next(0);
    auto run = [&] {
        for (std::size_t i = next++; i < count && !tbb::is_current_task_group_canceling();
             i = next++) {
            body(order[i]);
        }
    };
    if (!threaded) return run();
    const std::size_t threads =
        std::min<std::size_t>(count, std::size_t(tbb::this_task_arena::max_concurrency()));
    tbb::task_group group;
    for (std::size_t t = 0; t < threads; ++t) group.run(run);
    group.wait();
}

} // namespace vdbi
