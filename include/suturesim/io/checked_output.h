#pragma once
/**
 * @file
 * Writes that are checked (issue 26): a run whose disk fills up, or whose output folder
 * stops being writable, ends with one line naming the file and exit code 5, never with a
 * truncated file that looks complete. summary.json, the .pvd series and parameters.prm
 * are written whole to "<file>.tmp" and renamed, so a file of that name is complete or
 * absent.
 */

#include <ostream>
#include <stdexcept>
#include <string>

namespace suturesim::io
{
  /// An output that could not be written (main(): exit 5).
  class WriteError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// Flushes @p out and throws WriteError naming @p file unless every write to it
  /// succeeded, with errno's reason (callers clear errno before they write).
  void
  check_written(std::ostream &out, const std::string &file);

  /// Writes @p text to @p file through "<file>.tmp" and a rename; WriteError naming
  /// @p file when any step fails (the temporary file is then removed).
  void
  write_whole(const std::string &file, const std::string &text);
} // namespace suturesim::io
