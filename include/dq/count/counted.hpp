// A counting scalar: Counted<T> behaves like T and counts every arithmetic operation and function
// call it takes part in, so that dqkit's generic algorithms report their own operation counts
// (bench/operation_counts.cpp writes docs/operation-counts.md with it).
//
// What is counted: additions and subtractions (add), multiplications (mul), divisions (div),
// square roots and hypot (sqrt), trigonometric functions and their inverses (trig), exp and log
// (exp_log), comparisons and abs/min/max (cmp). Negation is free (a sign-bit flip), as are
// conversions from constants. Counters are per thread.
#pragma once

#include <cmath>
#include <ostream>

#include "dq/core/scalar.hpp"

namespace dq {

struct OpCounts {
  long add = 0, mul = 0, div = 0, sqrt = 0, trig = 0, exp_log = 0, cmp = 0;

  friend OpCounts operator-(const OpCounts& a, const OpCounts& b) {
    return {a.add - b.add, a.mul - b.mul, a.div - b.div, a.sqrt - b.sqrt, a.trig - b.trig, a.exp_log - b.exp_log, a.cmp - b.cmp};
  }
  friend bool operator==(const OpCounts&, const OpCounts&) = default;
};

/// The running totals of this thread.
inline OpCounts& op_counts() {
  thread_local OpCounts counts;
  return counts;
}

/// Counts the operations of one call: `count_ops([&] { a * b; })`.
template <class F>
OpCounts count_ops(F&& f) {
  const OpCounts before = op_counts();
  f();
  return op_counts() - before;
}

template <class T>
struct Counted {
  T v{};

  constexpr Counted() = default;
  Counted(const T& x) : v(x) {}  // NOLINT: implicit, like a literal
  template <class I>
    requires std::is_arithmetic_v<I> && (!std::is_same_v<I, T>)
  Counted(I x) : v(static_cast<T>(x)) {}  // NOLINT: T(2) in generic code

  friend Counted operator+(const Counted& a) { return a; }
  friend Counted operator-(const Counted& a) { return Counted(-a.v); }
  friend Counted operator+(const Counted& a, const Counted& b) { ++op_counts().add; return Counted(a.v + b.v); }
  friend Counted operator-(const Counted& a, const Counted& b) { ++op_counts().add; return Counted(a.v - b.v); }
  friend Counted operator*(const Counted& a, const Counted& b) { ++op_counts().mul; return Counted(a.v * b.v); }
  friend Counted operator/(const Counted& a, const Counted& b) { ++op_counts().div; return Counted(a.v / b.v); }
  Counted& operator+=(const Counted& o) { return *this = *this + o; }
  Counted& operator-=(const Counted& o) { return *this = *this - o; }
  Counted& operator*=(const Counted& o) { return *this = *this * o; }
  Counted& operator/=(const Counted& o) { return *this = *this / o; }

  friend bool operator==(const Counted& a, const Counted& b) { ++op_counts().cmp; return a.v == b.v; }
  friend bool operator<(const Counted& a, const Counted& b) { ++op_counts().cmp; return a.v < b.v; }
  friend bool operator>(const Counted& a, const Counted& b) { ++op_counts().cmp; return a.v > b.v; }
  friend bool operator<=(const Counted& a, const Counted& b) { ++op_counts().cmp; return a.v <= b.v; }
  friend bool operator>=(const Counted& a, const Counted& b) { ++op_counts().cmp; return a.v >= b.v; }

  friend std::ostream& operator<<(std::ostream& os, const Counted& a) { return os << a.v; }
};

template <class T>
struct scalar_traits<Counted<T>> {
  using real_type = real_t<T>;
  static constexpr real_type value(const Counted<T>& x) noexcept { return value_of(x.v); }
  static constexpr real_type largest_part(const Counted<T>& x) noexcept { return dq::largest_part(x.v); }
  static constexpr bool has_derivatives = has_derivatives_v<T>;
};

namespace detail {
template <class T, class F>
Counted<T> counted_call(long OpCounts::*field, F&& f) {
  ++(op_counts().*field);
  return Counted<T>(f());
}
}  // namespace detail

// clang-format off
template <class T> Counted<T> sqrt(const Counted<T>& a) { return detail::counted_call<T>(&OpCounts::sqrt, [&] { using std::sqrt; return sqrt(a.v); }); }
template <class T> Counted<T> cbrt(const Counted<T>& a) { return detail::counted_call<T>(&OpCounts::sqrt, [&] { using std::cbrt; return cbrt(a.v); }); }
template <class T> Counted<T> hypot(const Counted<T>& a, const Counted<T>& b) { return detail::counted_call<T>(&OpCounts::sqrt, [&] { using std::hypot; return hypot(a.v, b.v); }); }
template <class T> Counted<T> sin(const Counted<T>& a) { return detail::counted_call<T>(&OpCounts::trig, [&] { using std::sin; return sin(a.v); }); }
template <class T> Counted<T> cos(const Counted<T>& a) { return detail::counted_call<T>(&OpCounts::trig, [&] { using std::cos; return cos(a.v); }); }
template <class T> Counted<T> tan(const Counted<T>& a) { return detail::counted_call<T>(&OpCounts::trig, [&] { using std::tan; return tan(a.v); }); }
template <class T> Counted<T> asin(const Counted<T>& a) { return detail::counted_call<T>(&OpCounts::trig, [&] { using std::asin; return asin(a.v); }); }
template <class T> Counted<T> acos(const Counted<T>& a) { return detail::counted_call<T>(&OpCounts::trig, [&] { using std::acos; return acos(a.v); }); }
template <class T> Counted<T> atan(const Counted<T>& a) { return detail::counted_call<T>(&OpCounts::trig, [&] { using std::atan; return atan(a.v); }); }
template <class T> Counted<T> atan2(const Counted<T>& a, const Counted<T>& b) { return detail::counted_call<T>(&OpCounts::trig, [&] { using std::atan2; return atan2(a.v, b.v); }); }
template <class T> Counted<T> exp(const Counted<T>& a) { return detail::counted_call<T>(&OpCounts::exp_log, [&] { using std::exp; return exp(a.v); }); }
template <class T> Counted<T> log(const Counted<T>& a) { return detail::counted_call<T>(&OpCounts::exp_log, [&] { using std::log; return log(a.v); }); }
template <class T> Counted<T> abs(const Counted<T>& a) { return detail::counted_call<T>(&OpCounts::cmp, [&] { using std::abs; return abs(a.v); }); }
template <class T> Counted<T> round(const Counted<T>& a) { return detail::counted_call<T>(&OpCounts::cmp, [&] { using std::round; return round(a.v); }); }
// clang-format on
template <class T>
bool isfinite(const Counted<T>& a) {
  using std::isfinite;
  return isfinite(a.v);
}

}  // namespace dq
