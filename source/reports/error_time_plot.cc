#include <warpchol/reports/error_time_plot.h>
#include <warpchol/base/atomic_file.h>
#include <warpchol/base/format.h>
#include <warpchol/base/pareto_front.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace warpchol::app
{
  namespace
  {
    /**
     * An error above the largest displacement itself: the run strayed by more than the
     * whole motion (diverged). Such a point is drawn at this height with its value in its
     * label and is on no Pareto front: it is no trade-off.
     */
    constexpr double diverged_error = 1;

    /** @p text as a gnuplot string constant. */
    std::string quoted(const std::string &text)
    {
      std::string result = "\"";
      for (const char c : text)
        {
          if (c == '"' || c == '\\')
            result += '\\';
          result += c;
        }
      return result + "\"";
    }

    /** @p text as one word of a POSIX shell command. */
    std::string shell_word(const std::string &text)
    {
      std::string result = "'";
      for (const char c : text)
        result += c == '\'' ? std::string("'\\''") : std::string(1, c);
      return result + "'";
    }
  } // namespace

  bool program_on_path(const std::string &program)
  {
    const char *path = std::getenv("PATH");
    std::istringstream directories(path ? path : "");
    std::string        directory;
    while (std::getline(directories, directory, ':'))
      {
        const std::string candidate = (directory.empty() ? "." : directory) + "/" + program;
        if (std::filesystem::is_regular_file(candidate) && access(candidate.c_str(), X_OK) == 0)
          return true;
      }
    return false;
  }

  ErrorTimePlot::ErrorTimePlot(const std::string &title, const std::string &reference_name,
                               const double reference_seconds_per_step)
    : title(title)
    , reference_name(reference_name)
    , reference_seconds_per_step(reference_seconds_per_step)
  {}

  void ErrorTimePlot::add(const Point &point)
  {
    points.push_back(point);
  }

  std::vector<std::string> ErrorTimePlot::groups() const
  {
    // In the order of their first point: a colour and a point type each.
    std::vector<std::string> names;
    for (const auto &point : points)
      if (std::find(names.begin(), names.end(), point.group) == names.end())
        names.push_back(point.group);
    return names;
  }

  std::string ErrorTimePlot::script(const std::string &png_file) const
  {
    std::ostringstream out;
    out << "# The error-against-time study, written by warpchol-threshold-sweep: edit and\n"
        << "# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.\n"
        << "# Per configuration: seconds per step, the largest over the steps of the worst\n"
        << "# vertex's error max_i |x_i - x_i(ref)| and of the RMS error\n"
        << "# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.\n\n";
    const bool any_diverged = write_data(out);
    write_layout(out, png_file, any_diverged);
    write_panels(out);
    out << "unset multiplot\n";
    return out.str();
  }

  bool ErrorTimePlot::write_data(std::ostream &out) const
  {
    const auto                     number = [](const double value) { return format_number(value, 6); };
    const std::vector<std::string> groups = this->groups();
    bool                           any_diverged = false;
    for (unsigned int g = 0; g < groups.size(); ++g)
      {
        // Columns: seconds, max error, RMS error (both clipped at diverged_error), the labels
        // in the panels of the max and of the RMS error.
        out << "# " << groups[g] << "\n$group" << g << " << EOD\n";
        for (const auto &point : points)
          if (point.group == groups[g])
            {
              const auto clipped = [&](const double error) {
                any_diverged = any_diverged || !(error <= diverged_error);
                return number(error <= diverged_error ? error : diverged_error);
              };
              const auto label = [&](const double error) {
                return quoted(error <= diverged_error ? point.label :
                                                        point.label + " (diverged: " + format_number(error, 2) + ")");
              };
              out << number(point.seconds_per_step) << " " << clipped(point.max_error) << " "
                  << clipped(point.rms_error) << " " << label(point.max_error) << " "
                  << label(point.rms_error) << "\n";
            }
        out << "EOD\n";
      }
    // A log scale shows no error <= 0: those configurations (equal to the reference to the
    // last bit) and the reference itself are left to the vertical line.
    for (const bool rms : {false, true})
      {
        std::vector<double> seconds, errors;
        for (const auto &point : points)
          {
            const double error = rms ? point.rms_error : point.max_error;
            seconds.push_back(point.seconds_per_step);
            errors.push_back(error <= diverged_error ? error : std::nan(""));
          }
        seconds.push_back(reference_seconds_per_step);
        errors.push_back(0);
        out << (rms ? "$front_rms" : "$front_max") << " << EOD\n";
        for (const unsigned int i : pareto_front(seconds, errors))
          if (errors[i] > 0)
            out << number(seconds[i]) << " " << number(errors[i]) << "\n";
        out << "EOD\n";
      }
    return any_diverged;
  }

  void ErrorTimePlot::write_layout(std::ostream &out, const std::string &png_file, const bool any_diverged) const
  {
    const auto number = [](const double value) { return format_number(value, 6); };
    double     largest_seconds = reference_seconds_per_step, smallest_seconds = reference_seconds_per_step;
    for (const auto &point : points)
      {
        largest_seconds  = std::max(largest_seconds, point.seconds_per_step);
        smallest_seconds = std::min(smallest_seconds, point.seconds_per_step);
      }
    // Peers that take 100x longer would squeeze every other point against the axis.
    const bool log_seconds = smallest_seconds > 0 && largest_seconds > 30 * smallest_seconds;
    const auto [width, height, key_width] = picture_size();
    const auto fraction = [](const double pixels, const double of) { return format_number(pixels / of, 4); };
    const std::string size = std::to_string(static_cast<int>(width)) + "," + std::to_string(static_cast<int>(height));

    out << "\nif (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) {\n"
        << "  set terminal pngcairo size " << size << " font \",11\"\n"
        << "} else {\n"
        << "  set terminal png size " << size << "\n"
        << "}\n"
        << "set termoption noenhanced\n"
        << "set output " << quoted(png_file) << "\n"
        // Margins (left, right, bottom, top) and the space between the panels, in parts of
        // the picture: room for the y labels, the x labels, the title and the legend.
        << "set multiplot layout 1,2 margins " << fraction(90, width) << ", " << fraction(width - key_width, width)
        << ", " << fraction(70, height) << ", " << fraction(height - 55, height) << " spacing "
        << fraction(110, width) << " title " << quoted(title) << "\n"
        << "set logscale y\n"
        << "set format y \"%.0e\"\n"
        << "set grid\n"
        << "set key at screen " << fraction(width - key_width + 15, width) << ", screen "
        << fraction(height - 55, height) << " left top vertical Left reverse\n"
        << "set xlabel \"seconds per step\"\n"
        << (log_seconds ? "set logscale x\nset xrange [" + number(0.7 * smallest_seconds) + ":" +
                            number(1.4 * largest_seconds) + "]\n" :
                          "set xrange [0:" + number(1.08 * largest_seconds) + "]\n")
        << (any_diverged ? "set yrange [*:" + number(2 * diverged_error) + "]\n" : std::string())
        << "set arrow 1 from " << number(reference_seconds_per_step) << ", graph 0 to "
        << number(reference_seconds_per_step) << ", graph 1 nohead dashtype 2 linewidth 2 linecolor rgb \"black\"\n"
        << "set label 1 " << quoted(reference_name + " (error 0)") << " at "
        << number(reference_seconds_per_step) << ", graph 0.5 center rotate by 90 offset -1.2, 0\n";
  }

  std::array<double, 3> ErrorTimePlot::picture_size() const
  {
    // The legend is a column of its own right of both panels, outside their axes, so that
    // no number of groups brings it onto a tick label or an axis label: the picture widens
    // by the column, as wide as the longest title (pngcairo's 11 points take about 8
    // pixels a character; 9 here, and the sample before it), and the panels keep their
    // 1500 x 650 pixels.
    std::size_t longest_title = std::string("Pareto front").size();
    for (const auto &group : groups())
      longest_title = std::max(longest_title, group.size());
    const double height = 650, key_width = 90 + 9 * static_cast<double>(longest_title);
    return {{1500 + key_width, height, key_width}};
  }

  void ErrorTimePlot::write_panels(std::ostream &out) const
  {
    const std::vector<std::string> groups = this->groups();
    for (const bool rms : {false, true})
      {
        // One legend for both panels.
        if (rms)
          out << "unset key\n";
        out << "set ylabel " << quoted(rms ? "RMS error over the largest displacement (max over steps)" :
                                             "worst vertex error over the largest displacement (max over steps)")
            << "\n";
        const std::string column = rms ? "3" : "2";
        out << "plot " << (rms ? "$front_rms" : "$front_max")
            << " using 1:2 with lines linewidth 2 linecolor rgb \"gray40\" title \"Pareto front\"";
        // Each group's labels on its own side of the points, so that neighbours overlap less.
        const char *label_places[] = {"left offset 0.8, 0.7", "left offset 0.8, -0.7",
                                      "right offset -0.8, 0.7", "right offset -0.8, -0.7"};
        // A colour and a point shape per group, the pairs distinct for 12 groups (gnuplot's
        // own colours repeat after 8).
        const char *colours[] = {"#9400d3", "#009e73", "#56b4e9", "#e69f00", "#f0e442", "#0072b2",
                                 "#e51e10", "#000000", "#a0522d", "#ff69b4", "#808000", "#20b2aa"};
        const int   shapes[]  = {5, 7, 9, 11, 13, 15, 4, 6, 8, 10, 12, 14};
        for (unsigned int g = 0; g < groups.size(); ++g)
          {
            const std::string colour = quoted(colours[g % 12]);
            out << ", \\\n     $group" << g << " using 1:" << column << " with points pointtype "
                << shapes[g % 12] << " pointsize 1.6 linecolor rgb " << colour << " title " << quoted(groups[g])
                << ", \\\n     $group" << g << " using 1:" << column << ":" << (rms ? "5" : "4")
                << " with labels " << label_places[g % 4] << " textcolor rgb " << colour << " notitle";
          }
        out << "\n";
      }
  }

  bool ErrorTimePlot::write(const std::string &script_file, const std::string &png_file,
                            std::ostream &messages) const
  {
    write_file_atomically(script_file, [&](std::ostream &out) { out << script(png_file); });
    if (!program_on_path("gnuplot"))
      {
        messages << "no gnuplot on the PATH: no plot (the script " << script_file
                 << " draws it: gnuplot " << script_file << ")" << std::endl;
        return false;
      }
    std::error_code no_old_plot;
    std::filesystem::remove(png_file, no_old_plot);
    const int status = std::system(("gnuplot " + shell_word(script_file)).c_str());
    if (status != 0 || !std::filesystem::exists(png_file))
      {
        messages << "gnuplot failed on " << script_file << ": no plot" << std::endl;
        return false;
      }
    return true;
  }
} // namespace warpchol::app
