#include <suturesim/core/process.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <stdexcept>

extern char **environ;

namespace suturesim
{
  namespace
  {
    /// The null-terminated pointer array exec wants, over @p strings (kept alive by the caller).
    std::vector<char *>
    pointers(std::vector<std::string> &strings)
    {
      std::vector<char *> p;
      for (auto &s : strings)
        p.push_back(s.data());
      p.push_back(nullptr);
      return p;
    }
  } // namespace

  pid_t
  start_process(const std::vector<std::string> &argv, const std::string &log,
                const std::vector<std::string> &environment)
  {
    std::vector<std::string> args = argv, env;
    for (char **e = environ; *e; ++e)
      {
        const std::string entry = *e;
        const auto        name  = entry.substr(0, entry.find('=') + 1);
        bool              set   = false;
        for (const auto &over : environment)
          set = set || over.rfind(name, 0) == 0 ||
                (!over.empty() && over.back() == '*' && entry.rfind(over.substr(0, over.size() - 1), 0) == 0);
        if (!set)
          env.push_back(entry);
      }
    for (const auto &over : environment)
      if (over.empty() || over.back() != '*')
        env.push_back(over);
    auto arg_pointers = pointers(args), env_pointers = pointers(env);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (!log.empty())
      {
        posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
      }
    pid_t     pid = 0;
    const int rc  = posix_spawnp(&pid, arg_pointers[0], &actions, nullptr, arg_pointers.data(), env_pointers.data());
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0)
      throw std::runtime_error("cannot start '" + argv.at(0) + "': " + std::strerror(rc));
    return pid;
  }

  int
  run_process(const std::vector<std::string> &argv, const std::string &log)
  {
    pid_t pid = 0;
    try
      {
        pid = start_process(argv, log);
      }
    catch (const std::runtime_error &)
      {
        return -1;
      }
    int status = 0;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status))
      return -1;
    return WEXITSTATUS(status);
  }
} // namespace suturesim
