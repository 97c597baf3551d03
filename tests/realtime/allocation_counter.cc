// The allocation counter of allocation_counter.h.
//
// How every allocation is seen, in the library as in the test:
//  - Plain build: this binary defines malloc, calloc, realloc, free, aligned_alloc,
//    posix_memalign and memalign. glibc supports replacing them by ELF symbol interposition
//    (glibc manual, "Replacing malloc"): the executable comes first in the global lookup
//    scope, so libsuturesim_realtime, libstdc++ and glibc itself call these. They do not
//    replace the allocator: each forwards to glibc's own entry point (__libc_malloc,
//    __libc_calloc, __libc_realloc, __libc_free, __libc_memalign, exported by glibc since
//    2.2.5 for this use), so a block allocated here and released by a function not
//    interposed (or the reverse) still meets the same allocator. dlsym(RTLD_NEXT, "malloc")
//    was not chosen: dlsym may itself allocate, before the pointer it returns is known.
//    operator new is replaced too and counted apart (it allocates with __libc_malloc, so a
//    `new` counts once). valloc and pvalloc (obsolete) are not counted.
//  - AddressSanitizer build: interposing malloc would take every allocation away from
//    ASan's checks, so nothing is replaced; ASan's allocator, which serves malloc and
//    operator new, calls a hook installed with __sanitizer_install_malloc_and_free_hooks
//    for each allocation (compiler-rt, sanitizer/allocator_interface.h; GCC 12 ships the
//    function in libasan without the header, hence the declaration below).
#include "realtime/allocation_counter.h"

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <new>

namespace
{
  std::atomic<bool>        counting{false};
  std::atomic<std::size_t> news{0}, mallocs{0};

  void
  count(std::atomic<std::size_t> &counter)
  {
    if (counting.load(std::memory_order_relaxed))
      counter.fetch_add(1, std::memory_order_relaxed);
  }
} // namespace

#if defined(__SANITIZE_ADDRESS__)

extern "C" int
__sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void *, std::size_t),
                                          void (*free_hook)(const volatile void *));

namespace
{
  // installed before main() runs (both hooks must be given)
  const int hooks_installed = __sanitizer_install_malloc_and_free_hooks(
    [](const volatile void *, std::size_t) { count(mallocs); }, [](const volatile void *) {});
} // namespace

const bool suturesim::test_support::operator_new_counted_apart = false;

#else

extern "C"
{
  void *
  __libc_malloc(std::size_t size);
  void *
  __libc_calloc(std::size_t n, std::size_t size);
  void *
  __libc_realloc(void *p, std::size_t size);
  void
  __libc_free(void *p);
  void *
  __libc_memalign(std::size_t alignment, std::size_t size);

  // noexcept: glibc declares them __THROW
  void *
  malloc(std::size_t size) noexcept
  {
    count(mallocs);
    return __libc_malloc(size);
  }
  void *
  calloc(std::size_t n, std::size_t size) noexcept
  {
    count(mallocs);
    return __libc_calloc(n, size);
  }
  void *
  realloc(void *p, std::size_t size) noexcept
  {
    count(mallocs);
    return __libc_realloc(p, size);
  }
  void
  free(void *p) noexcept
  {
    __libc_free(p);
  }
  void *
  memalign(std::size_t alignment, std::size_t size) noexcept
  {
    count(mallocs);
    return __libc_memalign(alignment, size);
  }
  // glibc's aligned_alloc is memalign (the same address in libc.so.6)
  void *
  aligned_alloc(std::size_t alignment, std::size_t size) noexcept
  {
    count(mallocs);
    return __libc_memalign(alignment, size);
  }
  // POSIX: EINVAL unless the alignment is a power of two multiple of sizeof(void *)
  int
  posix_memalign(void **p, std::size_t alignment, std::size_t size) noexcept
  {
    count(mallocs);
    if (alignment % sizeof(void *) != 0 || (alignment & (alignment - 1)) != 0)
      return EINVAL;
    void *q = __libc_memalign(alignment, size);
    if (q == nullptr)
      return ENOMEM;
    *p = q;
    return 0;
  }
}

// The other forms of new (arrays, nothrow) call this one in libstdc++, and its aligned
// new calls aligned_alloc.
void *
operator new(std::size_t size)
{
  count(news);
  if (void *p = __libc_malloc(size == 0 ? 1 : size))
    return p;
  throw std::bad_alloc();
}
void
operator delete(void *p) noexcept
{
  __libc_free(p);
}
void
operator delete(void *p, std::size_t) noexcept
{
  __libc_free(p);
}

const bool suturesim::test_support::operator_new_counted_apart = true;

#endif

namespace suturesim::test_support
{
  void
  start_counting_allocations()
  {
    news    = 0;
    mallocs = 0;
    counting = true;
  }

  Allocations
  stop_counting_allocations()
  {
    counting = false;
    return {news.load(), mallocs.load()};
  }
} // namespace suturesim::test_support
