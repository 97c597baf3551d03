// Child processes (core/process.h): the environment a child gets is this process's with
// the given variables set over it and the given prefixes removed (a study's MPI case
// drops the study's own MPI variables, study/case_run.cc). suturesim's processes side by
// side, each an MPI singleton in a session directory of its own (core/mpi_session.h).
#include <suturesim/core/process.h>

#include "run_scene.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

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

TEST(Process, EachSuturesimSingletonHasASessionDirectoryOfItsOwnAndRemovesIt)
{
  // Open MPI 4.1's isolated singletons are all job [[0,1],0]: in one shared tmpdir base
  // they share the session directory jf.0/1/0, and one that finalizes removes it under
  // another that is starting, whose MPI_Init then fails (exit 1; core/mpi_session.h).
  // Two runs at once with TMPDIR here: each must make its session tree under a base of
  // its own (suturesim-mpi-*), none in the shared place (TMPDIR/ompi.*), and leave nothing.
  if (std::getenv("OMPI_MCA_orte_tmpdir_base") != nullptr)
    GTEST_SKIP() << "OMPI_MCA_orte_tmpdir_base is set: the runs keep the user's base";
  namespace fs = std::filesystem;
  const fs::path tmp = test_support::scratch_path() / "mpi_sessions";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  std::vector<pid_t> pids;
  for (const std::string run : {"a", "b"})
    pids.push_back(start_process(
      test_support::join({test_support::suturesim_binary()},
                         test_support::join(test_support::scene_with("parameters/suture_swing.prm",
                                                                     {"Model=realtime", "Time/End time=0.5"}),
                                            {"--output", (tmp.parent_path() / ("mpi_session_" + run)).string()})),
      (tmp.parent_path() / ("mpi_session_" + run + ".log")).string(), {"TMPDIR=" + tmp.string()}));
  std::set<std::string> private_sessions, shared_sessions;
  std::vector<int>      exit_codes;
  const auto            start = std::chrono::steady_clock::now();
  while (exit_codes.size() < pids.size() && std::chrono::steady_clock::now() - start < std::chrono::seconds(120))
    {
      std::error_code ec;
      for (const auto &entry : fs::directory_iterator(tmp, ec))
        {
          const std::string name = entry.path().filename().string();
          if (name.rfind("ompi.", 0) == 0)
            shared_sessions.insert(name);
          else if (name.rfind("suturesim-mpi-", 0) == 0)
            for (const auto &inner : fs::directory_iterator(entry.path(), ec))
              if (inner.path().filename().string().rfind("ompi.", 0) == 0)
                private_sessions.insert(name);
        }
      for (auto &pid : pids)
        {
          int status = 0;
          if (pid > 0 && waitpid(pid, &status, WNOHANG) == pid)
            {
              exit_codes.push_back(WIFEXITED(status) ? WEXITSTATUS(status) : -1);
              pid = 0;
            }
        }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  ASSERT_EQ(exit_codes, std::vector<int>({0, 0})) << test_support::read_text((tmp.parent_path() / "mpi_session_a.log").string())
                                                  << test_support::read_text((tmp.parent_path() / "mpi_session_b.log").string());
  EXPECT_EQ(private_sessions.size(), 2u);
  EXPECT_TRUE(shared_sessions.empty()) << *shared_sessions.begin();
  EXPECT_TRUE(fs::is_empty(tmp)) << fs::directory_iterator(tmp)->path();
}
