// Output/VTU precision = float64 writes every number of the VTU files in double precision
// (deal.II 9.4's DataOut writes Float32 only, about 7 digits): read back through VTK's own
// XML reader (as ParaView reads it), the displacements and velocities of the last step
// equal the run's to the last bit, and many of them differ from their float32 rounding.
// The default, float32, still writes deal.II's Float32 files.

#include "simulation_tests.h"

#include <warpchol/app/simulation.h>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <sstream>

using namespace warpchol;

namespace
{
  std::string scene(const std::string &name, const std::string &precision)
  {
    return "subsection Mesh\n  set Source = box\n  set Box subdivisions = 2, 1, 1\nend\n"
           "subsection Time stepping\n  set Number of steps = 3\nend\n"
           "subsection Fixed vertices\n  set Region = box\n"
           "  set Box lower corner = -1, -1, -1\n  set Box upper corner = 0, 1, 1\nend\n"
           "subsection Gravity\n  set Acceleration = 0, -9.81, 0\nend\n"
           "subsection Output\n  set Directory = results\n  set Scene = " + name + "\n"
           "  set VTU interval = 3\n  set Progress = off\n  set VTU precision = " + precision + "\nend\n";
  }

  /** Run the scene; return the simulation, done, for its final state. */
  std::unique_ptr<app::Simulation> run(const std::string &name, const std::string &precision)
  {
    tests::write_file(name + ".prm", scene(name, precision));
    auto               simulation = std::make_unique<app::Simulation>(app::AllParameters(name + ".prm"));
    std::ostringstream summary;
    simulation->run(summary);
    return simulation;
  }

  vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const std::string &filename)
  {
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(filename.c_str());
    reader->Update();
    return reader->GetOutput();
  }
} // namespace

int main()
{
  const auto simulation = run("double", "float64");
  const auto grid       = read_vtu("results/double/double-00003.vtu");
  const auto &body      = simulation->scene(0).body();
  const auto  exact_displacements = simulation->scene(0).integrator().displacements();
  const auto  exact_velocities    = simulation->scene(0).integrator().velocities();
  tests::check("float64: VTK reads a vertex per mesh vertex and a cell per tetrahedron",
               grid != nullptr && grid->GetNumberOfPoints() == body.n_vertices() &&
                 grid->GetNumberOfCells() == body.n_elements());
  vtkDataArray *displacement = grid->GetPointData()->GetArray("displacement");
  vtkDataArray *velocity     = grid->GetPointData()->GetArray("velocity");
  tests::check("float64: displacement and velocity are arrays of doubles",
               displacement != nullptr && velocity != nullptr &&
                 displacement->GetDataType() == VTK_DOUBLE && velocity->GetDataType() == VTK_DOUBLE &&
                 displacement->GetNumberOfComponents() == 3);
  tests::check("float64: the cell fields rerotated and steps_since_rerotation are there",
               grid->GetCellData()->GetArray("rerotated") != nullptr &&
                 grid->GetCellData()->GetArray("steps_since_rerotation") != nullptr);
  bool         exact           = displacement != nullptr && velocity != nullptr;
  unsigned int beyond_float32  = 0;
  double       largest_motion  = 0;
  for (unsigned int v = 0; exact && v < body.n_vertices(); ++v)
    for (unsigned int c = 0; c < 3; ++c)
      {
        const double written = displacement->GetComponent(v, c);
        exact = exact && written == exact_displacements[v][c] &&
                velocity->GetComponent(v, c) == exact_velocities[v][c];
        beyond_float32 += static_cast<double>(static_cast<float>(written)) != written;
        largest_motion = std::max(largest_motion, std::abs(written));
      }
  tests::check("float64: every displacement and velocity equals the run's to the last bit", exact);
  tests::check("float64: the body moved (some displacement above 1e-6)", largest_motion > 1e-6);
  tests::check("float64: over a third of the displacements hold more digits than a float32",
               beyond_float32 > body.n_vertices());
  // The rest positions too: a point plus its displacement is the current position.
  bool points_exact = true;
  for (unsigned int v = 0; v < body.n_vertices(); ++v)
    for (unsigned int c = 0; c < 3; ++c)
      points_exact = points_exact && grid->GetPoint(v)[c] == body.rest_positions()[v][c];
  tests::check("float64: the points are the rest positions, exactly", points_exact);

  run("single", "float32");
  const auto    single_grid  = read_vtu("results/single/single-00003.vtu");
  vtkDataArray *single_array = single_grid->GetPointData()->GetArray("displacement");
  tests::check("float32 (the default): deal.II's file of floats",
               single_array != nullptr && single_array->GetDataType() == VTK_FLOAT &&
                 tests::read_file("results/single/single-00003.vtu").find("Float64") == std::string::npos);
}
