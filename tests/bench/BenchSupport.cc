// SPDX-License-Identifier: Apache-2.0

#include "BenchSupport.h"

#include <openvdb/openvdb.h>

#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>

namespace vdbi_bench {

double
cpuSeconds()
{
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

double
childCpuSeconds()
{
    struct rusage usage;
    std::memset(&usage, 0, sizeof usage);
    getrusage(RUSAGE_CHILDREN, &usage);
    auto toSeconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
    return toSeconds(usage.ru_utime) + toSeconds(usage.ru_stime);
}

double
median(std::vector<double> v)
{
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double
ratio(double a, double b)
{
    return b > 0 ? a / b : 0.0;
}

MemKb
readMem()
{
    MemKb m;
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmRSS:", 0) == 0) m.rss = std::atol(line.c_str() + 6);
        if (line.rfind("VmHWM:", 0) == 0) m.hwm = std::atol(line.c_str() + 6);
    }
    return m;
}

bool
resetPeak()
{
    malloc_trim(0);
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    clear.flush();
    return bool(clear);
}

std::string
loadAverage()
{
    std::ifstream f("/proc/loadavg");
    std::string a, b, c;
    f >> a >> b >> c;
    return a + " " + b + " " + c;
}

std::string
heapPages()
{
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    const std::string t = tunables ? tunables : "";
    return t.find("glibc.malloc.hugetlb=1") != std::string::npos
        ? "transparent huge pages requested (GLIBC_TUNABLES=" + t + ")"
        : "4 KiB pages (the system malloc's default)";
}

long long
meshBytes(const vdbi::InterfaceMesh& m)
{
    return (long long)(m.points.size() * sizeof(openvdb::Vec3d)
        + m.triangles.size() * sizeof(openvdb::Vec3I)
        + m.pointKeys.size() * sizeof(vdbi::VertexKey)
        + m.patches.size() * sizeof(vdbi::InterfacePatch));
}

bool
runInChild(const std::function<void()>& fill, void* out, std::size_t size, long& maxRssKb)
{
    int fd[2];
    if (pipe(fd) != 0) { std::perror("pipe"); std::exit(1); }
    std::fflush(stdout);
    std::fflush(stderr);
    const pid_t pid = fork();
    if (pid < 0) { std::perror("fork"); std::exit(1); }
    if (pid == 0) {
        close(fd[0]);
        bool ok = false;
        try {
            openvdb::initialize();
            fill();
            const char* p = static_cast<const char*>(out);
            std::size_t left = size;
            while (left > 0) {
                const ssize_t w = write(fd[1], p, left);
                if (w <= 0) break;
                p += w;
                left -= std::size_t(w);
            }
            ok = left == 0;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "child: %s\n", e.what());
        }
        close(fd[1]);
        std::fflush(stdout);
        _exit(ok ? 0 : 1);
    }
    close(fd[1]);
    char* p = static_cast<char*>(out);
    std::size_t got = 0;
    while (got < size) {
        const ssize_t n = read(fd[0], p + got, size - got);
        if (n <= 0) break;
        got += std::size_t(n);
    }
    close(fd[0]);
    int status = 0;
    struct rusage usage;
    std::memset(&usage, 0, sizeof usage);
    wait4(pid, &status, 0, &usage);
    maxRssKb = usage.ru_maxrss;
    return got == size && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

} // namespace vdbi_bench
