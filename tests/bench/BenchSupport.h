// SPDX-License-Identifier: Apache-2.0
/// @file bench/BenchSupport.h
/// @brief What the benchmark programs share: clocks, medians, the process's memory (VmRSS,
/// VmHWM and its reset), the load average, and forked children that send a result back.

#pragma once

#include <vdbi/InterfaceMesh.h>

#include <chrono>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

namespace vdbi_bench {

using Clock = std::chrono::steady_clock;

inline double
seconds(Clock::time_point a, Clock::time_point b)
{
    return std::chrono::duration<double>(b - a).count();
}

/// CPU seconds of this process, all threads.
double cpuSeconds();

/// CPU seconds (user + system) of the children this process has waited for.
double childCpuSeconds();

/// The median of @a v (0 if empty).
double median(std::vector<double> v);

/// a / b, or 0 when b is not positive (a figure that was not measured).
double ratio(double a, double b);

/// VmRSS and VmHWM of this process in kB (0 if /proc is not readable).
struct MemKb
{
    long rss = 0, hwm = 0;
};
MemKb readMem();

/// Returns freed heap to the system and resets VmHWM to the current RSS.
/// @return false if the peak cannot be reset (then per-stage peaks are not reported)
bool resetPeak();

/// The 1, 5 and 15 minute load averages, as /proc/loadavg gives them.
std::string loadAverage();

/// The page size the heap asks for: the benchmarks restart themselves with huge pages as the
/// CLI does (vdbi::restartWithHugePages), unless GLIBC_TUNABLES says otherwise.
std::string heapPages();

/// Bytes of the mesh's arrays (points, triangles, keys, patches), at their sizes.
long long meshBytes(const vdbi::InterfaceMesh& mesh);

/// Forks; the child initializes OpenVDB, runs @a fill (which stores the result in the
/// child's copy of @a out) and sends the @a size bytes at @a out back through a pipe.
/// @param maxRssKb  the child's peak RSS (ru_maxrss from wait4())
/// @return false if the child failed
bool runInChild(const std::function<void()>& fill, void* out, std::size_t size,
    long& maxRssKb);

/// Runs @a body in a forked child of its own and stores what it returns in @a out, so that
/// every measurement gets a fresh heap and a peak RSS of its own. The parent never starts
/// TBB, so every child may set its own thread limit.
template<typename T, typename Body>
bool
inChild(const Body& body, T& out, long& maxRssKb)
{
    static_assert(std::is_trivially_copyable<T>::value, "the result is sent as bytes");
    return runInChild([&] { out = body(); }, &out, sizeof(T), maxRssKb);
}

} // namespace vdbi_bench
