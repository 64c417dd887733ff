// An instrument path read from a CSV file is linear between its samples: at a sample it is
// the sample to the bit, between two it is their interpolation, outside it holds; the
// times the path bends at between two times are its samples there. Column names, comments,
// blank lines and CRLF line ends are skipped.

#include "simulation_tests.h"

#include <warpchol/app/path_file.h>

#include <iomanip>

using namespace warpchol;

int main()
{
  tests::write_file("jaws.csv", "# jaws recorded at 100 Hz\r\ntime,x,y,z\r\n\r\n0.00, 0, 0, 0\r\n0.01, 1, 2, -4\r\n"
                                "0.02, 1, 4, -4\r\n");
  const app::PathFile jaws = app::PathFile::read("jaws.csv", 3, "time, x, y, z");
  std::cout << std::setprecision(17) << "samples " << jaws.path.n_samples() << " on lines " << jaws.first_line << " to "
            << jaws.last_line << ", from " << jaws.path.start_time() << " s to " << jaws.path.end_time() << " s"
            << std::endl;
  for (const double t : {-1., 0., 0.0025, 0.005, 0.01, 0.015, 0.0175, 0.02, 5.})
    {
      const fem::Vector3 p = jaws.path.position(t);
      std::cout << "  t " << t << ": " << p[0] << ", " << p[1] << ", " << p[2] << std::endl;
    }
  tests::check("at a sample, the sample", jaws.path.position(0.01) == fem::Vector3(1, 2, -4));
  tests::check_below("a quarter of the way", (jaws.path.position(0.0125) - fem::Vector3(1, 2.5, -4)).norm(), 1e-15);
  std::cout << "bends between 0.005 and 0.02:";
  for (const double t : jaws.path.times_between(0.005, 0.02))
    std::cout << " " << t;
  std::cout << std::endl;

  // A blade: both ends, each interpolated.
  tests::write_file("blade.csv", "0, 0, 0, 0, 0, 1, 0\n1, 2, 0, 0, 2, 1, 2\n");
  const app::PathFile blade = app::PathFile::read("blade.csv", 6, "time, start x, y, z, end x, y, z");
  const fem::Vector3  a = blade.path.position(0.25, 0), b = blade.path.position(0.25, 3);
  std::cout << "blade at 0.25 s: " << a[0] << ", " << a[1] << ", " << a[2] << " to " << b[0] << ", " << b[1] << ", "
            << b[2] << std::endl;
  fem::Blade edge{{}, {}, {}, 0, 1, blade.path};
  const auto [start, end] = edge.edge_at(0.5);
  tests::check("the blade's edge follows its path", start == fem::Vector3(1, 0, 0) && end == fem::Vector3(1, 1, 1));
  tests::check("a blade on a path moves", edge.moves_during(0.1, 0.2) && !edge.moves_during(1, 2));
}
