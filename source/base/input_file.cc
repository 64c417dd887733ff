#include <warpchol/base/exceptions.h>
#include <warpchol/base/input_file.h>

#include <sys/stat.h>

namespace warpchol
{
  void check_input_file(const std::string &filename, const std::string &what)
  {
    struct stat status;
    if (::stat(filename.c_str(), &status) == 0 && S_ISDIR(status.st_mode))
      throw InputError(filename + ": is a directory, not a " + what);
    if (!std::ifstream(filename))
      throw InputError(filename + ": cannot open the " + what);
  }

  std::ifstream open_input_file(const std::string &filename, const std::string &what)
  {
    check_input_file(filename, what);
    std::ifstream stream(filename, std::ios::binary);
    if (!stream)
      throw InputError(filename + ": cannot open the " + what);
    return stream;
  }
} // namespace warpchol
