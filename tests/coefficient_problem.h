#pragma once

/**
 * @file
 * A small deal.II problem whose matrix changes in a region, for the tests of
 * SparseDirectCholesky: -div(a grad u) + u on the unit square (Q1, 2^refinements cells
 * per side, no boundary condition: the mass term makes the matrix positive definite),
 * with a coefficient a that is 1 outside a disc and given inside it.
 */

#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace tests
{
  /** The cells whose center lies within @p radius of @p center. */
  struct Disc
  {
    dealii::Point<2> center;
    double           radius = 0;

    bool contains(const dealii::Point<2> &point) const
    {
      return point.distance(center) < radius;
    }
  };

  class CoefficientProblem
  {
  public:
    explicit CoefficientProblem(const unsigned int refinements = 5)
      : fe(1)
      , dof_handler(triangulation)
    {
      dealii::GridGenerator::hyper_cube(triangulation);
      triangulation.refine_global(refinements);
      dof_handler.distribute_dofs(fe);
      dealii::DynamicSparsityPattern dynamic_pattern(dof_handler.n_dofs());
      dealii::DoFTools::make_sparsity_pattern(dof_handler, dynamic_pattern);
      pattern.copy_from(dynamic_pattern);
    }

    /** The matrix for coefficient @p inside in the cells of @p disc, 1 elsewhere. */
    void assemble(dealii::SparseMatrix<double> &matrix, const double inside, const Disc &disc) const
    {
      matrix.reinit(pattern);
      const dealii::QGauss<2> quadrature(2);
      dealii::FEValues<2>     fe_values(fe, quadrature,
                                    dealii::update_values | dealii::update_gradients | dealii::update_JxW_values);
      const unsigned int      n = fe.n_dofs_per_cell();
      dealii::FullMatrix<double>                   cell_matrix(n, n);
      std::vector<dealii::types::global_dof_index> dofs(n);
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          fe_values.reinit(cell);
          const double coefficient = disc.contains(cell->center()) ? inside : 1.;
          cell_matrix              = 0;
          for (const unsigned int q : fe_values.quadrature_point_indices())
            for (unsigned int i = 0; i < n; ++i)
              for (unsigned int j = 0; j < n; ++j)
                cell_matrix(i, j) += (coefficient * fe_values.shape_grad(i, q) * fe_values.shape_grad(j, q) +
                                      fe_values.shape_value(i, q) * fe_values.shape_value(j, q)) *
                                     fe_values.JxW(q);
          cell->get_dof_indices(dofs);
          matrix.add(dofs, cell_matrix);
        }
    }

    /** The rows of the degrees of freedom of the cells of @p disc, sorted. */
    std::vector<dealii::types::global_dof_index> rows_in(const Disc &disc) const
    {
      std::vector<dealii::types::global_dof_index> rows, dofs(fe.n_dofs_per_cell());
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (disc.contains(cell->center()))
          {
            cell->get_dof_indices(dofs);
            rows.insert(rows.end(), dofs.begin(), dofs.end());
          }
      std::sort(rows.begin(), rows.end());
      rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
      return rows;
    }

    /** A right-hand side with entries of both signs. */
    dealii::Vector<double> rhs() const
    {
      dealii::Vector<double> b(dof_handler.n_dofs());
      for (unsigned int i = 0; i < b.size(); ++i)
        b(i) = 1. + std::sin(0.37 * i);
      return b;
    }

    dealii::Triangulation<2> triangulation;
    dealii::FE_Q<2>          fe;
    dealii::DoFHandler<2>    dof_handler;
    dealii::SparsityPattern  pattern;
  };
} // namespace tests
