#include <warpchol/base/stage_times.h>

#include <algorithm>
#include <utility>

namespace warpchol
{
  std::size_t StageTimes::index_of(const std::string &name) const
  {
    return std::find_if(stage_list.begin(), stage_list.end(),
                        [&](const Stage &stage) { return stage.name == name; }) -
           stage_list.begin();
  }

  const StageTimes::Stage *StageTimes::find(const std::string &name) const
  {
    const std::size_t index = index_of(name);
    return index < stage_list.size() ? &stage_list[index] : nullptr;
  }

  void StageTimes::add(const std::string &name, const double seconds, const unsigned int runs)
  {
    const std::size_t index = index_of(name);
    if (index == stage_list.size())
      stage_list.push_back(Stage{name, 0, 0});
    stage_list[index].seconds += seconds;
    stage_list[index].runs += runs;
  }

  void StageTimes::add(const StageTimes &other)
  {
    // A stage new here goes right after the one it followed in @p other: the stages stay
    // in the order a step runs them, whichever step ran one first.
    std::size_t next_position = 0;
    for (const Stage &other_stage : other.stage_list)
      {
        const std::size_t position = index_of(other_stage.name);
        if (position == stage_list.size())
          {
            stage_list.insert(stage_list.begin() + next_position, other_stage);
            ++next_position;
            continue;
          }
        stage_list[position].seconds += other_stage.seconds;
        stage_list[position].runs += other_stage.runs;
        next_position = position + 1;
      }
  }

  double StageTimes::seconds(const std::string &name) const
  {
    const Stage *stage = find(name);
    return stage ? stage->seconds : 0.0;
  }

  unsigned int StageTimes::runs(const std::string &name) const
  {
    const Stage *stage = find(name);
    return stage ? stage->runs : 0;
  }

  bool StageTimes::ran(const std::string &name) const
  {
    return find(name) != nullptr;
  }

  double StageTimes::total_seconds() const
  {
    double total = 0;
    for (const Stage &stage : stage_list)
      total += stage.seconds;
    return total;
  }

  const std::vector<StageTimes::Stage> &StageTimes::stages() const
  {
    return stage_list;
  }

  std::string StageTimes::names() const
  {
    std::string list;
    for (const Stage &stage : stage_list)
      list += (list.empty() ? "" : ", ") + stage.name;
    return list;
  }

  StageTimer::StageTimer(StageTimes &times, std::string name)
    : times(&times)
    , name(std::move(name))
  {}

  StageTimer::~StageTimer()
  {
    stop();
  }

  void StageTimer::stop()
  {
    if (times == nullptr)
      return;
    times->add(name, stopwatch.seconds());
    times = nullptr;
  }
} // namespace warpchol
