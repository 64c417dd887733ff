#pragma once

#include <chrono>

/**
 * @file
 * Wall-clock timing of solver phases.
 */
namespace warpchol
{
  /** Measures wall-clock seconds since construction or the last restart(). */
  class Stopwatch
  {
  public:
    Stopwatch()
      : start(std::chrono::steady_clock::now())
    {}

    void restart()
    {
      start = std::chrono::steady_clock::now();
    }

    double seconds() const
    {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }

  private:
    std::chrono::steady_clock::time_point start;
  };
} // namespace warpchol
