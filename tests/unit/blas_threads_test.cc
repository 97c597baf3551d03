// One BLAS thread per process unless the user asks for more (core/blas_threads.h).
#include <suturesim/core/blas_threads.h>

#include <gtest/gtest.h>

#include <dlfcn.h>

#include <cstdlib>
#include <optional>
#include <string>

TEST(BlasThreads, OneThreadUnlessTheUserAsksForMore)
{
  // scripts/install-deps.sh installs OpenBLAS (pthreads) as the system BLAS
  using Get      = int (*)();
  const auto get = reinterpret_cast<Get>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  ASSERT_NE(get, nullptr) << "the BLAS loaded is not OpenBLAS";
  const char                *given = std::getenv("OPENBLAS_NUM_THREADS");
  const std::optional<std::string> saved = given ? std::optional<std::string>(given) : std::nullopt;

  setenv("OPENBLAS_NUM_THREADS", "2", 1);
  EXPECT_EQ(suturesim::limit_blas_threads(), 0); // the user's choice stands
  unsetenv("OPENBLAS_NUM_THREADS");
  EXPECT_EQ(suturesim::limit_blas_threads(), 1);
  EXPECT_EQ(get(), 1);

  if (saved)
    setenv("OPENBLAS_NUM_THREADS", saved->c_str(), 1);
}
