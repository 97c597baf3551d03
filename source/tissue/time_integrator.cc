#include <suturesim/tissue/time_integrator.h>

#include <deal.II/base/mpi.h>

#include <iomanip>
#include <iostream>
#include <sstream>

namespace suturesim::tissue
{
  void
  TimeIntegrator::progress(const unsigned     step,
                           const unsigned     expected_steps,
                           const double       t,
                           const double       end_time,
                           const std::string &solver_info) const
  {
    if (dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) != 0)
      return;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double eta     = t > 0 ? elapsed * (end_time - t) / t : 0;
    std::ostringstream s;
    s << "step " << step << "/" << expected_steps << "  t = " << std::setprecision(4) << t << " s  "
      << solver_info << "  elapsed " << std::fixed << std::setprecision(1) << elapsed << " s  ETA " << eta
      << " s";
    std::cout << s.str() << std::endl;
  }
} // namespace suturesim::tissue
