// A cut removes the elements the blade crosses from A (their stiffness and mass) by a
// partial refactorization of their columns, the symbolic factor unchanged: the run then
// goes on as a run on a mesh built without those elements, started from the same state,
// to 1e-10 (with the linear model, stiffness warping and exact corotation). The blade must
// actually cut. A vertex it leaves in no element is a free particle in the cut run and
// absent from the mesh without the elements: the comparison is on the others.

#include "simulation_tests.h"

#include <fstream>
#include <iomanip>

namespace
{
  /** The small torus, no tool, gravity, model @p model_section, and @p extra sections. */
  std::string scene(const std::string &model_section, const std::string &mesh, const std::string &extra = "")
  {
    std::string text = tests::without_subsection(tests::small_torus_scene(model_section), "Tool");
    if (!mesh.empty())
      text = tests::without_subsection(text, "Mesh") + mesh;
    return text + extra + "subsection Solver\n  set Ordering = metis\nend\n";
  }

  const std::string blade = "subsection Cut\n"
                            "  set Blade start = 0.31, -0.2, -0.15\n"
                            "  set Blade end   = 0.31, 0.2, -0.15\n"
                            "  set Velocity    = 0, 0, 10\n"
                            "  set Start time  = 0.02\n"
                            "  set Duration    = 0.03\n"
                            "end\n";

  /** The vertices of @p body in some element that is not cut, in increasing order. */
  std::vector<unsigned int> vertices_left(const warpchol::fem::ElasticBody &body)
  {
    std::vector<unsigned int> left;
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      if (body.free_particle_mass(v) == 0)
        left.push_back(v);
    return left;
  }

  /** @p field on the vertices @p left only. */
  std::vector<warpchol::fem::Vector3> restricted(const std::vector<warpchol::fem::Vector3> &field,
                                                 const std::vector<unsigned int>            &left)
  {
    std::vector<warpchol::fem::Vector3> result;
    for (const unsigned int v : left)
      result.push_back(field[v]);
    return result;
  }

  /**
   * The mesh of @p body without its cut elements, as a Gmsh 2.2 file: the vertices left,
   * in their order (the mesh reader keeps it).
   */
  void write_mesh_without_cut_elements(const warpchol::fem::ElasticBody &body, const std::string &filename)
  {
    const std::vector<unsigned int> left = vertices_left(body);
    std::vector<unsigned int>       number(body.n_vertices(), 0);
    std::ofstream                   out(filename);
    out << std::setprecision(17) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << left.size() << "\n";
    for (std::size_t k = 0; k < left.size(); ++k)
      {
        const unsigned int v = left[k];
        number[v]            = k + 1;
        out << k + 1 << " " << body.rest_positions()[v][0] << " " << body.rest_positions()[v][1] << " "
            << body.rest_positions()[v][2] << "\n";
      }
    unsigned int n_left = 0;
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      n_left += !body.element_is_cut(e);
    out << "$EndNodes\n$Elements\n" << n_left << "\n";
    unsigned int k = 0;
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      if (!body.element_is_cut(e))
        {
          const auto &v = body.element_vertices(e);
          out << ++k << " 4 0 " << number[v[0]] << " " << number[v[1]] << " " << number[v[2]] << " " << number[v[3]]
              << "\n";
        }
    out << "$EndElements\n";
  }
} // namespace

int main()
{
  const unsigned int cut_steps = 8, later_steps = 12;
  for (const std::string model : {"  set Type = linear\n",
                                  "  set Type = warp_canceling\n  set Rerotation threshold = inf\n",
                                  "  set Type = corotational\n"})
    {
      std::cout << model.substr(model.find('=') + 2, model.find('\n') - model.find('=') - 2)
                << (model.find("inf") != std::string::npos ? " (inf: stiffness warping)" : "") << ":" << std::endl;
      tests::write_file("cut.prm", scene(model, "", blade));
      warpchol::app::Scene cut{warpchol::app::AllParameters("cut.prm")};
      unsigned int         elements_cut = 0;
      for (unsigned int step = 0; step < cut_steps; ++step)
        {
          warpchol::fem::StepStatistics statistics;
          cut.integrator().advance(statistics);
          elements_cut += statistics.elements_cut;
        }
      const auto &body = cut.body();
      const auto  left = vertices_left(body);
      std::cout << "  elements cut: " << elements_cut << ", vertices left in no element: " << body.n_vertices() - left.size()
                << std::endl;
      const auto positions  = restricted(cut.integrator().positions(), left);
      const auto velocities = restricted(cut.integrator().velocities(), left);

      // The mesh without them, from the same state.
      write_mesh_without_cut_elements(body, "without.msh");
      tests::write_file("without.prm", scene(model, "subsection Mesh\n  set Source = file\n  set File = without.msh\nend\n"));
      warpchol::app::Scene without{warpchol::app::AllParameters("without.prm")};
      tests::check("  the mesh without them has the vertices left", without.body().n_vertices() == left.size());
      without.integrator().set_initial_positions(positions);
      without.integrator().set_initial_velocities(velocities);
      for (unsigned int step = 0; step < later_steps; ++step)
        {
          warpchol::fem::StepStatistics statistics;
          cut.integrator().advance(statistics);
          without.integrator().advance(statistics);
        }
      tests::check_below("  later trajectory against the mesh without them",
                         tests::relative_difference(restricted(cut.integrator().positions(), left),
                                                    without.integrator().positions(),
                                                    restricted(body.rest_positions(), left)),
                         1e-10);
    }
}
