#pragma once

#include <warpchol/base/stopwatch.h>

#include <cstddef>
#include <string>
#include <vector>

/**
 * @file
 * Wall-clock seconds per named stage of a computation (the rotations, the factorization,
 * the VTU output, ...): what a step or a run spent where, and which stages ran at all.
 */
namespace warpchol
{
  /**
   * Seconds and runs per named stage, kept in the order in which the stages ran: a stage
   * that never ran is absent, so the list says what a computation did as well as what it
   * cost. Totals over steps (add(const StageTimes &)) keep the order of a step: a stage
   * that first runs in a later step (the first factorization of a WCC run) takes its place
   * after the stage it follows there. A dozen stages at most: a vector searched by name is
   * all it takes.
   */
  class StageTimes
  {
  public:
    /** One stage: its name, its seconds and how often it ran. */
    struct Stage
    {
      std::string  name;
      double       seconds = 0;
      unsigned int runs    = 0;
    };

    /**
     * Stage @p name ran @p runs times more (once by default; 0 adds time to its last run),
     * for @p seconds in all: added to the stage, appended if new.
     */
    void add(const std::string &name, double seconds, unsigned int runs = 1);

    /**
     * Add every stage of @p other (totals over steps). A stage new here is inserted after
     * the one it follows in @p other (at the front if it comes first there).
     */
    void add(const StageTimes &other);

    /** Seconds of stage @p name; 0 if it never ran. */
    double seconds(const std::string &name) const;
    /** How often stage @p name ran; 0 if it never did. */
    unsigned int runs(const std::string &name) const;
    bool         ran(const std::string &name) const;

    /** Seconds of all stages together. */
    double total_seconds() const;

    /** The stages in the order they first ran. */
    const std::vector<Stage> &stages() const;
    /** Their names, in that order, separated by ", " ("" if none ran). */
    std::string names() const;

  private:
    /** Where stage @p name is in the list; the list's size if the stage never ran. */
    std::size_t  index_of(const std::string &name) const;
    const Stage *find(const std::string &name) const;

    std::vector<Stage> stage_list;
  };

  /**
   * Times one run of a stage, from construction to stop() or destruction, whichever
   * comes first (an exception still records the time spent):
   *   { StageTimer timer(statistics.stages, "assembly"); system.assemble(...); }
   */
  class StageTimer
  {
  public:
    StageTimer(StageTimes &times, std::string name);
    ~StageTimer();

    StageTimer(const StageTimer &)            = delete;
    StageTimer &operator=(const StageTimer &) = delete;

    /** Record the stage now; later calls (and the destructor) do nothing. */
    void stop();

  private:
    StageTimes *times;
    std::string name;
    Stopwatch   stopwatch;
  };
} // namespace warpchol
