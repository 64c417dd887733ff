// The error-against-time plot keeps its legend outside the axes of both panels, whatever
// the number of groups: with the twelve groups of the peers' comparison it overlapped the
// x-axis label and the tick labels (doc/backends/torus_pull_60k.png). The script is drawn
// by gnuplot as SVG, whose texts carry their positions: every legend entry must lie right
// of the right panel's axes, inside the picture, and overlap no tick label or axis label.

#include "tests.h"

#include <warpchol/reports/error_time_plot.h>

#include <regex>

using namespace warpchol;

namespace
{
  /** A text of the SVG picture: its box (pixels, y downwards) and what it says. */
  struct Text
  {
    double      left, right, top, bottom;
    std::string text;
    bool        black;
  };

  /** The texts of gnuplot's SVG @p svg, their boxes estimated from the font size. */
  std::vector<Text> texts_of(const std::string &svg)
  {
    const std::regex text_element(
      "translate\\(([-0-9.]+),([-0-9.]+)\\)( rotate\\(270\\))?\"[^>]*fill=\"([^\"]*)\"[^>]*font-size=\"([0-9.]+)\""
      "[^>]*text-anchor=\"([a-z]+)\">\\s*<text>([^<]*)</text>");
    std::vector<Text> texts;
    for (auto match = std::sregex_iterator(svg.begin(), svg.end(), text_element); match != std::sregex_iterator();
         ++match)
      {
        const double x = std::stod((*match)[1]), y = std::stod((*match)[2]), size = std::stod((*match)[5]);
        const std::string anchor = (*match)[6], text = (*match)[7];
        // Arial's characters average about 0.6 of the font size; the anchor is the
        // baseline's start, middle or end.
        const double length = 0.6 * size * static_cast<double>(text.size());
        const double start  = anchor == "start" ? 0 : anchor == "middle" ? -length / 2 : -length;
        Text         box;
        if ((*match)[3].matched) // rotated: the text reads upwards from its anchor
          box = {x - size, x, y - start - length, y - start, text, false};
        else
          box = {x + start, x + start + length, y - size, y, text, false};
        box.black = (*match)[4] == "black";
        texts.push_back(box);
      }
    return texts;
  }

  bool overlap(const Text &a, const Text &b)
  {
    return a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;
  }
} // namespace

int main()
{
  // The groups of the peers' comparison, times from 0.2 to 100 s (a log axis).
  const std::vector<std::string> groups = {"WCC partial", "WCC auto", "WCC preconditioned", "cholmod",
                                           "umfpack", "eigen", "eigen_cholmod", "trilinos_amg_cg",
                                           "warp_preconditioned_cg", "WCC target error", "WCC delayed_top",
                                           "another peer"};
  app::ErrorTimePlot plot("torus_pull_60k: twelve groups", "corotational", 0.86);
  for (std::size_t g = 0; g < groups.size(); ++g)
    plot.add({groups[g], "1", 0.2 * std::pow(1.8, static_cast<double>(g)), std::pow(10., -2. - g), std::pow(10., -3. - g)});

  // The script as the program writes it, drawn as SVG at the same size, in the font size
  // of pngcairo's 11 points (96 pixels an inch: 14.7 pixels).
  std::string script = plot.script("plot.svg");
  std::smatch size;
  if (!std::regex_search(script, size, std::regex("set terminal pngcairo size ([0-9]+),([0-9]+)")))
    throw std::runtime_error("the script sets no pngcairo terminal");
  // The sizes are copied before the script they point into is replaced.
  const std::string width_text = size[1].str(), height_text = size[2].str();
  script = std::regex_replace(script, std::regex("set terminal png[^\n]*"),
                              "set terminal svg size " + width_text + "," + height_text + " font \"Arial,14.67\"");
  // Where the right panel's axes end (pixels from the left), as gnuplot drew them.
  script += "set print \"right_axis.txt\"\nprint GPVAL_TERM_XMAX\n";
  std::ofstream("plot_svg.gp") << script;
  if (std::system("gnuplot plot_svg.gp") != 0)
    throw std::runtime_error("gnuplot failed on plot_svg.gp");
  const double      right_axis = std::stod(tests::read_file("right_axis.txt"));
  const double      width      = std::stod(width_text);
  const std::vector<Text> texts = texts_of(tests::read_file("plot.svg"));

  std::vector<std::string> titles = groups;
  titles.push_back("Pareto front");
  std::vector<Text> legend, labels;
  for (const Text &text : texts)
    (std::find(titles.begin(), titles.end(), text.text) != titles.end() && text.black ? legend : labels).push_back(text);
  tests::check("the legend lists the Pareto front and the 12 groups", legend.size() == titles.size());
  tests::check("the x-axis label is drawn under both panels",
               std::count_if(labels.begin(), labels.end(),
                             [](const Text &text) { return text.text == "seconds per step"; }) == 2);
  bool outside = true, inside_picture = true, clear = true;
  for (const Text &entry : legend)
    {
      outside        = outside && entry.left > right_axis;
      inside_picture = inside_picture && entry.right <= width;
      for (const Text &label : labels)
        if (label.black && overlap(entry, label))
          {
            clear = false;
            std::cout << "'" << entry.text << "' overlaps '" << label.text << "'" << std::endl;
          }
    }
  tests::check("every legend entry lies right of the right panel's axes", outside);
  tests::check("every legend entry lies inside the picture", inside_picture);
  tests::check("no legend entry overlaps a tick label, an axis label or the title", clear);
}
