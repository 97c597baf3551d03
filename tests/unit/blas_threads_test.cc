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

TEST(BlasKernels, FitForTheCpuNotOpenBlasGenericFallback)
{
  // main() chose them (tests/unit/main.cc, as the program's main does): on a CPU with
  // AVX2 and FMA the generic Prescott kernels are the fallback for a model OpenBLAS does
  // not know, 5x slower in dgemm here (core/blas_threads.h)
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma"))
    GTEST_SKIP() << "a CPU without AVX2 and FMA: Prescott may be its right kernels";
  if (suturesim::blas_kernels().empty())
    GTEST_SKIP() << "the BLAS loaded is not OpenBLAS";
  const char *asked = std::getenv("OPENBLAS_CORETYPE");
  if (asked != nullptr && std::string(asked) == "Prescott")
    GTEST_SKIP() << "OPENBLAS_CORETYPE=Prescott: the user's choice stands";
  EXPECT_NE(suturesim::blas_kernels(), "Prescott");
  // chosen once: nothing better is left to run again for
  EXPECT_EQ(suturesim::better_blas_kernels(), "");
}
