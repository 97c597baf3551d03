// GoogleTest main that initialises MPI (and with it PETSc) once, as deal.II requires,
// after choosing the BLAS kernels as the program does.
#include <suturesim/core/blas_threads.h>

#include <deal.II/base/mpi.h>

#include <gtest/gtest.h>

int
main(int argc, char **argv)
{
  suturesim::select_blas_kernels(argv); // as the program does (core/blas_threads.h)
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
