#include <warpchol/app/scene_mesh.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/mesh/cell_order.h>
#include <warpchol/mesh/mesh_generators.h>

#include <deal.II/grid/grid_tools.h>

#include <algorithm>
#include <cmath>

namespace warpchol::app
{
  SceneMesh::SceneMesh(const AllParameters &parameters)
    : all(parameters)
  {
    const auto &mesh = all.mesh;
    if (mesh.source == "torus")
      {
        fem::create_torus(tria, mesh.torus);
        text = "generated torus (R " + format_number(mesh.torus.major_radius) + ", r " +
               format_number(mesh.torus.minor_radius) + ", " +
               std::to_string(mesh.torus.toroidal_cells) + " toroidal cells, " +
               std::to_string(mesh.torus.refinements) + " refinements)";
      }
    else if (mesh.source == "box")
      {
        fem::create_box(tria, mesh.box);
        text = "generated box";
        if (mesh.box.grading > 1)
          text += ", graded " + format_number(mesh.box.grading);
        if (mesh.box.sliver_flattening < 1)
          text += ", slivers flattened to " + format_number(mesh.box.sliver_flattening);
      }
    else if (mesh.source == "cylinder")
      {
        fem::create_cylinder(tria, mesh.cylinder);
        text = "generated cylinder (radius " + format_number(mesh.cylinder.radius) + ", length " +
               format_number(mesh.cylinder.length) + ", " + std::to_string(mesh.cylinder.axial_cells) +
               " axial cells, " + std::to_string(mesh.cylinder.refinements) + " refinements)";
      }
    else if (mesh.source == "tube")
      {
        fem::create_tube(tria, mesh.tube);
        text = "generated tube (radii " + format_number(mesh.tube.inner_radius) + " and " +
               format_number(mesh.tube.outer_radius) + ", length " + format_number(mesh.tube.length) + ")";
      }
    else
      {
        numbering = fem::read_mesh(all.mesh_file_path(), tria);
        if (mesh.scale != 1)
          dealii::GridTools::scale(mesh.scale, tria);
        // The file's vertices keep their numbers (deal.II numbers new vertices after them).
        tria.refine_global(mesh.refinements);
        text = mesh.file_name;
        if (mesh.refinements > 0)
          text += ", refined " + std::to_string(mesh.refinements) + " times";
      }
    order = fem::order_cells_for_locality(tria, mesh.cell_order);
    if (numbering.vertex_of_file_vertex.empty())
      for (unsigned int v = 0; v < tria.n_vertices(); ++v)
        numbering.vertex_of_file_vertex.push_back(v);
  }

  const dealii::Triangulation<3> &SceneMesh::triangulation() const
  {
    return tria;
  }

  const fem::CellOrder &SceneMesh::cell_order() const
  {
    return order;
  }

  const std::string &SceneMesh::description() const
  {
    return text;
  }

  void SceneMesh::partition(const unsigned int n_parts)
  {
    dealii::GridTools::partition_triangulation(n_parts, tria);
  }

  std::vector<bool> SceneMesh::marks(const std::vector<unsigned int> &vertices) const
  {
    std::vector<bool> marked(tria.n_vertices(), false);
    for (const unsigned int v : vertices)
      marked[v] = true;
    return marked;
  }

  double SceneMesh::volume() const
  {
    double volume = 0;
    for (const auto &cell : tria.active_cell_iterators())
      {
        const dealii::Tensor<1, 3> a = cell->vertex(1) - cell->vertex(0);
        const dealii::Tensor<1, 3> b = cell->vertex(2) - cell->vertex(0);
        const dealii::Tensor<1, 3> c = cell->vertex(3) - cell->vertex(0);
        volume += std::abs(dealii::scalar_product(a, dealii::cross_product_3d(b, c))) / 6;
      }
    return volume;
  }

  fem::Material SceneMesh::material() const
  {
    fem::Material material{all.material.youngs_modulus, all.material.poisson_ratio, all.material.density};
    if (all.material.total_mass > 0)
      material.density = all.material.total_mass / volume();
    return material;
  }

  std::vector<unsigned int> SceneMesh::select_vertices(const RegionParameters &region,
                                                       const std::string      &subsection) const
  {
    std::vector<unsigned int> selected;
    if (region.kind == "none")
      return selected;
    const auto where = [&](const std::string &entry) { return all.file.where(subsection, entry); };
    if (region.kind == "ids")
      {
        const long n_file_vertices = numbering.vertex_of_file_vertex.size();
        for (const long id : region.vertex_ids)
          {
            if (id < 0 || id >= n_file_vertices)
              throw InputError(where("Vertex ids") + ": vertex " + std::to_string(id) +
                               " does not exist (the mesh has " +
                               std::to_string(n_file_vertices) + " vertices, ids from 0)");
            const long vertex = numbering.vertex_of_file_vertex[id];
            if (vertex < 0)
              throw InputError(where("Vertex ids") + ": vertex " + std::to_string(id) +
                               " belongs to no tetrahedron");
            selected.push_back(vertex);
          }
        std::sort(selected.begin(), selected.end());
        selected.erase(std::unique(selected.begin(), selected.end()), selected.end());
        return selected;
      }
    const auto &rest = tria.get_vertices();
    for (unsigned int v = 0; v < rest.size(); ++v)
      {
        const fem::Vector3 x(rest[v][0], rest[v][1], rest[v][2]);
        const bool         inside =
          region.kind == "box" ?
                    (x.array() >= region.box_lower_corner.array()).all() &&
              (x.array() <= region.box_upper_corner.array()).all() :
                    (x - region.sphere_center).norm() <= region.sphere_radius;
        if (inside)
          selected.push_back(v);
      }
    if (selected.empty())
      throw InputError(where("Region") + " = " + region.kind + ": the region holds no vertex of the mesh");
    return selected;
  }

} // namespace warpchol::app
