#include <suturesim/core/mpi_session.h>

#include <deal.II/base/mpi.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

namespace suturesim
{
  namespace
  {
    /// Whether a launcher started this process: Open MPI's mpirun, a PMIx launcher, or
    /// MPICH's Hydra, each of which sets its rank's variable.
    bool
    launched()
    {
      for (const char *variable : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
        if (std::getenv(variable) != nullptr)
          return true;
      return false;
    }

    /// A fresh directory under the system's temporary directory, "" when none can be
    /// made (Open MPI then uses its default, as without this).
    std::string
    fresh_tmpdir()
    {
      std::error_code ec;
      const auto      base = std::filesystem::temp_directory_path(ec);
      if (ec)
        return "";
      const std::string pattern = (base / "suturesim-mpi-XXXXXX").string();
      std::vector<char> name(pattern.begin(), pattern.end());
      name.push_back('\0');
      return mkdtemp(name.data()) == nullptr ? "" : std::string(name.data());
    }
  } // namespace

  MpiSession::MpiSession(int &argc, char **&argv)
  {
    std::vector<const char *> set; // the variables set here, for MPI_Init alone
    if (!launched())
      {
        if (std::getenv("OMPI_MCA_ess_singleton_isolated") == nullptr)
          {
            setenv("OMPI_MCA_ess_singleton_isolated", "1", 1);
            set.push_back("OMPI_MCA_ess_singleton_isolated");
          }
        if (std::getenv("OMPI_MCA_orte_tmpdir_base") == nullptr)
          tmpdir = fresh_tmpdir();
        if (!tmpdir.empty())
          {
            setenv("OMPI_MCA_orte_tmpdir_base", tmpdir.c_str(), 1);
            set.push_back("OMPI_MCA_orte_tmpdir_base");
          }
      }
    mpi = std::make_unique<dealii::Utilities::MPI::MPI_InitFinalize>(argc, argv, 1);
    // Open MPI has read them. Removed again, the processes this one starts (a study's
    // cases, the unit tests' runs of suturesim) choose their own instead of sharing this
    // process's directory.
    for (const char *variable : set)
      unsetenv(variable);
  }

  MpiSession::~MpiSession()
  {
    mpi.reset();
    if (tmpdir.empty())
      return;
    // What Open MPI left in it (it removes its own session directories as it finalizes);
    // a failure leaves a directory in the temporary one, nothing the run depends on.
    std::error_code ec;
    std::filesystem::remove_all(tmpdir, ec);
  }
} // namespace suturesim
