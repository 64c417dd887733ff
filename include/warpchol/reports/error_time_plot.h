#pragma once

#include <array>
#include <ostream>
#include <string>
#include <vector>

/**
 * @file
 * The plot of the error-against-time study: trajectory error (log scale) against seconds
 * per step, one point per configuration, the Pareto front drawn, drawn by gnuplot.
 */
namespace warpchol::app
{
  /**
   * A gnuplot script with its data inline (so that a user can edit and rerun it) and the
   * PNG it draws: two panels, the worst vertex's error and the RMS error (app::PositionError,
   * each its largest over the steps), against seconds per step. Each configuration is a
   * point of its group's colour, labelled with its threshold; the configurations that no
   * other one beats in both time and error are joined as the Pareto front. The exact
   * reference run has error 0, which a log scale cannot show: it is the vertical line at
   * its time (it ends the front, since it beats every slower configuration). A run whose
   * error exceeds 1 (more than the whole motion: it diverged) is drawn at 1 with its error
   * in its label, and is on no front.
   */
  class ErrorTimePlot
  {
  public:
    /** One configuration of the study. */
    struct Point
    {
      /** The legend entry, e.g. "WCC partial". */
      std::string group;
      /** The label beside the point, e.g. the threshold "0.3". */
      std::string label;
      double      seconds_per_step = 0;
      double      max_error        = 0;
      double      rms_error        = 0;
    };

    /** @p reference_seconds_per_step: the time of the exact run, with error 0. */
    ErrorTimePlot(const std::string &title, const std::string &reference_name,
                  double reference_seconds_per_step);

    void add(const Point &point);

    /**
     * Write the script @p script_file, which draws @p png_file, and run gnuplot on it if it
     * is on the PATH (from the working directory: the paths are as given). Prints one line
     * on @p messages when there is no gnuplot or it fails; returns whether the PNG was
     * written.
     */
    bool write(const std::string &script_file, const std::string &png_file,
               std::ostream &messages) const;

    /** The script that draws @p png_file. */
    std::string script(const std::string &png_file) const;

  private:
    /** The legend's groups, in the order of their first point. */
    std::vector<std::string> groups() const;
    /** The points of each group and the Pareto fronts as data blocks; whether a point diverged. */
    bool write_data(std::ostream &out) const;
    /** The terminal, the two panels' margins and axes, the reference's line. */
    void write_layout(std::ostream &out, const std::string &png_file, bool any_diverged) const;
    /** Width, height and the legend column's width (pixels). */
    std::array<double, 3> picture_size() const;
    /** The plot commands of both panels: the front, each group's points and labels. */
    void write_panels(std::ostream &out) const;

    std::string        title;
    std::string        reference_name;
    double             reference_seconds_per_step;
    std::vector<Point> points;
  };

  /** Whether an executable @p program is on the PATH. */
  bool program_on_path(const std::string &program);
} // namespace warpchol::app
