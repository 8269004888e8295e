// Preconditions: the one policy of the whole library (docs/design.md, "Preconditions").
//
// A precondition is a promise the caller makes (spans of matching sizes, outputs that do not
// overlap inputs, a validated job). Breaking one is a bug in the calling code, not bad data: it is
// reported through DQ_PRECONDITION, which calls the precondition handler. The default handler
// prints what failed and where and aborts; a program (or a test) may install its own, for example
// one that throws, with `set_precondition_handler`. If the handler returns, the call that
// detected the violation returns without doing its work (outputs untouched).
//
// Input that comes from outside the program (files, command lines, Python) is never checked with
// preconditions: it goes through functions that return `Expected`/`Status` with a reason.
//
// The checks are cheap (sizes and pointer ranges, never a pass over the data) and always on;
// defining DQKIT_NO_PRECONDITION_CHECKS before including dqkit turns them off.
#pragma once

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <span>

namespace dq {

/// What was violated, and where (the caller's source location is not known: the function's).
struct PreconditionViolation {
  const char* condition;  ///< the expression that was false
  const char* message;    ///< what it means, in words
  const char* function;   ///< the dqkit function that checked it
};

using PreconditionHandler = void (*)(const PreconditionViolation&);

namespace detail {
[[noreturn]] inline void abort_on_precondition(const PreconditionViolation& v) {
  std::fprintf(stderr, "dqkit: precondition violated in %s: %s (%s)\n", v.function, v.message, v.condition);
  std::abort();
}
inline std::atomic<PreconditionHandler>& precondition_handler() {
  static std::atomic<PreconditionHandler> handler{&abort_on_precondition};
  return handler;
}
}  // namespace detail

/// Installs a handler for precondition violations (nullptr restores the default, which aborts);
/// returns the previous one. Thread-safe.
inline PreconditionHandler set_precondition_handler(PreconditionHandler handler) noexcept {
  return detail::precondition_handler().exchange(handler ? handler : &detail::abort_on_precondition);
}

/// Calls the installed handler.
inline void precondition_failed(const char* condition, const char* message, const char* function) {
  detail::precondition_handler().load()(PreconditionViolation{condition, message, function});
}

/// Whether two spans share any element (a kernel that writes one while reading the other
/// assumes they do not).
template <class A, class B>
bool overlaps(std::span<A> a, std::span<B> b) noexcept {
  if (a.empty() || b.empty()) return false;
  const auto* a0 = reinterpret_cast<const unsigned char*>(a.data());
  const auto* b0 = reinterpret_cast<const unsigned char*>(b.data());
  return a0 < b0 + b.size_bytes() && b0 < a0 + a.size_bytes();
}

}  // namespace dq

#if defined(DQKIT_NO_PRECONDITION_CHECKS)
#define DQ_PRECONDITION(condition, message, ...) static_cast<void>(0)
#else
/// Checks `condition`; if false, reports it and returns from the calling function (with the
/// value given after the message, if any).
#define DQ_PRECONDITION(condition, message, ...)                   \
  do {                                                             \
    if (!(condition)) [[unlikely]] {                               \
      ::dq::precondition_failed(#condition, message, __func__);    \
      return __VA_ARGS__;                                          \
    }                                                              \
  } while (false)
#endif
