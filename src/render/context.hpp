// The headless OpenGL context of dqkit::render: EGL on Mesa's surfaceless platform.
#pragma once

#include <memory>
#include <string>

#include "dq/util/expected.hpp"

namespace dq::render::detail {

class Context {
 public:
  /// An OpenGL 3.3 core context, current on the calling thread, with no surface.
  static Expected<std::unique_ptr<Context>> create();
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  void make_current() const;

 private:
  Context() = default;
  void* display_ = nullptr;
  void* context_ = nullptr;
};

}  // namespace dq::render::detail
