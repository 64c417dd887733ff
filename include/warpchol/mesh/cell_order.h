#pragma once

#include <warpchol/base/named_values.h>

#include <deal.II/grid/tria.h>

#include <array>
#include <vector>

/**
 * @file
 * The order of a mesh's cells and of its unknowns, chosen for the element kernels' memory
 * traffic: the assembly of A adds each element's 78 entries into the columns of its four
 * vertices, and finds them in cache when the elements before it wrote there.
 */
namespace warpchol::fem
{
  /** Mesh/Cell order. */
  enum class CellOrderChoice
  {
    /** Sorted when that makes the elements meet their vertices sooner again (see below). */
    automatic,
    /** Always sorted. */
    locality,
    /** The file's or the generator's order, unknowns in vertex order. */
    given
  };

  /** The names of Mesh/Cell order (base/named_values.h): "automatic", "locality", "given". */
  inline constexpr NameTable<CellOrderChoice, 3> cell_order_names{{{CellOrderChoice::automatic, "automatic"},
                                                                  {CellOrderChoice::locality, "locality"},
                                                                  {CellOrderChoice::given, "given"}}};

  /** What order_cells_for_locality() did. */
  struct CellOrder
  {
    /** Whether the cells were sorted. */
    bool sorted = false;
    /** For every cell, its active cell index before (the identity when not sorted). */
    std::vector<unsigned int> given_cell;
    /**
     * Every vertex once, in the order the free ones are to get their unknowns
     * (ElasticBody's @p unknown_order); empty: vertex order.
     */
    std::vector<unsigned int> unknown_order;
    /** vertex_misses_per_cell() of the given and of the sorted order. */
    double given_misses  = 0;
    double sorted_misses = 0;
  };

  /**
   * How often the cells, taken in @p order, use a vertex that none of the @p window cells
   * before used: the misses per cell of a small cache of the vertices' columns. 4 for
   * cells in random order, 0.45 for deal.II's tetrahedra of refined hexahedra (24 per
   * hexahedron, in a row), about 1 for cells sorted by their vertices.
   */
  double vertex_misses_per_cell(const std::vector<std::array<unsigned int, 4>> &cell_vertices,
                                const std::vector<unsigned int> &order, unsigned int n_vertices,
                                unsigned int window = 16);

  /**
   * Order the cells of @p triangulation for locality. The vertices are put in Cuthill-McKee
   * order (deal.II's SparsityTools, on the graph of the mesh's edges: level by level from a
   * boundary vertex, a narrow front through slender and compact bodies alike); the cells
   * sorted by their vertices' ranks in it (the smallest first), and the unknowns numbered
   * in it. With @p choice automatic the cells are sorted if that lowers
   * vertex_misses_per_cell(): a mesh whose cells come in no useful
   * order (SOFA's) is sorted, so that consecutive cells share vertices and the element
   * kernels find them in cache (doc/kernels.md gives the effect), while a generated
   * mesh's tetrahedra come 24 per hexahedron and are best left so.
   *
   * Sorting rebuilds @p triangulation from its active cells as one coarse level. The
   * vertices keep their numbers (the file's, for a mesh read: its vertex ids, and the
   * outputs' points, stay the file's), each cell its vertices in their order (its
   * orientation); manifold and boundary ids are not kept (the simulation uses neither).
   */
  CellOrder order_cells_for_locality(dealii::Triangulation<3> &triangulation, CellOrderChoice choice);
} // namespace warpchol::fem
