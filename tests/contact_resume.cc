// Checkpoints of a contact scene: a run stopped after 10 steps and resumed with "--resume"
// to 20 ends where the same run never stopped ends: the log's last row, its contact work
// and friction's dissipation (totals over the run) and its energies, to 1e-9 relative. The
// checkpoint holds the contact totals and the warm start (the last step's contacts and
// impulses). Not to the bit: the resumed run's factor is a new revision, so the columns of
// L^-1 the uninterrupted run kept are solved anew, which changes the last bits of W.
// Scene: the tests' small torus, held on its far side, sagging under gravity onto a table
// with friction 0.5; the same with W lagging behind the factor (Contact/Compliance lag: a
// checkpoint drops the kept columns, and the run that wrote it renews W as the resumed one
// does); then with penalty springs (Contact/Method = penalty), whose checkpoint also holds
// the springs tied and their diagonal.

#include "simulation_tests.h"

#include <algorithm>
#include <filesystem>
#include <map>

namespace
{
  /** The scene, its contacts by constraints (W lagging if @p lag) or, if @p penalty, by penalty springs. */
  std::string scene(const std::string &directory, const unsigned int n_steps, const bool penalty, const bool lag)
  {
    return tests::without_subsection(tests::small_torus_scene("  set Type = corotational\n"), "Tool") +
           "subsection Time stepping\n"
           "  set Number of steps = " + std::to_string(n_steps) + "\n"
           "end\n"
           "subsection Contact\n"
           "  set Alarm distance   = 0.002\n"
           "  set Contact distance = 1e-4\n" +
           (penalty ? std::string("  set Method = penalty\n") :
                      std::string("  set Max iterations   = 500\n  set Tolerance        = 1e-10\n")) +
           (lag ? "  set Compliance lag = true\n" : "") +
           "end\n"
           "subsection Obstacle\n"
           "  set Type     = plane\n"
           "  set Point    = 0, -0.11, 0\n"
           "  set Normal   = 0, 1, 0\n" +
           (penalty ? "" : "  set Friction = 0.5\n") +
           "end\n"
           "subsection Output\n"
           "  set Directory = " + directory + "\n"
           "  set VTU interval = 10\n"
           "  set Write log = true\n"
           "  set Print timings = false\n"
           "  set Progress = off\n"
           "  set Checkpoint interval = 10\n"
           "end\n";
  }

  /** The columns of the last row of the log.csv under @p directory, by name. */
  std::map<std::string, std::string> last_row(const std::string &directory)
  {
    std::string file;
    for (const auto &entry : std::filesystem::recursive_directory_iterator(directory))
      if (entry.path().filename() == "log.csv")
        file = entry.path().string();
    std::istringstream text(tests::read_file(file));
    std::string        header, line, last;
    std::getline(text, header);
    while (std::getline(text, line))
      if (!line.empty())
        last = line;
    const auto split = [](const std::string &row) {
      std::vector<std::string> fields;
      std::istringstream       stream(row);
      for (std::string field; std::getline(stream, field, ',');)
        fields.push_back(field);
      return fields;
    };
    std::map<std::string, std::string> row;
    const auto names = split(header), values = split(last);
    for (std::size_t k = 0; k < names.size() && k < values.size(); ++k)
      row[names[k]] = values[k];
    return row;
  }
} // namespace

int main()
{
  for (const std::string method : {"constraints", "lagged", "penalty"})
    {
      const bool penalty = method == "penalty", lag = method == "lagged";
      std::cout << "-- contact by " << method << std::endl;
      const std::string straight_directory = "straight_" + method, resumed_directory = "resumed_" + method;
      tests::write_file(straight_directory + ".prm", scene(straight_directory, 20, penalty, lag));
      std::cout << "20 steps: " << tests::run_warpchol({straight_directory + ".prm"}) << std::endl;
      // The same file (its name names the output folder), extended from 10 steps to 20.
      tests::write_file(resumed_directory + ".prm", scene(resumed_directory, 10, penalty, lag));
      std::cout << "10 steps: " << tests::run_warpchol({resumed_directory + ".prm"}) << std::endl;
      tests::write_file(resumed_directory + ".prm", scene(resumed_directory, 20, penalty, lag));
      std::cout << "resumed to 20: " << tests::run_warpchol({resumed_directory + ".prm", "--resume"}) << std::endl;

      const auto straight = last_row(straight_directory), resumed = last_row(resumed_directory);
      tests::check("both logs end at step 20", straight.at("step") == "20" && resumed.at("step") == "20");
      tests::check("the table holds the torus (contacts in the last step)", std::stod(straight.at("contacts")) > 0);
      for (const std::string column : {"contact_work", "friction_dissipation", "kinetic_energy", "elastic_energy"})
        {
          const double a = std::stod(straight.at(column)), b = std::stod(resumed.at(column));
          tests::check_below("|" + column + " resumed - straight| / |straight|",
                             std::abs(b - a) / std::max(std::abs(a), 1e-300), 1e-9);
        }
    }
}
