// Owning storage for batches in structure-of-arrays layout: N arrays of n values each (the x, y, z
// of points, the twelve entries of 3x4 matrices, the eight components of dual quaternions), laid
// out for SIMD and for streaming far beyond the cache.
#pragma once

#include <algorithm>
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

/// N arrays of `size()` values of T, allocated once at construction and zeroed; with N =
/// std::dynamic_extent, the count of arrays is given at construction. Every array starts on a
/// 64-byte cache line, and consecutive arrays are an odd number of lines apart (one or two lines of
/// padding), so that no two of the first 64 arrays are a multiple of 4 KiB apart. Arrays a multiple
/// of 4 KiB apart map to the same cache sets (and look alike to the prefetchers), and the streams of
/// a kernel evict each other: the batch forward kinematics ran 1.3–1.55 × faster on padded, skewed
/// arrays with no change to the kernel, and DQS skinning in the cache 1.06–3.2 × faster on a skin
/// stored so (docs/skinning.md). A copy allocates and copies; a moved-from object has size 0 and no
/// arrays.
template <class T, std::size_t N>
class ComponentArrays {
 public:
  static constexpr bool dynamic = N == std::dynamic_extent;
  static constexpr std::size_t alignment = 64;
  static constexpr std::size_t line = alignment / sizeof(T);  ///< values per cache line
  static_assert(N > 0 && alignment % sizeof(T) == 0);
  static_assert(std::is_arithmetic_v<T>, "ComponentArrays holds numbers (no constructors or destructors run)");

  ComponentArrays() = default;
  /// Throws std::length_error when N arrays of `size` values cannot be addressed.
  explicit ComponentArrays(std::size_t size)
    requires(!dynamic)
      : ComponentArrays(size, N, 0) {}
  /// `count` arrays (N = std::dynamic_extent). Throws std::length_error when they cannot be addressed.
  ComponentArrays(std::size_t size, std::size_t count)
    requires(dynamic)
      : ComponentArrays(size, count, 0) {}
  ComponentArrays(const ComponentArrays& other)
      : size_(other.size_), count_(other.count_), distance_(other.distance_), data_(allocate(count_ * distance_)) {
    std::copy_n(other.data_.get(), count_ * distance_, data_.get());
  }
  ComponentArrays& operator=(const ComponentArrays& other) {
    if (this != &other) *this = ComponentArrays(other);
    return *this;
  }
  ComponentArrays(ComponentArrays&& other) noexcept
      : size_(std::exchange(other.size_, 0)), count_(std::exchange(other.count_, dynamic ? 0 : N)),
        distance_(std::exchange(other.distance_, 0)), data_(std::move(other.data_)) {}
  ComponentArrays& operator=(ComponentArrays&& other) noexcept {
    size_ = std::exchange(other.size_, 0);
    count_ = std::exchange(other.count_, dynamic ? 0 : N);
    distance_ = std::exchange(other.distance_, 0);
    data_ = std::move(other.data_);
    return *this;
  }

  /// Values per array.
  std::size_t size() const noexcept { return size_; }
  /// The number of arrays (N, or the count given at construction).
  std::size_t count() const noexcept { return count_; }
  /// Values from one array's start to the next's (0 with no arrays).
  std::size_t distance() const noexcept { return distance_; }
  /// The largest size whose `count` padded arrays can be addressed (larger ones throw).
  static constexpr std::size_t max_size(std::size_t count = dynamic ? 1 : N) noexcept {
    return std::numeric_limits<std::size_t>::max() / sizeof(T) / count - 3 * line;
  }
  /// Array k (k < count()).
  std::span<T> operator[](std::size_t k) noexcept { return {data_.get() + k * distance_, size_}; }
  std::span<const T> operator[](std::size_t k) const noexcept { return {data_.get() + k * distance_, size_}; }
  /// The N array starts, in the form the batch kernels take (dq::simd::transform_points, ...).
  std::array<T*, N> data() noexcept
    requires(!dynamic)
  {
    return starts<T>(*this);
  }
  std::array<const T*, N> data() const noexcept
    requires(!dynamic)
  {
    return starts<const T>(*this);
  }

 private:
  struct Free {
    void operator()(T* p) const noexcept { ::operator delete[](p, std::align_val_t{alignment}); }
  };
  ComponentArrays(std::size_t size, std::size_t count, int)
      : size_(size), count_(count), distance_(distance_for(size, count)), data_(allocate(count * distance_)) {}
  static std::size_t distance_for(std::size_t size, std::size_t count) {
    if (count == 0) return 0;
    if (size > max_size(count))  // the padding adds at most 3 lines
      throw std::length_error("dq::ComponentArrays: too many values to address");
    const std::size_t lines = (size + line - 1) / line + 1;
    return (lines % 2 == 1 ? lines : lines + 1) * line;
  }
  static std::unique_ptr<T[], Free> allocate(std::size_t n) {
    if (n == 0) return nullptr;
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
  std::size_t count_ = dynamic ? 0 : N;
  std::size_t distance_ = 0;  ///< values from one array's start to the next's
  std::unique_ptr<T[], Free> data_;
};

}  // namespace dq
