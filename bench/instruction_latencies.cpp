// Latencies of the instructions on the paths of the compose chains (docs/performance.md), measured
// on this machine: the machines here have no hardware counters for `perf stat`, and the latencies
// differ between the AMD and Intel machines of this kind.
//   instruction_latencies
// Each instruction runs as a chain of dependent copies (its result is its next input); the time per
// copy, divided by that of a chain of integer additions (one cycle on every x86-64 core), is its
// latency in cycles. The best of five runs of each chain; prints a Markdown table.
#include <chrono>
#include <cstdio>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
namespace {

using float4 = float __attribute__((vector_size(16)));
using float8 = float __attribute__((vector_size(32)));
constexpr long kCopies = 20'000'000;

/// The best time per copy, in ns, of five runs of `run` (which performs kCopies dependent copies).
double best_ns(void (*run)()) {
  double best = 1e300;
  for (int r = 0; r < 5; ++r) {
    const auto start = std::chrono::steady_clock::now();
    run();
    const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() / kCopies;
    if (ns < best) best = ns;
  }
  return best;
}

// One chain per instruction: kCopies / 4 iterations of four dependent copies. %0 is the chained
// register (ymm for float8, %x0 its xmm half); %1 a second register of ones (xorps of a register
// with itself would break the chain); %2 the address of a 32-byte buffer for the store-and-load chains.
#define DQKIT_CHAIN(name, type, text)                                                             \
  [[gnu::target("avx2,fma"), gnu::noinline]] void name##_chain() {                              \
    type v{1, 1, 1, 1}, ones{1, 1, 1, 1};                                                       \
    alignas(32) float buffer[8] = {};                                                           \
    for (long i = 0; i < kCopies / 4; ++i)                                                      \
      asm volatile(text "\n\t" text "\n\t" text "\n\t" text : "+x"(v) : "x"(ones), "r"(buffer) : "memory"); \
  }                                                                                             \
  double name() { return best_ns(name##_chain); }
DQKIT_CHAIN(addps, float4, "addps %x0, %x0")
DQKIT_CHAIN(mulps, float4, "mulps %x0, %x0")
DQKIT_CHAIN(shufps, float4, "shufps $0x1b, %x0, %x0")
DQKIT_CHAIN(xorps, float4, "xorps %x1, %x0")
DQKIT_CHAIN(vxorps, float4, "vxorps %x1, %x0, %x0")
DQKIT_CHAIN(vaddps, float8, "vaddps %0, %0, %0")
DQKIT_CHAIN(vmulps, float8, "vmulps %0, %0, %0")
DQKIT_CHAIN(vfmadd, float8, "vfmadd231ps %0, %0, %0")
DQKIT_CHAIN(vpermilps_xmm, float4, "vpermilps $0x1b, %x0, %x0")
DQKIT_CHAIN(vpermilps_ymm, float8, "vpermilps $0x1b, %0, %0")
DQKIT_CHAIN(vbroadcastss, float8, "vbroadcastss %x0, %0")
DQKIT_CHAIN(vinsertf128, float8, "vinsertf128 $1, %x0, %0, %0")
DQKIT_CHAIN(vextractf128, float8, "vextractf128 $1, %0, %x0")
DQKIT_CHAIN(vperm2f128, float8, "vperm2f128 $0x01, %0, %0, %0")
DQKIT_CHAIN(store_load, float4, "vmovaps %x0, (%2)\n\tvmovaps (%2), %x0")
DQKIT_CHAIN(store_broadcast, float8, "vmovaps %x0, (%2)\n\tvbroadcastss 4(%2), %0")
DQKIT_CHAIN(store_halves_load, float8, "vmovaps %x0, (%2)\n\tvmovaps %x0, 16(%2)\n\tvmovaps (%2), %0")
#undef DQKIT_CHAIN

[[gnu::noinline]] void integer_add_chain() {
  long x = 0;
  for (long i = 0; i < kCopies / 4; ++i) asm volatile("add $1, %0\n\tadd $1, %0\n\tadd $1, %0\n\tadd $1, %0" : "+r"(x));
}
double integer_add() { return best_ns(integer_add_chain); }

}  // namespace

int main() {
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) {
    std::puts("instruction_latencies: this CPU has no AVX2 and FMA");
    return 0;
  }
  const double cycle = integer_add();
  std::printf("One cycle: %.3f ns (%.2f GHz), from a chain of integer additions.\n\n", cycle, 1 / cycle);
  std::puts("| instruction | on the path of | latency, cycles |\n| --- | --- | ---: |");
  const struct {
    const char* name;
    const char* where;
    double (*measure)();
  } rows[] = {
      {"`addps`", "portable sums", addps},
      {"`mulps`", "portable products", mulps},
      {"`shufps`", "portable broadcasts and permutations", shufps},
      {"`xorps`", "a sign flip", xorps},
      {"`vxorps` (xmm)", "a sign flip, AVX encoding", vxorps},
      {"`vaddps` (ymm)", "AVX sums", vaddps},
      {"`vmulps` (ymm)", "AVX products", vmulps},
      {"`vfmadd231ps` (ymm)", "a contracted product and sum; Eigen's product", vfmadd},
      {"`vpermilps` (xmm)", "a four-lane permutation", vpermilps_xmm},
      {"`vpermilps` (ymm)", "an eight-lane permutation within halves", vpermilps_ymm},
      {"`vbroadcastss` ymm ← xmm", "a broadcast from a register", vbroadcastss},
      {"`vinsertf128`", "joining two quaternions into eight lanes", vinsertf128},
      {"`vextractf128`", "taking the high half (the eight-lane dual part)", vextractf128},
      {"`vperm2f128`", "moving a half across", vperm2f128},
      {"16-byte store, 16-byte load", "a chained value kept in memory", store_load},
      {"16-byte store, `vbroadcastss` load", "a component broadcast from memory just stored", store_broadcast},
      {"two 16-byte stores, one 32-byte load", "eight lanes read over two halves just stored", store_halves_load},
  };
  for (const auto& r : rows) std::printf("| %s | %s | %.1f |\n", r.name, r.where, r.measure() / cycle);
}
#else
int main() { std::puts("instruction_latencies: x86-64 only"); }
#endif
