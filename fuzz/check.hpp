// The fuzz targets' property check: report the violated property and abort (libFuzzer then
// saves the input).
#pragma once

#include <cstdio>
#include <cstdlib>

namespace dq::fuzz {
inline void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "property violated: %s\n", what);
    std::abort();
  }
}
}  // namespace dq::fuzz
