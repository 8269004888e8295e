// Where the sample files of Debian's assimp-testmodels are: the DQKIT_ASSIMP_MODELS environment
// variable at run time, else the DQKIT_ASSIMP_MODELS CMake cache variable. Tests that need them
// start with DQKIT_REQUIRE_MODELS(), which skips the test with a message when they are missing.
#pragma once

#include <cstdlib>
#include <filesystem>

namespace dq::test {

inline std::filesystem::path assimp_models() {
  const char* env = std::getenv("DQKIT_ASSIMP_MODELS");
  return env && *env ? std::filesystem::path(env) : std::filesystem::path(DQKIT_ASSIMP_MODELS);
}

}  // namespace dq::test

#define DQKIT_REQUIRE_MODELS()                                                                                           \
  do {                                                                                                                   \
    std::error_code models_ec_;                                                                                          \
    if (!std::filesystem::is_directory(dq::test::assimp_models() / "BVH", models_ec_))                                   \
      GTEST_SKIP() << "no sample files at " << dq::test::assimp_models()                                                \
                   << " (install Debian's assimp-testmodels, or set DQKIT_ASSIMP_MODELS to their folder)";              \
  } while (false)
