// Skinning kernels (library dqkit::skin): linear blend skinning (LBS), dual-quaternion skinning
// (DQS, Kavan et al. 2008, with the two-phase handling of scaled binds) and centre-of-rotation
// skinning (CoR, Le and Hodgins 2016), as a batch job over vertices in structure-of-arrays form,
// written as component arrays or as rows (x, y, z a vertex: SkinnedVertices).
//
// Per frame: update_palette turns the bones' rigid world transforms into the palette (one 3x4
// matrix and one dual quaternion per bone, float); a SkinningJob then skins a vertex range. Jobs
// allocate nothing; SkinningThreads keeps its threads between frames, so a frame allocates nothing
// (but for a call with several jobs, the first time it has that many: SkinningThreads::run).
//
// The kernels run on vectors of 4, 8 or 16 vertices (SSE2, SSE4.2, AVX2, AVX-512), the instruction set
// chosen at run time from the CPU by dqkit::simd (dq::simd::current_target; dq::simd::use_target
// limits it). Every vertex runs the same K influence slots (padding has weight 0), data is read from
// component arrays, each lane loads its bones' palette records whole and a transpose makes component
// vectors (no gathers), and the antipodality sign is a copysign (no branch). Every vector path
// performs the scalar path's operations in the same order without fused multiply-adds, so its
// results are bit-identical to the scalar path's (tested on every instruction set the CPU has);
// vertex counts that are no multiple of the width finish on the scalar path.
#pragma once

#include <atomic>
#include <cfenv>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <mutex>
#include <span>
#include <thread>
#include <vector>

#include "dq/skin/skin.hpp"
#include "dq/util/expected.hpp"

namespace dq {

enum class SkinningMethod { lbs, dqs, cor };

/// Per-frame bone transforms, one record per bone (a kernel loads a bone's record with whole
/// vector loads; each SIMD lane loads its bone's record, then a transpose). `matrices[12 b + 4 r + c]` is entry
/// (r, c) of bone b's full 3x4 skinning matrix W · B; `dual_quaternions[8 b + k]` is component k
/// (real w, x, y, z, dual w, x, y, z) of its rigid part W · rigid(B); `scale_shear[12 b + 4 r + c]`
/// is entry (r, c < 3) of B's scale/shear P (the linear phase of DQS and CoR; column 3 unused).
struct SkinPalette {
  explicit SkinPalette(std::size_t bones = 0);
  std::size_t size() const noexcept { return dual_quaternions.size() / 8; }
  std::vector<float> matrices, dual_quaternions, scale_shear;
};

/// Fills the palette from the bones' rigid world transforms (one per bone, the skeleton's
/// pose at the bones of this skin; unit dual quaternions: LBS would read a scaled one as a scale
/// and DQS normalize it, so the methods would disagree). Precondition: sizes match the skin.
/// Allocates nothing.
void update_palette(const Skin& skin, std::span<const DualQuaternion<double>> bone_world, SkinPalette& palette);

/// Skinned output: each quantity as component arrays of at least `first + count` entries each, or
/// as rows (below). Positions are always written; normals and tangents when given (non-empty
/// spans; the skin must have them).
struct SkinnedVertices {
  std::span<float> px{}, py{}, pz{};  // initialized, so that `{.positions = rows}` draws no -Wmissing-field-initializers
  std::span<float> nx{}, ny{}, nz{};
  std::span<float> tx{}, ty{}, tz{};
  /// Or a quantity as rows, in place of its three arrays: vertex i's x, y, z at [3 i, 3 i + 3), of
  /// at least 3 (first + count) floats (a NumPy (V, 3) float32 array; a GPU buffer of one vertex
  /// attribute). The kernels write rows as they write arrays, with the same values bit for bit,
  /// and no pass over the output after them.
  std::span<float> positions{}, normals{}, tangents{};
};

struct SkinningJob {
  const Skin* skin = nullptr;
  const SkinPalette* palette = nullptr;
  SkinningMethod method = SkinningMethod::dqs;
  SkinnedVertices out;
  std::size_t first = 0;  ///< vertex range [first, first + count)
  std::size_t count = 0;

