#include <suturesim/core/blas_threads.h>

#include <dlfcn.h>

#include <cstdlib>

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
} // namespace suturesim
