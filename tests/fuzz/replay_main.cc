// SPDX-License-Identifier: Apache-2.0
/// @file fuzz/replay_main.cc
/// @brief A main() for the fuzz targets without libFuzzer (any compiler), for the test suite.
/// @details
///     replay_<target> [-runs=N] [-max_total_time=S] [-seed=K] [-crash=FILE] INPUT...
///
/// Runs LLVMFuzzerTestOneInput on every INPUT (a file, or every file of a folder), then on
/// up to N pseudo-random mutations of them (default 100000), stopping after S seconds
/// (default 5). The mutations are deterministic for a given seed (default 1): a failure seen
/// once comes back with the same command, at least as far as the time limit lets it run.
/// There is no coverage feedback; some mutants join the pool, so that mutations stack.
/// When the target crashes, aborts or a sanitizer reports, the input at fault is written to
/// FILE (default replay-crash.bin in the working folder) for libFuzzer or a debugger.

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__)
#define VDBI_REPLAY_HAS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VDBI_REPLAY_HAS_SANITIZER 1
#endif
#endif
#ifdef VDBI_REPLAY_HAS_SANITIZER
#include <sanitizer/common_interface_defs.h>
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr std::size_t MAX_INPUT_BYTES = 1 << 16;
constexpr std::size_t MAX_POOL = 512;

// The input being run and where to save it, for the crash handlers (async-signal-safe).
const std::uint8_t* gCurrentData = nullptr;
std::size_t gCurrentSize = 0;
std::string gCrashPath = "replay-crash.bin";

void
saveCurrentInput()
{
    if (gCurrentData == nullptr) return;
    const int fd = ::open(gCrashPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) return;
    std::size_t done = 0;
    while (done < gCurrentSize) {
        const ssize_t n = ::write(fd, gCurrentData + done, gCurrentSize - done);
        if (n <= 0) break;
        done += std::size_t(n);
    }
    ::close(fd);
    static const char message[] = "\nreplay: the input at fault was written to ";
    ssize_t ignored = ::write(2, message, sizeof(message) - 1);
    ignored = ::write(2, gCrashPath.c_str(), gCrashPath.size());
    ignored = ::write(2, "\n", 1);
    (void)ignored;
    gCurrentData = nullptr;
}