  /// Says why the job cannot run: no skin or palette, a palette of another size, a range past
  /// the skin, output spans too short, a quantity with one or two of its three arrays, or given
  /// both as rows and as arrays, normals or tangents of a skin without them, outputs that overlap
  /// in the range, CoR without centres.
  Status validate() const;
  /// Runs on the calling thread. Precondition: validate() succeeds (checked).
  void run() const;
};

/// A fixed set of worker threads for skinning jobs, started once and reused every frame (no
/// thread creation per frame). run() cuts each job's range into parts of whole 16-vertex vectors,
/// of one size for all the jobs of a call: about kPartsPerThread per thread, plus at most one per
/// job (a job's last part, which may be smaller), and none but those smaller than `min_part`
/// vertices. The calling thread and the workers claim parts until none is left, and run() returns
/// when the claimed parts are done. A worker that wakes late claims fewer parts, or none, and a
/// call of at most `min_part` vertices in all runs on the calling thread alone, so a small call
/// costs about its time on one thread and not that plus a worker's wake-up (docs/skinning.md,
/// "Threads", has the measurements). A worker spins for up to `worker_spin_microseconds` (by
/// default 100 where the pool has a CPU per thread) for the next call before it sleeps, so that
/// calls back to back need no wake-up; a pool between frames sleeps. Several jobs in one call (the
/// meshes of a model) share the threads as one job would: small meshes need not each run alone.
/// The result does not depend on who runs a part: workers take the caller's floating-point
/// environment (rounding, flush-to-zero) for each call. One run() at a time: calls from several
/// threads need a lock of their own (the Python binding has one).
class SkinningThreads {
 public:
  /// The default `min_part`: on the machine of docs/skinning.md, handing a part to a worker costs
  /// a few microseconds, and 4096 vertices take about ten in cache.
  static constexpr std::size_t kDefaultMinPart = 4096;
  static constexpr unsigned kPartsPerThread = 4;
  static constexpr unsigned kSpinMicroseconds = 100;  ///< run() spins this long for the workers that joined a call before it sleeps
  static constexpr unsigned kWorkerSpinMicroseconds = 100;  ///< the automatic spin where every thread has a CPU
  /// `worker_spin_microseconds`'s default: kWorkerSpinMicroseconds when the pool has no more threads
  /// than the CPUs this process may run on (its affinity mask), else 0.
  static constexpr unsigned kAutomaticWorkerSpin = std::numeric_limits<unsigned>::max();

  /// `threads`: the total, the caller included (0 counts as 1). `min_part` is rounded up to a
  /// multiple of 16 (0 counts as 16; the largest values, to the largest multiple).
  /// `worker_spin_microseconds`: how long a worker watches for the next call, burning its core,
  /// before it sleeps; give 0 where cores are scarce in a way the affinity mask does not show (a
  /// container's CPU quota). Throws std::system_error, with no thread left running, when the
  /// system cannot start one.
  explicit SkinningThreads(unsigned threads, std::size_t min_part = kDefaultMinPart,
                           unsigned worker_spin_microseconds = kAutomaticWorkerSpin);
  ~SkinningThreads();
  SkinningThreads(const SkinningThreads&) = delete;
  SkinningThreads& operator=(const SkinningThreads&) = delete;
  unsigned size() const noexcept { return static_cast<unsigned>(workers_.size()) + 1; }
  std::size_t min_part() const noexcept { return min_part_; }
  unsigned worker_spin_microseconds() const noexcept { return worker_spin_; }
  /// Validates, then runs the job on the calling thread and the workers.
  Status run(const SkinningJob& job) { return run(std::span<const SkinningJob>(&job, 1)); }
  /// Validates every job, and that no two jobs write the same element; then runs them all, their
  /// parts claimed across the jobs. Nothing is written when a job is refused (the error names it).
  /// Inputs are not checked against outputs (a job must not write into a skin or palette it or
  /// another job reads). Allocates (and so may throw std::bad_alloc) only when a call has more jobs
  /// than every call before it on this pool: room for nine output ranges per job, sorted to find
  /// overlaps.
  Status run(std::span<const SkinningJob> jobs);

 private:
  void work();
  void stop();                             ///< ends and joins the workers
  /// Claims parts of the current call's jobs until none is left. A part cannot fail once its job
  /// has validated; noexcept, so that a bug would end the program rather than leave the call open.
  void run_parts() noexcept;
  std::size_t min_part_;
  unsigned worker_spin_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  // Under mutex_: the call's jobs, whether workers may still join it (open_), and how many have.
  std::span<const SkinningJob> jobs_;
  std::size_t part_size_ = 0, parts_ = 0;  // parts_: over all jobs, each job's parts after the last job's
  struct Written {
    std::uintptr_t begin, end;  // an output range [begin, end), in bytes
    std::size_t job;
  };
  std::vector<Written> written_;  // run()'s scratch: every job's output ranges, sorted
  std::fenv_t env_{};  // the caller's floating-point environment, set by each worker that joins
  std::atomic<std::size_t> next_part_{0};  // claimed by fetch_add; reset only while no worker holds a call
  std::atomic<std::size_t> generation_{0};  // changed under mutex_; read without it while a worker spins
  std::atomic<unsigned> joined_{0};       // changed under mutex_; read without it while run() spins
  bool open_ = false, stop_ = false;
};

}  // namespace dq
