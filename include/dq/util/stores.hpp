// How a batch job writes its results: the choice between keeping them in the cache and streaming
// them past it (BlockedForwardKinematicsJob::stores).
#pragma once

namespace dq {

/// How a batch job writes its results. A hint for the vector kernels; the results are the same
/// bits either way.
enum class Stores {
  /// Ordinary stores: the results stay in the cache for whatever reads them next.
  cached,
  /// Non-temporal stores, past the cache, for batches larger than the last-level cache whose
  /// results are not read at once: a store then does not first read the line it overwrites
  /// (write-allocate), nor evict data still to be read. It costs where the results would have
  /// been read from the cache.
  streaming,
};

}  // namespace dq
