#include <warpchol/base/atomic_file.h>
#include <warpchol/base/exceptions.h>

#include <cstdio>
#include <fstream>
#include <unistd.h>

namespace warpchol
{
  void write_file_atomically(const std::string                        &filename,
                             const std::function<void(std::ostream &)> &write)
  {
    // The process id keeps two concurrent writers of the same file apart.
    const std::string temporary = filename + ".tmp." + std::to_string(::getpid());
    try
      {
        std::ofstream stream(temporary);
        if (!stream)
          throw InputError(filename + ": cannot open for writing");
        write(stream);
        stream.close();
        if (!stream)
          throw InputError(filename + ": write failed");
      }
    catch (...)
      {
        std::remove(temporary.c_str());
        throw;
      }
    if (std::rename(temporary.c_str(), filename.c_str()) != 0)
      {
        std::remove(temporary.c_str());
        throw InputError(filename + ": cannot rename the temporary file into place");
      }
  }
} // namespace warpchol