extern "C" void
onFatalSignal(int sig)
{
    saveCurrentInput();
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

/// splitmix64: small, fast and the same everywhere (std distributions are not).
class Random
{
public:
    explicit Random(std::uint64_t seed): mState(seed) {}
    std::uint64_t next()
    {
        std::uint64_t z = (mState += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    /// Uniform enough in [0, n); 0 for n == 0.
    std::size_t below(std::size_t n) { return n == 0 ? 0 : std::size_t(next() % n); }

private:
    std::uint64_t mState;
};

void
putLE32(Bytes& b, std::size_t at, std::uint32_t v)
{
    for (int k = 0; k < 4 && at + std::size_t(k) < b.size(); ++k) {
        b[at + std::size_t(k)] = std::uint8_t(v >> (8 * k));
    }
}

/// One random edit of @a b; @a other is a second corpus entry for splicing.
void
mutate(Bytes& b, const Bytes& other, Random& rng)
{
    static const std::uint8_t BYTES[] = {0, 1, 2, 0x7f, 0x80, 0xfe, 0xff, '0', '9', '=', '\n',
        ' '};
    static const std::uint32_t WORDS[] = {0, 1, 2, 4, 12, 255, 256, 0x7fff, 0xffff, 0x10000,
        0x7fffffff, 0x80000000, 0xffffffff, 0xfffffffe, 150, 200};
    static const char* const NUMBERS[] = {"0", "1", "-1", "2147483647", "2147483648",
        "-2147483648", "4294967296", "99999999999999999999", "1e308", "-0", "nan", "inf",
        "0.5", "+3", "1 1"};
    const std::size_t size = b.size();
    switch (rng.below(11)) {
    case 0: // flip a bit
        if (size) b[rng.below(size)] ^= std::uint8_t(1u << rng.below(8));
        break;
    case 1: // a random byte
        if (size) b[rng.below(size)] = std::uint8_t(rng.next());
        break;
    case 2: // an interesting byte
        if (size) b[rng.below(size)] = BYTES[rng.below(sizeof(BYTES))];
        break;
    case 3: // an interesting 32-bit little-endian word, often aligned (chunk sizes, counts)
        if (size) {
            std::size_t at = rng.below(size);
            if (rng.below(2)) at &= ~std::size_t(3);
            std::uint32_t word = WORDS[rng.below(sizeof(WORDS) / sizeof(WORDS[0]))];
            if (rng.below(4) == 0) word += std::uint32_t(rng.below(9)) - 4u;
            putLE32(b, at, word);
        }
        break;
    case 4: { // erase a range
        if (!size) break;
        const std::size_t at = rng.below(size);
        const std::size_t n = 1 + rng.below(std::min<std::size_t>(size - at, 16));
        b.erase(b.begin() + std::ptrdiff_t(at), b.begin() + std::ptrdiff_t(at + n));
        break;
    }
    case 5: { // insert random bytes
        const std::size_t at = rng.below(size + 1);
        Bytes extra(1 + rng.below(8));
        for (auto& x : extra) x = std::uint8_t(rng.next());
        b.insert(b.begin() + std::ptrdiff_t(at), extra.begin(), extra.end());
        break;
    }
    case 6: { // copy a range of this input or another one to a random place
        const Bytes& from = rng.below(2) ? b : other;
        if (from.empty()) break;
        const std::size_t start = rng.below(from.size());
        const std::size_t n = 1 + rng.below(std::min<std::size_t>(from.size() - start, 64));
        const Bytes piece(from.begin() + std::ptrdiff_t(start),
                          from.begin() + std::ptrdiff_t(start + n));
        b.insert(b.begin() + std::ptrdiff_t(rng.below(b.size() + 1)), piece.begin(), piece.end());
        break;
    }
    case 7: // truncate
        b.resize(rng.below(size + 1));
        break;
    case 8: { // splice: a prefix of this, a suffix of the other
        const std::size_t cut = rng.below(size + 1);
        const std::size_t from = rng.below(other.size() + 1);
        b.resize(cut);
        b.insert(b.end(), other.begin() + std::ptrdiff_t(from), other.end());
        break;
    }
    case 9: { // replace a run of digits (text formats) with an interesting number
        if (!size) break;
        std::size_t at = rng.below(size);
        while (at < size && !(b[at] >= '0' && b[at] <= '9')) ++at;
        if (at == size) break;
        std::size_t end = at;
        while (end < size && ((b[end] >= '0' && b[end] <= '9') || b[end] == '.')) ++end;
        const char* number = NUMBERS[rng.below(sizeof(NUMBERS) / sizeof(NUMBERS[0]))];
        b.erase(b.begin() + std::ptrdiff_t(at), b.begin() + std::ptrdiff_t(end));
        b.insert(b.begin() + std::ptrdiff_t(at), number, number + std::strlen(number));
        break;
    }
    default: { // swap two bytes
        if (size < 2) break;
        std::swap(b[rng.below(size)], b[rng.below(size)]);
        break;
    }
    }
    if (b.size() > MAX_INPUT_BYTES) b.resize(MAX_INPUT_BYTES);
}

void
runOne(const Bytes& input)
{
    gCurrentData = input.data();
    gCurrentSize = input.size();
    // A copy of exactly the input's size, so that ASan sees reads past its end.
    std::unique_ptr<std::uint8_t[]> copy(
        new std::uint8_t[std::max<std::size_t>(input.size(), 1)]);
    std::copy(input.begin(), input.end(), copy.get());
    LLVMFuzzerTestOneInput(input.empty() ? nullptr : copy.get(), input.size());
    gCurrentData = nullptr;
}

bool
readFile(const std::filesystem::path& path, Bytes& bytes)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return !in.bad();
}

bool
startsWith(const std::string& s, const char* prefix)
{
    return s.compare(0, std::strlen(prefix), prefix) == 0;
}

} // namespace

int
main(int argc, char** argv)
{
    namespace fs = std::filesystem;
    std::uint64_t runs = 100000, seed = 1;
    double seconds = 5.0;
    std::vector<fs::path> inputs;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (startsWith(arg, "-runs=")) {
            runs = std::strtoull(arg.c_str() + 6, nullptr, 10);
        } else if (startsWith(arg, "-max_total_time=")) {
            seconds = std::strtod(arg.c_str() + 16, nullptr);
        } else if (startsWith(arg, "-seed=")) {
            seed = std::strtoull(arg.c_str() + 6, nullptr, 10);
        } else if (startsWith(arg, "-crash=")) {
            gCrashPath = arg.substr(7);
        } else if (!arg.empty() && arg[0] == '-') {
            std::fprintf(stderr, "usage: %s [-runs=N] [-max_total_time=S] [-seed=K] "
                "[-crash=FILE] INPUT...\n", argv[0]);
            return 2;
        } else if (fs::is_directory(arg)) {
            std::vector<fs::path> files;
            for (const auto& entry : fs::directory_iterator(arg)) {
                if (entry.is_regular_file()) files.push_back(entry.path());
            }
            std::sort(files.begin(), files.end()); // a fixed order: deterministic mutations
            inputs.insert(inputs.end(), files.begin(), files.end());
        } else {
            inputs.push_back(arg);
        }
    }
    for (const int sig : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL}) {
        std::signal(sig, onFatalSignal);
    }
#ifdef VDBI_REPLAY_HAS_SANITIZER
    __sanitizer_set_death_callback(saveCurrentInput);
#endif

    const auto start = std::chrono::steady_clock::now();
    std::vector<Bytes> pool;
    for (const fs::path& path : inputs) {
        Bytes bytes;
        if (!readFile(path, bytes)) {
            std::fprintf(stderr, "replay: cannot read %s\n", path.c_str());
            return 2;
        }
        std::fprintf(stderr, "replay: %s (%zu bytes)\n", path.c_str(), bytes.size());
        runOne(bytes);
        pool.push_back(std::move(bytes));
    }
    if (pool.empty()) pool.emplace_back(); // mutate from nothing
    const std::size_t seeds = pool.size();  // never replaced

    Random rng(seed);
    std::uint64_t done = 0;
    for (; done < runs; ++done) {
        if ((done & 15) == 0) {
            const std::chrono::duration<double> elapsed =
                std::chrono::steady_clock::now() - start;
            if (elapsed.count() >= seconds) break;
        }
        Bytes mutant = pool[rng.below(pool.size())];
        const Bytes& other = pool[rng.below(pool.size())];
        for (std::size_t n = 1 + rng.below(4); n > 0; --n) mutate(mutant, other, rng);
        runOne(mutant);
        if (rng.below(8) == 0) { // let some mutants be mutated further
            if (pool.size() < seeds + MAX_POOL) {
                pool.push_back(std::move(mutant));
            } else {
                pool[seeds + rng.below(MAX_POOL)] = std::move(mutant);
            }
        }
    }
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    std::fprintf(stderr, "replay: %zu inputs and %llu mutations (seed %llu) in %.1f s: no"
        " failure\n", inputs.size(), static_cast<unsigned long long>(done),
        static_cast<unsigned long long>(seed), elapsed.count());
    return 0;
}
