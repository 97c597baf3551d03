// GoogleTest main that initialises MPI (and with it PETSc) once, as deal.II requires,
// after choosing the BLAS kernels as the program does.
#include <suturesim/core/blas_threads.h>
#include <suturesim/core/mpi_session.h>

#include <gtest/gtest.h>

int
main(int argc, char **argv)
{
  suturesim::select_blas_kernels(argv); // as the program does (core/blas_threads.h)
  const suturesim::MpiSession mpi(argc, argv); // as the program does (core/mpi_session.h)
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
