#pragma once

/**
 * @file
 * What the tests of updates and downdates of the factor share: columns of C placed where
 * the modification's paths differ (vertices, supernode boundaries, the top separator,
 * the root, cliques of A), and comparisons of factors.
 */

#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/conversions.h>
#include <warpchol/sparse/residual.h>
#include <warpchol/sparse/spd_perturbation.h>

#include "tests.h"

#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

namespace tests
{
  using warpchol::Index;
  using warpchol::sparse::CSCMatrix;

  /** The solver the updates need: supernodal, METIS ordering. */
  inline warpchol::cholesky::SparseCholesky::Settings supernodal_metis()
  {
    warpchol::cholesky::SparseCholesky::Settings settings;
    settings.ordering.method = warpchol::cholesky::OrderingMethod::metis;
    settings.method          = warpchol::cholesky::FactorizationMethod::supernodal;
    return settings;
  }

  /**
   * A clique of the graph of @p full (both triangles stored) grown greedily from column
   * @p start: a neighbour of @p start joins if it is coupled with every column already in,
   * until @p max_size (sorted). C C^T of a column on these rows adds nothing outside A's
   * pattern, and the rows are coupled in L as well.
   */
  inline std::vector<Index> clique_from(const CSCMatrix &full, const Index start, const std::size_t max_size)
  {
    const auto coupled = [&](const Index i, const Index j) {
      const auto first = full.row_index.begin() + full.column_start[j];
      const auto last  = full.row_index.begin() + full.column_start[j + 1];
      return std::binary_search(first, last, i);
    };
    std::vector<Index> clique{start};
    for (Index k = full.column_start[start]; k < full.column_start[start + 1] && clique.size() < max_size; ++k)
      {
        const Index candidate = full.row_index[k];
        if (candidate != start &&
            std::all_of(clique.begin(), clique.end(), [&](const Index member) { return coupled(candidate, member); }))
          clique.push_back(candidate);
      }
    std::sort(clique.begin(), clique.end());
    return clique;
  }

  /**
   * C (n x rows.size()) whose column t holds, on the rows @p rows[t], @p scale r sqrt(A(i,i))
   * with r uniform in [-1, 1] drawn with @p seed: dense columns, each on its own rows.
   */
  inline CSCMatrix dense_columns(const CSCMatrix &matrix, const std::vector<std::vector<Index>> &rows,
                                 const double scale, const std::uint64_t seed)
  {
    Random    random(seed);
    CSCMatrix c = CSCMatrix::zero(matrix.n_rows, static_cast<Index>(rows.size()));
    for (std::size_t t = 0; t < rows.size(); ++t)
      {
        std::vector<Index> column = rows[t];
        std::sort(column.begin(), column.end());
        for (const Index i : column)
          {
            c.row_index.push_back(i);
            c.values.push_back(scale * (2. * random.uniform() - 1.) * std::sqrt(std::abs(matrix(i, i))));
          }
        c.column_start[t + 1] = static_cast<Index>(c.row_index.size());
      }
    return c;
  }

  /** The columns of @p a and @p b side by side: [a b], or interleaved [a_0 b_0 a_1 b_1 ...] (same counts). */
  inline CSCMatrix side_by_side(const CSCMatrix &a, const CSCMatrix &b, const bool interleaved)
  {
    CSCMatrix c = CSCMatrix::zero(a.n_rows, a.n_cols + b.n_cols);
    const auto append = [&](const CSCMatrix &from, const Index t) {
      c.row_index.insert(c.row_index.end(), from.row_index.begin() + from.column_start[t],
                         from.row_index.begin() + from.column_start[t + 1]);
      c.values.insert(c.values.end(), from.values.begin() + from.column_start[t],
                      from.values.begin() + from.column_start[t + 1]);
    };
    Index column = 0;
    const auto close = [&]() { c.column_start[++column] = static_cast<Index>(c.row_index.size()); };
    if (interleaved)
      for (Index t = 0; t < a.n_cols; ++t)
        {
          append(a, t);
          close();
          append(b, t);
          close();
        }
    else
      {
        for (Index t = 0; t < a.n_cols; ++t)
          {
            append(a, t);
            close();
          }
        for (Index t = 0; t < b.n_cols; ++t)
          {
            append(b, t);
            close();
          }
      }
    return c;
  }

  /** Whether the two factors hold the same values, bit for bit. */
  inline bool same_bits(const CSCMatrix &a, const CSCMatrix &b)
  {
    return a.column_start == b.column_start && a.row_index == b.row_index && a.values == b.values;
  }

  /** ||A x - b|| / ||b|| of @p solver's solve of @p matrix x = b, for b of a random solution. */
  inline double solve_residual(const warpchol::cholesky::SparseCholesky &solver, const CSCMatrix &matrix)
  {
    const std::vector<double> b = right_hand_side_of_random_solution(matrix, 17);
    std::vector<double>       x;
    solver.solve(b, x);
    return warpchol::sparse::relative_residual(matrix, x, b);
  }

  /** A fresh factorization of @p matrix with the analysis of @p solver (same permutation). */
  inline warpchol::cholesky::SparseCholesky fresh_factorization(const warpchol::cholesky::SparseCholesky &solver,
                                                                const CSCMatrix                          &matrix)
  {
    warpchol::cholesky::SparseCholesky fresh = solver;
    fresh.factorize(matrix);
    return fresh;
  }
  /**
   * The change steps of the tests of the update-or-recompute choice, on @p matrix: a
   * penalty on the 9 dofs around a vertex (a grasp), then a random change of 2 vertices'
   * block, then both taken back. Each step: its label, the new matrix, the changed columns.
   */
  struct GraspThenPerturbation
  {
    using Step = std::tuple<std::string, const CSCMatrix *, std::vector<Index>>;

    explicit GraspThenPerturbation(const CSCMatrix &matrix)
      : grasped(warpchol::sparse::local_vertex_columns(matrix, 3, 3, 2))
      , changed_block(warpchol::sparse::local_vertex_columns(matrix, 3, 2, 8))
      , penalized(matrix)
    {
      warpchol::sparse::add_outer_products(penalized, warpchol::sparse::penalty_columns(matrix, grasped, 10.), 1.);
      perturbed = penalized;
      warpchol::sparse::perturb_columns_spd(perturbed, changed_block, 4, 0.2);
      std::vector<Index> both = grasped;
      both.insert(both.end(), changed_block.begin(), changed_block.end());
      steps = {{"a penalty on 9 dofs", &penalized, grasped},
               {"a random change of 2 vertices' block", &perturbed, changed_block},
               {"both removed", &matrix, both}};
    }

    std::vector<Index> grasped, changed_block;
    CSCMatrix          penalized, perturbed;
    std::vector<Step>  steps;
  };

} // namespace tests
