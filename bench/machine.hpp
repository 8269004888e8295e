// The machine's limits for the benchmarks, measured in the same run as the cases they bound
// (bench_batch, bench_skin): the last-level cache size read from the CPU (32 MB on some machines of
// this kind, 260 MB on others), the CPU model, and STREAM's copy and triad bandwidth over arrays
// four times the last-level cache, on one or more threads.
#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

namespace dq::bench {

/// The last-level cache and where its size was read: Linux's sysfs, else the CPU's own word
/// (CPUID, through glibc's sysconf; some virtual machines have no cache entries in sysfs), else an
/// assumed 32 MB. A hypervisor may report the whole socket's cache, more than one core can use: the
/// arrays are then larger than they need be, which still puts them in memory, the safe direction.
struct CacheSize {
  std::size_t bytes;
  const char* source;
};
inline CacheSize last_level_cache() {
  std::size_t best = 0;
  for (int index = 0; index < 8; ++index) {
    std::ifstream f("/sys/devices/system/cpu/cpu0/cache/index" + std::to_string(index) + "/size");
    std::string s;
    if (!(f >> s)) continue;
    std::size_t v = std::strtoull(s.c_str(), nullptr, 10);
    if (s.back() == 'K') v <<= 10;
    if (s.back() == 'M') v <<= 20;
    best = std::max(best, v);
  }
  if (best) return {best, "sysfs"};
  for (int name : {_SC_LEVEL4_CACHE_SIZE, _SC_LEVEL3_CACHE_SIZE, _SC_LEVEL2_CACHE_SIZE}) {
    const long v = sysconf(name);
    if (v > 0) return {static_cast<std::size_t>(v), "cpuid"};
  }
  return {std::size_t{32} << 20, "assumed"};
}
inline std::size_t last_level_cache_bytes() { return last_level_cache().bytes; }

/// The benchmark's context keys for the cache: its size in MB and where that was read.
inline void add_cache_context() {
  const CacheSize cache = last_level_cache();
  benchmark::AddCustomContext("llc_MB", std::to_string(cache.bytes >> 20));
  benchmark::AddCustomContext("llc_source", cache.source);
}

inline std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

/// Floats per array for the DRAM cases: four times the last-level cache per array.
inline std::size_t dram_floats() { return 4 * last_level_cache_bytes() / sizeof(float); }

/// body(lo, hi) over [0, n) in `threads` equal parts, each on its own thread (one: the caller's).
template <class Body>
void split(unsigned threads, std::size_t n, Body body) {
  if (threads <= 1) return body(0, n);
  std::vector<std::thread> t;
  const std::size_t chunk = (n + threads - 1) / threads;
  for (unsigned k = 0; k < threads; ++k) t.emplace_back([&, k] { body(k * chunk, std::min(n, (k + 1) * chunk)); });
  for (auto& x : t) x.join();
}

/// STREAM's copy (b = a: 8 bytes per element) and triad (a = b + 3 c: 12 bytes per element) over
/// arrays of dram_floats() floats. Bytes are counted as STREAM counts them (the write-allocate
/// reads of the written array are not counted).
struct StreamArrays {
  std::vector<float> a, b, c;
  StreamArrays() : a(dram_floats(), 1.0f), b(dram_floats(), 1.0f), c(dram_floats(), 2.0f) {}
  std::size_t size() const { return a.size(); }
  void copy(unsigned threads) {
    split(threads, size(), [&](std::size_t lo, std::size_t hi) { std::copy(a.data() + lo, a.data() + hi, b.data() + lo); });
    benchmark::DoNotOptimize(b.data());
  }
  void triad(unsigned threads) {
    split(threads, size(), [&](std::size_t lo, std::size_t hi) {
      for (std::size_t i = lo; i < hi; ++i) a[i] = b[i] + 3.0f * c[i];
    });
    benchmark::DoNotOptimize(a.data());
  }
  static constexpr double copy_bytes = 2 * sizeof(float), triad_bytes = 3 * sizeof(float);
};

/// Copy and Triad as benchmark cases (state.range(0): threads), reporting bytes per second.
inline void Copy(benchmark::State& state) {
  StreamArrays s;
  for (auto _ : state) s.copy(static_cast<unsigned>(state.range(0)));
  state.SetBytesProcessed(static_cast<std::int64_t>(static_cast<double>(state.iterations()) * static_cast<double>(s.size()) * StreamArrays::copy_bytes));
  state.counters["array_MB"] = static_cast<double>(s.size() * sizeof(float)) / 1e6;
}
inline void Triad(benchmark::State& state) {
  StreamArrays s;
  for (auto _ : state) s.triad(static_cast<unsigned>(state.range(0)));
  state.SetBytesProcessed(static_cast<std::int64_t>(static_cast<double>(state.iterations()) * static_cast<double>(s.size()) * StreamArrays::triad_bytes));
  state.counters["array_MB"] = static_cast<double>(s.size() * sizeof(float)) / 1e6;
}

/// Bytes per second of copy or triad on `threads` threads, measured directly (the median of
/// `passes` passes, after one that touches the pages): the roof of the roofline counters.
enum class Stream { copy, triad };
inline double measure_bandwidth(Stream kind, unsigned threads, int passes = 5) {
  StreamArrays s;
  std::vector<double> seconds;
  for (int k = 0; k <= passes; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    kind == Stream::copy ? s.copy(threads) : s.triad(threads);
    if (k > 0) seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::nth_element(seconds.begin(), seconds.begin() + passes / 2, seconds.end());
  const double bytes = kind == Stream::copy ? StreamArrays::copy_bytes : StreamArrays::triad_bytes;
  return bytes * static_cast<double>(s.size()) / seconds[static_cast<std::size_t>(passes / 2)];
}

}  // namespace dq::bench
