#include <suturesim/core/blas_threads.h>

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace suturesim
{
  int
  limit_blas_threads()
  {
    if (std::getenv("OPENBLAS_NUM_THREADS") != nullptr)
      return 0;
    using SetThreads = void (*)(int);
    const auto set   = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    if (set == nullptr)
      return 0;
    set(1);
    return 1;
  }

  std::string
  blas_kernels()
  {
    using CoreName  = char *(*)();
    const auto name = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
    const char *core = name != nullptr ? name() : nullptr;
    return core != nullptr ? core : "";
  }

  std::string
  better_blas_kernels()
  {
    if (std::getenv("OPENBLAS_CORETYPE") != nullptr || blas_kernels() != "Prescott")
      return "";
    // libgcc's checks include the operating system's support (XCR0), as OpenBLAS's do
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512vl"))
      return "SkylakeX";
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
      return "Haswell";
    return "";
  }

  void
  select_blas_kernels(char **argv)
  {
    const std::string kernels = better_blas_kernels();
    // started through the dynamic loader (ld-linux*.so program ...), /proc/self/exe is
    // the loader, which would take argv[0] for its own: keep the kernels loaded
    std::error_code   error;
    const std::string self = std::filesystem::read_symlink("/proc/self/exe", error).filename().string();
    if (kernels.empty() || error || self.rfind("ld-", 0) == 0 || setenv("OPENBLAS_CORETYPE", kernels.c_str(), 1) != 0)
      return;
    execv("/proc/self/exe", argv);
    // not executed again (a system without /proc): this process keeps the kernels it
    // loaded, slow rather than wrong, and the processes it starts load the better ones
  }
} // namespace suturesim
