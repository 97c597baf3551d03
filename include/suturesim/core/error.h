#pragma once
/**
 * @file
 * Error types that reach the user. Their what() is one line that names the file, line
 * and parameter (input errors) or the solver state (solver errors); main() prints it
 * and exits non-zero.
 */

#include <stdexcept>
#include <string>

namespace suturesim
{
  /// Bad input: scene file, command line, mesh. Message: "file:line: key: problem".
  class InputError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// A solver that failed after every cutback; the last converged state was kept.
  class SolverError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// Collapses runs of white space (including new lines) into single blanks and trims.
  std::string
  one_line(const std::string &text);
} // namespace suturesim
