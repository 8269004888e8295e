// Owning storage for batches in structure-of-arrays layout: N arrays of n values each (the x, y, z
// of points, the twelve entries of 3x4 matrices, the eight components of dual quaternions), laid
// out for SIMD and for streaming far beyond the cache.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <memory>
#include <new>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace dq {

/// N arrays of `size()` values of T, allocated once at construction and zeroed. Every array starts
/// on a 64-byte cache line, and consecutive arrays are an odd number of lines apart (one or two
/// lines of padding), so that no two of the first 64 arrays are a multiple of 4 KiB apart. Arrays
/// a multiple of 4 KiB apart map to the same cache sets (and look alike to the prefetchers), and
/// the streams of a kernel evict each other: the batch forward kinematics ran 1.3–1.55 × faster
/// on padded, skewed arrays with no change to the kernel. Move-only; a moved-from object has size
/// 0 and no arrays.
template <class T, std::size_t N>
class ComponentArrays {
 public:
  static constexpr std::size_t alignment = 64;
  static constexpr std::size_t line = alignment / sizeof(T);  ///< values per cache line
  static_assert(N > 0 && alignment % sizeof(T) == 0);
  static_assert(std::is_arithmetic_v<T>, "ComponentArrays holds numbers (no constructors or destructors run)");

  ComponentArrays() = default;
  /// Throws std::length_error when N arrays of `size` values cannot be addressed.
  explicit ComponentArrays(std::size_t size)
      : size_(size), distance_(distance_for(size)), data_(allocate(N * distance_)) {}
  ComponentArrays(ComponentArrays&& other) noexcept
      : size_(std::exchange(other.size_, 0)), distance_(std::exchange(other.distance_, 0)), data_(std::move(other.data_)) {}
  ComponentArrays& operator=(ComponentArrays&& other) noexcept {
    size_ = std::exchange(other.size_, 0);
    distance_ = std::exchange(other.distance_, 0);
    data_ = std::move(other.data_);
    return *this;
  }

  /// Values per array.
  std::size_t size() const noexcept { return size_; }
  /// The largest size whose N padded arrays can be addressed (larger ones throw).
  static constexpr std::size_t max_size() noexcept { return std::numeric_limits<std::size_t>::max() / sizeof(T) / N - 3 * line; }
  /// Array k (k < N).
  std::span<T> operator[](std::size_t k) noexcept { return {data_.get() + k * distance_, size_}; }
  std::span<const T> operator[](std::size_t k) const noexcept { return {data_.get() + k * distance_, size_}; }
  /// The N array starts, in the form the batch kernels take (dq::simd::transform_points, ...).
  std::array<T*, N> data() noexcept { return starts<T>(*this); }
  std::array<const T*, N> data() const noexcept { return starts<const T>(*this); }

 private:
  struct Free {
    void operator()(T* p) const noexcept { ::operator delete[](p, std::align_val_t{alignment}); }
  };
  static std::size_t distance_for(std::size_t size) {
    if (size > max_size())  // the padding adds at most 3 lines
      throw std::length_error("dq::ComponentArrays: too many values to address");
    const std::size_t lines = (size + line - 1) / line + 1;
    return (lines % 2 == 1 ? lines : lines + 1) * line;
  }
  static std::unique_ptr<T[], Free> allocate(std::size_t n) {
    T* p = static_cast<T*>(::operator new[](n * sizeof(T), std::align_val_t{alignment}));
    std::uninitialized_value_construct_n(p, n);
    return std::unique_ptr<T[], Free>(p);
  }
  template <class X, class Self>
  static std::array<X*, N> starts(Self& self) noexcept {
    std::array<X*, N> out{};
    for (std::size_t k = 0; k < N; ++k) out[k] = self[k].data();
    return out;
  }

  std::size_t size_ = 0;
  std::size_t distance_ = 0;  ///< values from one array's start to the next's
  std::unique_ptr<T[], Free> data_;
};

}  // namespace dq
