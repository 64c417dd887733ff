#pragma once

#include <warpchol/app/scene_mesh.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/small_dense.h>

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <array>
#include <memory>
#include <vector>

/**
 * @file
 * A body distributed over the ranks of an MPI communicator: deal.II's
 * parallel::fullydistributed::Triangulation and DoFHandler for the global numbering, and
 * on each rank an ElasticBody over its own cells and one layer of ghost cells, so that
 * the element kernels of the serial code (rotations, corotated forces, WCC's estimate,
 * element matrices) run unchanged on a rank's part.
 */
namespace warpchol::distributed
{
  /**
   * The mesh of a scene partitioned by METIS (GridTools::partition_triangulation) into one
   * part per rank, as a parallel::fullydistributed::Triangulation<3> with the element
   * FESystem(FE_SimplexP<3>(1), 3) and its DoFHandler.
   *
   * The rank's *local body* is an ElasticBody over its locally owned cells and its ghost
   * cells, with a local numbering of their vertices. Every vertex of an owned cell has all
   * its elements in the local body: its elastic force, its nodal rotation and its row of
   * the mass matrix are complete there. Owned dofs are those deal.II gives the rank; they
   * all sit on vertices of owned cells. Ghost cells are evaluated on two ranks: one layer,
   * the price of running the serial kernels unchanged.
   *
   * Fixed vertices are not unknowns of the global system: their rows and columns hold only
   * a 1 on the diagonal, and their velocities stay 0.
   */
  class DistributedBody
  {
  public:
    /**
     * Partition @p mesh (its subdomain ids are overwritten: every rank computes the same
     * partition) over @p communicator and set up the local body. @p fixed_vertex is
     * indexed by the vertices of @p mesh. Throws InputError naming the cell when an
     * element has no volume (on the rank that owns it; the others then fail too).
     */
    DistributedBody(app::SceneMesh &mesh, const fem::Material &material, fem::MassMatrix mass_matrix,
                    const std::vector<bool> &fixed_vertex, MPI_Comm communicator);

    MPI_Comm     communicator() const;
    unsigned int rank() const;
    unsigned int n_ranks() const;

    const dealii::parallel::fullydistributed::Triangulation<3> &triangulation() const;
    const dealii::DoFHandler<3>                                 &dof_handler() const;
    const dealii::Mapping<3>                                    &mapping() const;
    const dealii::IndexSet &locally_owned_dofs() const;
    const dealii::IndexSet &locally_relevant_dofs() const;
    /** The couplings of the owned rows (every dof of every cell with every other), distributed. */
    const dealii::DynamicSparsityPattern &sparsity_pattern() const;

    /** The rank's cells (owned and ghost) as a serial body, in the local numbering. */
    const fem::ElasticBody &local_body() const;
    /** The owned elements of the local body, in increasing order. */
    const std::vector<unsigned int> &owned_elements() const;
    /** The local vertices whose dofs this rank owns, in increasing order. */
    const std::vector<unsigned int> &owned_vertices() const;
    /** The global dofs of local vertex @p v, component by component. */
    const std::array<dealii::types::global_dof_index, 3> &dofs_of_vertex(unsigned int v) const;
    /** The vertex of the scene's mesh that local vertex @p v is. */
    unsigned int mesh_vertex(unsigned int v) const;
    /** The active cell index (in triangulation()) of local element @p e. */
    unsigned int active_cell_index(unsigned int e) const;

    /** Cells, vertices and unknowns (free dofs) of the whole body. */
    unsigned long n_global_elements() const;
    unsigned long n_global_vertices() const;
    unsigned long n_global_unknowns() const;

    /**
     * The rows of @p values (one per owned dof, in the order of locally_owned_dofs()) that
     * local vertex @p v's dofs are, or -1 for a vertex this rank does not own.
     */
    int first_owned_row(unsigned int v) const;

    /** Sum of @p value over the ranks. */
    double sum(double value) const;
    /** Maximum of @p value over the ranks. */
    double max(double value) const;

  private:
    MPI_Comm                                             comm;
    dealii::parallel::fullydistributed::Triangulation<3> tria;
    dealii::FESystem<3>                                  fe;
    dealii::MappingFE<3>                                 fe_mapping;
    dealii::DoFHandler<3>                                dofs;
    dealii::IndexSet                                     owned_dofs;
    dealii::IndexSet                                     relevant_dofs;
    dealii::DynamicSparsityPattern                       pattern;

    /** The serial triangulation of the local body's cells (it must outlive the body). */
    dealii::Triangulation<3>               local_tria;
    std::unique_ptr<fem::ElasticBody>      body;
    std::vector<unsigned int>              owned_element_list;
    std::vector<unsigned int>              owned_vertex_list;
    std::vector<int>                       owned_row;
    std::vector<std::array<dealii::types::global_dof_index, 3>> vertex_dofs;
    std::vector<unsigned int>              vertex_in_mesh;
    std::vector<unsigned int>              cell_index;
    unsigned long                          global_elements = 0;
    unsigned long                          global_vertices = 0;
    unsigned long                          global_unknowns = 0;
  };
} // namespace warpchol::distributed
