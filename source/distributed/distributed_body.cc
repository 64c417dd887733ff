#include <warpchol/base/exceptions.h>
#include <warpchol/distributed/distributed_body.h>

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/grid/tria_description.h>
#include <deal.II/lac/sparsity_tools.h>

#include <algorithm>

namespace warpchol::distributed
{
  DistributedBody::DistributedBody(app::SceneMesh &mesh, const fem::Material &material,
                                   const fem::MassMatrix mass_matrix, const std::vector<bool> &fixed_vertex,
                                   const MPI_Comm communicator)
    : comm(communicator)
    , tria(communicator)
    , fe(dealii::FE_SimplexP<3>(1), 3)
    , fe_mapping(dealii::FE_SimplexP<3>(1))
  {
    // Every rank holds the whole coarse mesh (read or generated alike) and computes the
    // same METIS partition; deal.II then keeps each rank's cells and a layer of ghosts.
    const dealii::Triangulation<3> &serial = mesh.triangulation();
    mesh.partition(n_ranks());
    tria.create_triangulation(
      dealii::TriangulationDescription::Utilities::create_description_from_triangulation(serial, comm));
    dofs.reinit(tria);
    dofs.distribute_dofs(fe);
    owned_dofs = dofs.locally_owned_dofs();
    dealii::DoFTools::extract_locally_relevant_dofs(dofs, relevant_dofs);
    pattern.reinit(relevant_dofs.size(), relevant_dofs.size(), relevant_dofs);
    dealii::DoFTools::make_sparsity_pattern(dofs, pattern);
    dealii::SparsityTools::distribute_sparsity_pattern(pattern, owned_dofs, comm, relevant_dofs);

    // The local body: owned and ghost cells, their vertices numbered in order of appearance.
    std::vector<int>                      local_of_mesh_vertex(serial.n_vertices(), -1);
    std::vector<dealii::Point<3>>         points;
    std::vector<dealii::CellData<3>>      cells;
    std::vector<dealii::types::global_dof_index> cell_dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dofs.active_cell_iterators())
      {
        if (!cell->is_locally_owned() && !cell->is_ghost())
          continue;
        const auto          serial_cell = serial.create_cell_iterator(cell->id());
        dealii::CellData<3> data(4);
        for (unsigned int a = 0; a < 4; ++a)
          {
            const unsigned int mesh_v = serial_cell->vertex_index(a);
            if (local_of_mesh_vertex[mesh_v] < 0)
              {
                local_of_mesh_vertex[mesh_v] = points.size();
                points.push_back(serial_cell->vertex(a));
                vertex_in_mesh.push_back(mesh_v);
                vertex_dofs.emplace_back();
              }
            data.vertices[a] = local_of_mesh_vertex[mesh_v];
          }
        cell->get_dof_indices(cell_dofs);
        for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
          {
            const auto [component, a] = fe.system_to_component_index(i);
            vertex_dofs[data.vertices[a]][component] = cell_dofs[i];
          }
        if (cell->is_locally_owned())
          owned_element_list.push_back(cells.size());
        cell_index.push_back(cell->active_cell_index());
        cells.push_back(data);
      }
    local_tria.create_triangulation(points, cells, dealii::SubCellData());

    std::vector<bool> local_fixed(points.size());
    for (unsigned int v = 0; v < points.size(); ++v)
      local_fixed[v] = fixed_vertex[vertex_in_mesh[v]];
    body = std::make_unique<fem::ElasticBody>(local_tria, material, mass_matrix, local_fixed);
    // The element kernels index the local body's elements as the cells were given.
    for (unsigned int e = 0; e < cells.size(); ++e)
      for (unsigned int a = 0; a < 4; ++a)
        if (body->element_vertices(e)[a] != cells[e].vertices[a])
          throw Error("distributed body: the local triangulation reordered cell " + std::to_string(e));

    unsigned long owned_unknowns = 0;
    owned_row.assign(points.size(), -1);
    for (unsigned int v = 0; v < points.size(); ++v)
      if (owned_dofs.is_element(vertex_dofs[v][0]))
        {
          const auto row = owned_dofs.index_within_set(vertex_dofs[v][0]);
          // A vertex's three dofs are consecutive rows: the blocks ML aggregates whole.
          for (unsigned int c = 1; c < 3; ++c)
            if (owned_dofs.index_within_set(vertex_dofs[v][c]) != row + c)
              throw Error("distributed body: the dofs of a vertex are not consecutive");
          owned_row[v] = row;
          owned_vertex_list.push_back(v);
          if (!local_fixed[v])
            owned_unknowns += 3;
        }
    global_elements = tria.n_global_active_cells();
    global_vertices = dealii::Utilities::MPI::sum<unsigned long>(owned_vertex_list.size(), comm);
    global_unknowns = dealii::Utilities::MPI::sum(owned_unknowns, comm);
  }

  MPI_Comm DistributedBody::communicator() const
  {
    return comm;
  }

  unsigned int DistributedBody::rank() const
  {
    return dealii::Utilities::MPI::this_mpi_process(comm);
  }

  unsigned int DistributedBody::n_ranks() const
  {
    return dealii::Utilities::MPI::n_mpi_processes(comm);
  }

  const dealii::parallel::fullydistributed::Triangulation<3> &DistributedBody::triangulation() const
  {
    return tria;
  }

  const dealii::DoFHandler<3> &DistributedBody::dof_handler() const
  {
    return dofs;
  }

  const dealii::Mapping<3> &DistributedBody::mapping() const
  {
    return fe_mapping;
  }

  const dealii::IndexSet &DistributedBody::locally_owned_dofs() const
  {
    return owned_dofs;
  }

  const dealii::IndexSet &DistributedBody::locally_relevant_dofs() const
  {
    return relevant_dofs;
  }

  const dealii::DynamicSparsityPattern &DistributedBody::sparsity_pattern() const
  {
    return pattern;
  }

  const fem::ElasticBody &DistributedBody::local_body() const
  {
    return *body;
  }

  const std::vector<unsigned int> &DistributedBody::owned_elements() const
  {
    return owned_element_list;
  }

  const std::vector<unsigned int> &DistributedBody::owned_vertices() const
  {
    return owned_vertex_list;
  }

  const std::array<dealii::types::global_dof_index, 3> &DistributedBody::dofs_of_vertex(const unsigned int v) const
  {
    return vertex_dofs[v];
  }

  unsigned int DistributedBody::mesh_vertex(const unsigned int v) const
  {
    return vertex_in_mesh[v];
  }

  unsigned int DistributedBody::active_cell_index(const unsigned int e) const
  {
    return cell_index[e];
  }

  unsigned long DistributedBody::n_global_elements() const
  {
    return global_elements;
  }

  unsigned long DistributedBody::n_global_vertices() const
  {
    return global_vertices;
  }

  unsigned long DistributedBody::n_global_unknowns() const
  {
    return global_unknowns;
  }

  int DistributedBody::first_owned_row(const unsigned int v) const
  {
    return owned_row[v];
  }

  double DistributedBody::sum(const double value) const
  {
    return dealii::Utilities::MPI::sum(value, comm);
  }

  double DistributedBody::max(const double value) const
  {
    return dealii::Utilities::MPI::max(value, comm);
  }
} // namespace warpchol::distributed
