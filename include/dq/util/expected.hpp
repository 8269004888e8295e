// A value or an error that says what went wrong and where: the return type of everything in
// dqkit that validates input (builders, parsers, importers). No exceptions cross the library's
// interface; the CLI and bindings print `error().message`.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace dq {

struct Error {
  std::string message;  ///< what, and where ("file:line: ..." for files, the joint's name for skeletons)
};

template <class T>
class [[nodiscard]] Expected {
 public:
  Expected(T value) : state_(std::move(value)) {}     // NOLINT: implicit, like std::expected
  Expected(Error error) : state_(std::move(error)) {}  // NOLINT

  bool has_value() const noexcept { return state_.index() == 0; }
  explicit operator bool() const noexcept { return has_value(); }
  T& value() & { return std::get<0>(state_); }
  const T& value() const& { return std::get<0>(state_); }
  T&& value() && { return std::get<0>(std::move(state_)); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  const Error& error() const { return std::get<1>(state_); }

 private:
  std::variant<T, Error> state_;
};

/// Expected<void>: success, or an error.
struct Status {
  Status() = default;
  Status(Error e) : error_(std::move(e.message)), failed_(true) {}  // NOLINT
  bool ok() const noexcept { return !failed_; }
  explicit operator bool() const noexcept { return ok(); }
  Error error() const { return {error_}; }

 private:
  std::string error_;
  bool failed_ = false;
};

}  // namespace dq
