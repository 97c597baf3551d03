// The paths of this build, compiled into one file only (see run_scene.h).
#include "run_scene.h"

namespace suturesim::test_support
{
  const char *
  source_directory()
  {
    return SUTURESIM_SOURCE_DIR;
  }

  const char *
  suturesim_binary()
  {
    return SUTURESIM_BINARY;
  }

  const char *
  scratch_directory()
  {
    return SUTURESIM_TEST_SCRATCH;
  }
} // namespace suturesim::test_support
