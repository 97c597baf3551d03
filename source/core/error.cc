#include <suturesim/core/error.h>

#include <cctype>

namespace suturesim
{
  std::string
  one_line(const std::string &text)
  {
    std::string out;
    bool        blank = false;
    for (const char c : text)
      {
        if (std::isspace(static_cast<unsigned char>(c)))
          blank = !out.empty();
        else
          {
            if (blank)
              out += ' ';
            out += c;
            blank = false;
          }
      }
    return out;
  }
} // namespace suturesim
