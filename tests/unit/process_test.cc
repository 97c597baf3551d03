// Child processes (core/process.h): the environment a child gets is this process's with
// the given variables set over it and the given prefixes removed (a study's MPI case
// drops the study's own MPI variables, study/case_run.cc).
#include <suturesim/core/process.h>

#include "run_scene.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

using namespace suturesim;

TEST(Process, TheChildsEnvironmentHasTheSetVariablesAndNotTheDroppedOnes)
{
  ASSERT_EQ(setenv("SUTURESIM_TEST_DROP_A", "1", 1), 0);
  ASSERT_EQ(setenv("SUTURESIM_TEST_DROP_B", "2", 1), 0);
  ASSERT_EQ(setenv("SUTURESIM_TEST_KEEP", "3", 1), 0);
  ASSERT_EQ(setenv("SUTURESIM_TEST_OVER", "old", 1), 0);
  const std::string log = (test_support::scratch_path() / "process_environment.txt").string();
  const std::vector<std::string> argv{"env"};
  const pid_t pid = start_process(argv, log, {"SUTURESIM_TEST_DROP_*", "SUTURESIM_TEST_OVER=new"});
  int         status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  std::ifstream      in(log);
  std::ostringstream text;
  text << in.rdbuf();
  const std::string env = "\n" + text.str();
  EXPECT_EQ(env.find("\nSUTURESIM_TEST_DROP_"), std::string::npos) << env;
  EXPECT_NE(env.find("\nSUTURESIM_TEST_KEEP=3\n"), std::string::npos) << env;
  EXPECT_NE(env.find("\nSUTURESIM_TEST_OVER=new\n"), std::string::npos) << env;
  EXPECT_EQ(env.find("SUTURESIM_TEST_OVER=old"), std::string::npos) << env;
  EXPECT_EQ(env.find("SUTURESIM_TEST_DROP_*"), std::string::npos) << env; // a pattern is not a variable
  EXPECT_NE(env.find("\nPATH="), std::string::npos) << env;
  for (const char *name : {"SUTURESIM_TEST_DROP_A", "SUTURESIM_TEST_DROP_B", "SUTURESIM_TEST_KEEP", "SUTURESIM_TEST_OVER"})
    unsetenv(name);
}
