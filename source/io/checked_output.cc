#include <suturesim/io/checked_output.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace suturesim::io
{
  void
  check_written(std::ostream &out, const std::string &file)
  {
    out.flush();
    if (!out.good())
      throw WriteError(file + ": cannot be written (" + std::string(errno != 0 ? std::strerror(errno) : "write failed") +
                       ")");
  }

  void
  write_whole(const std::string &file, const std::string &text)
  {
    const std::string temporary = file + ".tmp";
    try
      {
        {
          errno = 0;
          std::ofstream out(temporary, std::ios::trunc);
          if (!out)
            throw WriteError(file + ": cannot be written (" + std::string(errno != 0 ? std::strerror(errno) : "cannot open") +
                             ")");
          out << text;
          check_written(out, file);
          out.close();
          if (out.fail())
            throw WriteError(file + ": cannot be written (closing it failed)");
        }
        std::error_code error;
        std::filesystem::rename(temporary, file, error);
        if (error)
          throw WriteError(file + ": cannot be written (" + error.message() + ")");
      }
    catch (const WriteError &)
      {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw;
      }
  }
} // namespace suturesim::io
