#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

/**
 * @file
 * A fuzz input as a file, for the readers that take a file name (the mesh readers, the
 * parameter file): the same path the programs take, VTK's file reading included.
 */
namespace warpchol::fuzz
{
  /**
   * Holds the bytes of one fuzz input in /tmp under a name of this process (fuzzers run
   * side by side under ctest -j and libFuzzer -jobs), with the extension @p extension
   * that selects the reader. Removed when the process ends.
   */
  class InputFile
  {
  public:
    explicit InputFile(const std::string &extension)
      : name("/tmp/warpchol-fuzz-" + std::to_string(::getpid()) + extension)
    {}

    ~InputFile()
    {
      std::remove(name.c_str());
    }

    /** Replace the file's contents by @p data; returns the file name. */
    const std::string &write(const std::uint8_t *data, const std::size_t size)
    {
      std::ofstream file(name, std::ios::binary | std::ios::trunc);
      file.write(reinterpret_cast<const char *>(data), static_cast<std::streamsize>(size));
      file.close();
      if (!file)
        {
          // Not the reader's fault: a full /tmp would make every input look bad.
          std::perror(name.c_str());
          std::abort();
        }
      return name;
    }

    const std::string name;
  };
} // namespace warpchol::fuzz
