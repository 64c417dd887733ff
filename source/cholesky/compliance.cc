#include <warpchol/base/exceptions.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/cholesky/compliance.h>

#include <algorithm>
#include <type_traits>
#include <unordered_map>

#include "supernode_solve_kernel.h"

namespace warpchol::cholesky
{
  namespace
  {
    void check_constraints(const SupernodalSymbolic &symbolic, const std::vector<double> &values,
                           const sparse::CSCMatrix &ht)
    {
      if (ht.n_rows != symbolic.n)
        throw InputError("the constraints have " + std::to_string(ht.n_rows) + " rows, the factor " +
                         std::to_string(symbolic.n) + " columns");
      if (values.size() < static_cast<std::size_t>(symbolic.n_stored_values()))
        throw Error("compliance of a factor without values (factorize() first)");
      ht.check_consistency();
    }

    /**
     * Copy the lower triangle of the m x m @p w into its upper one, in tiles: a tile's
     * strided writes then fall on a few dozen rows that stay in cache.
     */
    void symmetrize(std::vector<double> &w, const Index m)
    {
      constexpr Index tile = 32;
      for (Index jb = 0; jb < m; jb += tile)
        for (Index ib = jb; ib < m; ib += tile)
          for (Index j = jb; j < std::min(jb + tile, m); ++j)
            for (Index i = std::max(ib, j + 1); i < std::min(ib + tile, m); ++i)
              w[j + i * m] = w[i + j * m];
    }

    /**
     * The structure of the forward solve of the columns of @p ht on their paths: the
     * supernodes, their constraints and where their panels start; the panels are left to
     * the caller (in the precision it solves in).
     */
    PathForwardSolve path_structure(const SupernodalSymbolic &symbolic, const sparse::CSCMatrix &ht)
    {
      const Index      ns = symbolic.n_supernodes();
      const Index      m  = ht.n_cols;
      PathForwardSolve solve;
      solve.m = m;

      // The paths: from the supernode of each nonzero of h_i up to the root, stopping where
      // an earlier nonzero of the same column has been (the reach of h_i). Columns are
      // visited in order, so each supernode's list of constraints comes out sorted.
      std::vector<Index> visited_by(ns, -1), count(ns, 0);
      const auto         walk_paths = [&](const auto &visit) {
        std::fill(visited_by.begin(), visited_by.end(), Index(-1));
        for (Index i = 0; i < m; ++i)
          for (Index p = ht.column_start[i]; p < ht.column_start[i + 1]; ++p)
            for (Index s = symbolic.supernode_of[ht.row_index[p]]; s >= 0 && visited_by[s] != i;
                 s       = symbolic.supernode_parent[s])
              {
                visited_by[s] = i;
                visit(s, i);
              }
      };
      walk_paths([&](const Index s, Index) { ++count[s]; });

      std::vector<Index> position_of(ns, -1);
      solve.constraint_start.push_back(0);
      solve.panel_start.push_back(0);
      for (Index s = 0; s < ns; ++s)
        if (count[s] > 0)
          {
            position_of[s] = static_cast<Index>(solve.supernodes.size());
            solve.supernodes.push_back(s);
            solve.constraint_start.push_back(solve.constraint_start.back() + count[s]);
            solve.panel_start.push_back(solve.panel_start.back() +
                                        static_cast<std::size_t>(count[s]) * symbolic.n_columns(s));
          }
      solve.constraints.resize(solve.constraint_start.back());
      std::vector<Index> filled(solve.supernodes.size(), 0);
      walk_paths([&](const Index s, const Index i) {
        const Index k = position_of[s];
        solve.constraints[solve.constraint_start[k] + filled[k]++] = i;
      });
      return solve;
    }

    /** position_of[s]: the place of supernode s in @p solve's list, -1 if off its paths. */
    std::vector<Index> positions_of(const SupernodalSymbolic &symbolic, const PathForwardSolve &solve)
    {
      std::vector<Index> position_of(symbolic.n_supernodes(), -1);
      for (std::size_t k = 0; k < solve.supernodes.size(); ++k)
        position_of[solve.supernodes[k]] = static_cast<Index>(k);
      return position_of;
    }

    /** The local row of constraint @p i in supernode entry @p k of @p solve. */
    Index local_row(const PathForwardSolve &solve, const Index k, const Index i)
    {
      const auto begin = solve.constraints.begin() + solve.constraint_start[k];
      const auto end   = solve.constraints.begin() + solve.constraint_start[k + 1];
      return static_cast<Index>(std::lower_bound(begin, end, i) - begin);
    }

    /** The unit columns (n x |which|) of the rows rows[which[0]], rows[which[1]], ... */
    sparse::CSCMatrix unit_columns(const Index n, const std::vector<Index> &rows, const std::vector<Index> &which)
    {
      sparse::CSCMatrix columns = sparse::CSCMatrix::zero(n, static_cast<Index>(which.size()));
      for (std::size_t f = 0; f < which.size(); ++f)
        {
          columns.row_index.push_back(rows[which[f]]);
          columns.values.push_back(1.);
          columns.column_start[f + 1] = static_cast<Index>(f + 1);
        }
      return columns;
    }
  } // namespace

  namespace
  {
    /**
     * B = B L^-T for the m x n panel B and the n x n diagonal block L of a supernode, in
     * blocks of columns: a triangular solve on each block's diagonal, then a product
     * (gemm) for the columns after it. BLAS's right-sided trsm alone runs at a third to a
     * half of gemm's rate on the panels of the top supernodes (m several hundred).
     */
    template <typename Scalar>
    void solve_panel(const Index m, const Index n, const Scalar *l, const Index ldl, Scalar *b)
    {
      constexpr Index block = 32;
      for (Index j = 0; j < n; j += block)
        {
          const Index width = std::min(block, n - j), after = n - j - width;
          blas::trsm_right_lower_transpose(static_cast<int>(m), static_cast<int>(width), l + j + j * ldl,
                                           static_cast<int>(ldl), b + j * m, static_cast<int>(m));
          if (after > 0)
            blas::gemm_nt(static_cast<int>(m), static_cast<int>(after), static_cast<int>(width), Scalar(-1),
                          b + j * m, static_cast<int>(m), l + j + width + j * ldl, static_cast<int>(ldl), Scalar(1),
                          b + (j + width) * m, static_cast<int>(m));
        }
    }

    /**
     * The panels of @p solve (its structure from path_structure()) solved with the factor
     * @p values in the precision Scalar: the right-hand sides of @p ht placed, then
     * supernode by supernode, children first, Y_s = L_ss^-1 b_s on the panel (transposed:
     * Y_s^T L_ss^-T), then the rows below it, L_bs Y_s (gemm), subtracted from the panels
     * of the ancestors that hold those rows. In single precision each supernode's values
     * are rounded as it comes, into a buffer that stays in cache for its products.
     */
    template <typename Scalar>
    void solve_panels(const SupernodalSymbolic &symbolic, const std::vector<double> &values,
                      const sparse::CSCMatrix &ht, PathForwardSolve &solve, std::vector<Scalar> &panels)
    {
      std::vector<Scalar> rounded;
      const auto          values_of = [&](const Index s) -> const Scalar * {
        const double *begin = values.data() + symbolic.value_start[s];
        if constexpr (std::is_same_v<Scalar, double>)
          return begin;
        else
          {
            rounded.assign(begin, begin + symbolic.n_rows(s) * symbolic.n_columns(s));
            return rounded.data();
          }
      };
      const std::vector<Index> position_of = positions_of(symbolic, solve);
      panels.assign(solve.panel_start.back(), Scalar(0));
      for (Index i = 0; i < ht.n_cols; ++i)
        for (Index p = ht.column_start[i]; p < ht.column_start[i + 1]; ++p)
          {
            const Index row = ht.row_index[p], s = symbolic.supernode_of[row], k = position_of[s];
            const Index n_constraints = solve.constraint_start[k + 1] - solve.constraint_start[k];
            panels[solve.panel_start[k] + local_row(solve, k, i) +
                   static_cast<std::size_t>(row - symbolic.first_column[s]) * n_constraints] +=
              static_cast<Scalar>(ht.values[p]);
          }

      std::vector<Scalar> below;
      std::vector<Index>  map;
      for (std::size_t k = 0; k < solve.supernodes.size(); ++k)
        {
          const Index   s  = solve.supernodes[k];
          const Index   kc = solve.constraint_start[k + 1] - solve.constraint_start[k];
          const Index   nc = symbolic.n_columns(s), nr = symbolic.n_rows(s), rows_below = nr - nc;
          const Scalar *ls = values_of(s);
          const Index  *rows = symbolic.row_index.data() + symbolic.row_start[s];
          Scalar       *panel = panels.data() + solve.panel_start[k];
          solve_panel(kc, nc, ls, nr, panel);
          solve.solve_flops += static_cast<double>(kc) * nc * nc;
          if (rows_below == 0)
            continue;
          below.resize(static_cast<std::size_t>(kc) * rows_below);
          blas::gemm_nt(static_cast<int>(kc), static_cast<int>(rows_below), static_cast<int>(nc), Scalar(1), panel,
                        static_cast<int>(kc), ls + nc, static_cast<int>(nr), Scalar(0), below.data(),
                        static_cast<int>(kc));
          solve.solve_flops += 2. * static_cast<double>(kc) * nc * rows_below;

          // The rows below, grouped by the ancestor holding them (rows are sorted, and a
          // supernode's columns contiguous). Every path through s goes on through that
          // ancestor, so its constraints include those of s: map them by a merge.
          const Index *own = solve.constraints.data() + solve.constraint_start[k];
          for (Index q = 0; q < rows_below;)
            {
              const Index t     = symbolic.supernode_of[rows[nc + q]];
              const Index kt    = position_of[t];
              const Index ct    = solve.constraint_start[kt + 1] - solve.constraint_start[kt];
              const Index end_t = symbolic.first_column[t + 1];
              Index       end   = q;
              while (end < rows_below && rows[nc + end] < end_t)
                ++end;
              Scalar *target = panels.data() + solve.panel_start[kt];
              if (ct == kc)
                for (; q < end; ++q)
                  {
                    Scalar *to = target + static_cast<std::size_t>(rows[nc + q] - symbolic.first_column[t]) * ct;
                    const Scalar *from = below.data() + static_cast<std::size_t>(q) * kc;
                    for (Index a = 0; a < kc; ++a)
                      to[a] -= from[a];
                  }
              else
                {
                  map.resize(kc);
                  const Index *theirs = solve.constraints.data() + solve.constraint_start[kt];
                  for (Index a = 0, b = 0; a < kc; ++a)
                    {
                      while (theirs[b] != own[a])
                        ++b;
                      map[a] = b;
                    }
                  for (; q < end; ++q)
                    {
                      Scalar *to = target + static_cast<std::size_t>(rows[nc + q] - symbolic.first_column[t]) * ct;
                      const Scalar *from = below.data() + static_cast<std::size_t>(q) * kc;
                      for (Index a = 0; a < kc; ++a)
                        to[map[a]] -= from[a];
                    }
                }
            }
        }
    }

    /**
     * W = Y^T Y (m x m, column-major, both triangles) from @p panels, laid out as the
     * panels of @p solve, summed in the precision Scalar.
     */
    template <typename Scalar>
    std::vector<double> product_of_panels(const SupernodalSymbolic &symbolic, PathForwardSolve &solve,
                                          const std::vector<Scalar> &panels)
    {
      const Index         m = solve.m;
      std::vector<Scalar> w(static_cast<std::size_t>(m) * m, Scalar(0));
      std::vector<Scalar> gram;
      solve.product_flops = 0;
      // W = sum over the supernodes on the paths of Y_s^T Y_s, each on its constraints: at
      // the top, where every path meets, straight into W. Consecutive supernodes with the
      // same constraints (a chain no path joins) have their panels one after the other, as
      // one wider panel: one product for the run.
      const auto same_constraints = [&](const std::size_t a, const std::size_t b) {
        return std::equal(solve.constraints.begin() + solve.constraint_start[a],
                          solve.constraints.begin() + solve.constraint_start[a + 1],
                          solve.constraints.begin() + solve.constraint_start[b],
                          solve.constraints.begin() + solve.constraint_start[b + 1]);
      };
      for (std::size_t k = 0, next = 0; k < solve.supernodes.size(); k = next)
        {
          const Index kc    = solve.constraint_start[k + 1] - solve.constraint_start[k];
          Index       width = 0;
          for (next = k; next < solve.supernodes.size() && (next == k || same_constraints(k, next)); ++next)
            width += symbolic.n_columns(solve.supernodes[next]);
          const Scalar *panel = panels.data() + solve.panel_start[k];
          solve.product_flops += static_cast<double>(kc) * (kc + 1) * width;
          if (kc == m)
            {
              blas::syrk_lower(static_cast<int>(m), static_cast<int>(width), Scalar(1), panel, static_cast<int>(m),
                               Scalar(1), w.data(), static_cast<int>(m));
              continue;
            }
          gram.resize(static_cast<std::size_t>(kc) * kc);
          blas::syrk_lower(static_cast<int>(kc), static_cast<int>(width), Scalar(1), panel, static_cast<int>(kc),
                           Scalar(0), gram.data(), static_cast<int>(kc));
          const Index *own = solve.constraints.data() + solve.constraint_start[k];
          for (Index b = 0; b < kc; ++b)
            for (Index a = b; a < kc; ++a)
              w[own[a] + static_cast<std::size_t>(own[b]) * m] += gram[a + static_cast<std::size_t>(b) * kc];
        }
      if constexpr (std::is_same_v<Scalar, double>)
        {
          symmetrize(w, m);
          return w;
        }
      else
        {
          std::vector<double> result(w.begin(), w.end());
          symmetrize(result, m);
          return result;
        }
    }
  } // namespace

  PathForwardSolve forward_solve_on_paths(const SupernodalSymbolic &symbolic, const std::vector<double> &values,
                                          const sparse::CSCMatrix &ht)
  {
    check_constraints(symbolic, values, ht);
    PathForwardSolve solve = path_structure(symbolic, ht);
    solve_panels(symbolic, values, ht, solve, solve.panels);
    return solve;
  }

  std::vector<double> compliance_from_paths(const SupernodalSymbolic &symbolic, PathForwardSolve &solve)
  {
    return product_of_panels(symbolic, solve, solve.panels);
  }

  std::vector<double> compliance_on_paths_in_single_precision(const SupernodalSymbolic &symbolic,
                                                              const std::vector<double> &values,
                                                              const sparse::CSCMatrix &ht, PathForwardSolve &solve)
  {
    check_constraints(symbolic, values, ht);
    solve = path_structure(symbolic, ht);
    solve_panels(symbolic, values, ht, solve, solve.single_panels);
    return product_of_panels(symbolic, solve, solve.single_panels);
  }

  namespace
  {
    /** Where a column of Y lives: its layer and its column (constraint) there. */
    struct ColumnPlace
    {
      Index layer = -1, column = -1;
    };

    /** The panels of @p solve in the precision Scalar (PathForwardSolve::single_panels for float). */
    template <typename Scalar>
    std::vector<Scalar> &panels_of(PathForwardSolve &solve)
    {
      if constexpr (std::is_same_v<Scalar, float>)
        return solve.single_panels;
      else
        return solve.panels;
    }

    /**
     * The layers of @p columns merged into one: Y on the paths of the unknowns at the
     * places in use, each column copied from its layer. A column's path is that of its
     * one nonzero: the same supernodes in either.
     */
    template <typename Scalar>
    void merge_layers(const SupernodalSymbolic &symbolic, KeptInverseColumns &columns)
    {
      const Index              n_places = static_cast<Index>(columns.rows.size());
      std::vector<ColumnPlace> place(n_places);
      std::vector<std::vector<Index>> at(columns.layers.size());
      for (std::size_t l = 0; l < columns.layers.size(); ++l)
        {
          at[l] = positions_of(symbolic, columns.layers[l]);
          for (std::size_t c = 0; c < columns.layer_positions[l].size(); ++c)
            if (const Index i = columns.layer_positions[l][c]; i >= 0)
              place[i] = {static_cast<Index>(l), static_cast<Index>(c)};
        }
      std::vector<Index> used;
      for (Index p = 0; p < n_places; ++p)
        if (columns.rows[p] >= 0)
          used.push_back(p);
      PathForwardSolve merged = path_structure(symbolic, unit_columns(symbolic.n, columns.rows, used));
      std::vector<Scalar> &merged_panels = panels_of<Scalar>(merged);
      merged_panels.resize(merged.panel_start.back());
      // Per supernode, where each of its constraints' rows comes from; then the panel
      // column by column, so that reads and writes both run down the rows.
      std::vector<const Scalar *> from;
      std::vector<Index>          from_ld;
      for (std::size_t k = 0; k < merged.supernodes.size(); ++k)
        {
          const Index s  = merged.supernodes[k];
          const Index nc = symbolic.n_columns(s);
          const Index kc = merged.constraint_start[k + 1] - merged.constraint_start[k];
          from.resize(kc);
          from_ld.resize(kc);
          for (Index a = 0; a < kc; ++a)
            {
              const ColumnPlace where  = place[used[merged.constraints[merged.constraint_start[k] + a]]];
              PathForwardSolve &source = columns.layers[where.layer];
              const Index       ks     = at[where.layer][s];
              from[a] = panels_of<Scalar>(source).data() + source.panel_start[ks] + local_row(source, ks, where.column);
              from_ld[a] = source.constraint_start[ks + 1] - source.constraint_start[ks];
            }
          Scalar *to = merged_panels.data() + merged.panel_start[k];
          for (Index c = 0; c < nc; ++c)
            for (Index a = 0; a < kc; ++a)
              to[a + static_cast<std::size_t>(c) * kc] = from[a][static_cast<std::size_t>(c) * from_ld[a]];
        }
      columns.layers.assign(1, std::move(merged));
      columns.layer_positions.assign(1, std::move(used));
    }

    /**
     * The rows of G at the places @p fresh of the unknowns solved as @p solved (in its
     * column order): among themselves from @p solved alone, and with each kept column
     * supernode by supernode (their panel rows times the layer's panel, gemm), mirrored
     * into their columns; in the precision Scalar that the panels are kept in.
     */
    template <typename Scalar>
    void add_fresh_rows_of_gram(const SupernodalSymbolic &symbolic, const std::vector<Index> &fresh,
                                PathForwardSolve &solved, KeptInverseColumns &columns)
    {
      const std::size_t ld    = columns.rows.size();
      double           *gram  = columns.gram.data();
      for (const Index i : fresh)
        for (std::size_t j = 0; j < ld; ++j)
          gram[i + j * ld] = 0.;
      const std::vector<double> among = product_of_panels(symbolic, solved, panels_of<Scalar>(solved));
      for (std::size_t b = 0; b < fresh.size(); ++b)
        for (std::size_t a = 0; a < fresh.size(); ++a)
          gram[fresh[a] + fresh[b] * ld] = among[a + b * fresh.size()];
      const std::vector<Index> solved_at = positions_of(symbolic, solved);
      std::vector<Scalar>      product;
      for (std::size_t l = 0; l < columns.layers.size(); ++l)
        {
          PathForwardSolve         &layer     = columns.layers[l];
          const std::vector<Index> &positions = columns.layer_positions[l];
          for (std::size_t k = 0; k < layer.supernodes.size(); ++k)
            {
              const Index ks = solved_at[layer.supernodes[k]];
              if (ks < 0)
                continue;
              const Index nc = symbolic.n_columns(layer.supernodes[k]);
              const Index kf = solved.constraint_start[ks + 1] - solved.constraint_start[ks];
              const Index kc = layer.constraint_start[k + 1] - layer.constraint_start[k];
              product.resize(static_cast<std::size_t>(kf) * kc);
              blas::gemm_nt(static_cast<int>(kf), static_cast<int>(kc), static_cast<int>(nc), Scalar(1),
                            panels_of<Scalar>(solved).data() + solved.panel_start[ks], static_cast<int>(kf),
                            panels_of<Scalar>(layer).data() + layer.panel_start[k], static_cast<int>(kc), Scalar(0),
                            product.data(), static_cast<int>(kf));
              const Index *own_fresh = solved.constraints.data() + solved.constraint_start[ks];
              const Index *own_kept  = layer.constraints.data() + layer.constraint_start[k];
              for (Index b = 0; b < kc; ++b)
                if (const Index j = positions[own_kept[b]]; j >= 0)
                  for (Index a = 0; a < kf; ++a)
                    gram[fresh[own_fresh[a]] + static_cast<std::size_t>(j) * ld] +=
                      product[a + static_cast<std::size_t>(b) * kf];
            }
        }
      for (const Index i : fresh)
        for (std::size_t j = 0; j < ld; ++j)
          gram[j + static_cast<std::size_t>(i) * ld] = gram[i + j * ld];
    }

    /**
     * @p columns laid out anew with the unknowns of @p asked at the places 0, 1, ... and
     * @p spare free places after them: the entries of G among those kept (at @p kept_at,
     * -1: new) copied, the layers' positions moved with them.
     */
    void lay_out_anew(const std::vector<Index> &asked, const std::vector<Index> &kept_at, const std::size_t spare,
                      KeptInverseColumns &columns)
    {
      const std::size_t   n_places = asked.size() + spare, ld = columns.rows.size();
      std::vector<Index>  goes(ld, -1), kept_rows;
      std::vector<double> gram(n_places * n_places, 0.);
      for (std::size_t i = 0; i < asked.size(); ++i)
        if (kept_at[i] >= 0)
          {
            goes[kept_at[i]] = static_cast<Index>(i);
            kept_rows.push_back(static_cast<Index>(i));
          }
      // Column by column over the kept rows only; the new rows and columns stay zero.
      for (const Index j : kept_rows)
        {
          double       *to   = gram.data() + static_cast<std::size_t>(j) * n_places;
          const double *from = columns.gram.data() + static_cast<std::size_t>(kept_at[j]) * ld;
          for (const Index i : kept_rows)
            to[i] = from[kept_at[i]];
        }
      for (std::vector<Index> &positions : columns.layer_positions)
        for (Index &position : positions)
          position = position >= 0 ? goes[position] : -1;
      columns.gram = std::move(gram);
      columns.rows = asked;
      columns.rows.resize(n_places, -1);
    }
  } // namespace

  std::vector<double> KeptInverseColumns::block() const
  {
    const std::size_t   m = places.size(), ld = rows.size();
    std::vector<double> g(m * m);
    for (std::size_t j = 0; j < m; ++j)
      for (std::size_t i = 0; i < m; ++i)
        g[i + j * m] = gram[places[i] + places[j] * ld];
    return g;
  }

  void update_inverse_columns(const SupernodalSymbolic &symbolic, const std::vector<double> &values,
                              const std::uint64_t factor_revision, const std::vector<Index> &asked,
                              KeptInverseColumns &columns)
  {
    const Index m = static_cast<Index>(asked.size()), group = columns.group;
    if (group < 1 || m % group != 0)
      throw Error("update_inverse_columns(): " + std::to_string(m) + " unknowns in groups of " +
                  std::to_string(group));
    if (columns.factor_revision != factor_revision)
      {
        if (columns.outlive_factor_changes && columns.factor_revision != 0)
          {
            columns.factor_revision = factor_revision;
            ++columns.factor_changes_behind;
          }
        else
          {
            KeptInverseColumns anew;
            anew.outlive_factor_changes = columns.outlive_factor_changes;
            anew.group                  = group;
            columns                     = std::move(anew);
          }
      }

    // A group is kept where all of its unknowns sit, in order, at places starting at a
    // multiple of the group; otherwise it is new, and the places it had are freed.
    std::unordered_map<Index, Index> place_of;
    for (std::size_t p = 0; p < columns.rows.size(); ++p)
      if (columns.rows[p] >= 0)
        place_of.emplace(columns.rows[p], static_cast<Index>(p));
    const auto find = [&](const Index unknown) {
      const auto found = place_of.find(unknown);
      return found == place_of.end() ? Index(-1) : found->second;
    };
    std::vector<Index> kept_at(m, -1), fresh; // fresh: indices into asked
    for (Index g = 0; g < m; g += group)
      {
        const Index first = find(asked[g]);
        bool        kept  = first >= 0 && first % group == 0;
        for (Index c = 1; c < group && kept; ++c)
          kept = find(asked[g + c]) == first + c;
        for (Index c = 0; c < group; ++c)
          if (kept)
            kept_at[g + c] = first + c;
          else
            fresh.push_back(g + c);
      }
    columns.kept   = m - static_cast<Index>(fresh.size());
    columns.solved = static_cast<Index>(fresh.size());
    const sparse::CSCMatrix unit = unit_columns(symbolic.n, asked, fresh);
    if (columns.kept == 0)
      {
        // Nothing kept: Y is the solve itself, G its product; in single precision where
        // W is checked anyway.
        PathForwardSolve solved;
        columns.single_precision      = columns.outlive_factor_changes;
        columns.factor_revision       = factor_revision;
        columns.factor_changes_behind = 0;
        if (columns.single_precision)
          columns.gram = compliance_on_paths_in_single_precision(symbolic, values, unit, solved);
        else
          {
            solved       = forward_solve_on_paths(symbolic, values, unit);
            columns.gram = compliance_from_paths(symbolic, solved);
          }
        columns.rows   = asked;
        columns.places = fresh;
        columns.layers.assign(1, std::move(solved));
        columns.layer_positions.assign(1, fresh);
        return;
      }

    // The places no longer asked for are freed, and the columns kept for them dropped.
    std::vector<char> asked_at(columns.rows.size(), 0);
    for (const Index p : kept_at)
      if (p >= 0)
        asked_at[p] = 1;
    for (std::size_t p = 0; p < columns.rows.size(); ++p)
      if (!asked_at[p])
        columns.rows[p] = -1;
    std::size_t stored_columns = 0;
    for (std::size_t l = 0; l < columns.layers.size();)
      {
        bool live = false;
        for (Index &position : columns.layer_positions[l])
          {
            position = position >= 0 && columns.rows[position] >= 0 ? position : -1;
            live     = live || position >= 0;
          }
        if (live)
          stored_columns += columns.layer_positions[l++].size();
        else
          {
            columns.layers.erase(columns.layers.begin() + static_cast<std::ptrdiff_t>(l));
            columns.layer_positions.erase(columns.layer_positions.begin() + static_cast<std::ptrdiff_t>(l));
          }
      }

    // The new groups into free places, lowest first. A set that outgrows the places is
    // laid out anew in the order asked with an eighth more places, for the next to grow
    // into; one that would leave a quarter of them free, without.
    const Index        n_places = static_cast<Index>(columns.rows.size());
    std::vector<Index> free_groups;
    for (Index p = 0; p < n_places; p += group)
      if (columns.rows[p] < 0)
        free_groups.push_back(p);
    const Index n_fresh_groups = static_cast<Index>(fresh.size()) / group;
    const bool  outgrown       = n_fresh_groups > static_cast<Index>(free_groups.size());
    if (outgrown || 4 * (n_places - m) > m)
      {
        const Index spare = outgrown ? group * ((m / group + 7) / 8) : 0;
        lay_out_anew(asked, kept_at, static_cast<std::size_t>(spare), columns);
        for (Index i = 0; i < m; ++i)
          kept_at[i] = i;
      }
    else
      for (Index f = 0; f < n_fresh_groups; ++f)
        for (Index c = 0; c < group; ++c)
          {
            const Index i            = fresh[f * group + c];
            kept_at[i]               = free_groups[f] + c;
            columns.rows[kept_at[i]] = asked[i];
          }
    columns.places = std::move(kept_at);
    if (fresh.empty())
      return;

    std::vector<Index> fresh_places(fresh.size());
    for (std::size_t f = 0; f < fresh.size(); ++f)
      fresh_places[f] = columns.places[fresh[f]];
    PathForwardSolve solved = forward_solve_on_paths(symbolic, values, unit);
    if (columns.single_precision)
      {
        // Kept as the renewal keeps its columns: G's new rows are then checked as the rest.
        solved.single_panels.assign(solved.panels.begin(), solved.panels.end());
        std::vector<double>().swap(solved.panels);
        add_fresh_rows_of_gram<float>(symbolic, fresh_places, solved, columns);
      }
    else
      add_fresh_rows_of_gram<double>(symbolic, fresh_places, solved, columns);
    stored_columns += fresh.size();
    columns.layer_positions.push_back(std::move(fresh_places));
    columns.layers.push_back(std::move(solved));
    // Merged once the dropped columns outnumber the kept ones, or the layers grow many.
    constexpr std::size_t most_layers = 16;
    if (stored_columns > 2 * static_cast<std::size_t>(m) || columns.layers.size() > most_layers)
      {
        if (columns.single_precision)
          merge_layers<float>(symbolic, columns);
        else
          merge_layers<double>(symbolic, columns);
      }
  }

  std::vector<double> compliance_by_full_solves(const SupernodalSymbolic &symbolic,
                                                const std::vector<double> &values, const sparse::CSCMatrix &ht)
  {
    check_constraints(symbolic, values, ht);
    const Index         n = symbolic.n, m = ht.n_cols, ns = symbolic.n_supernodes();
    std::vector<double> y_transposed(static_cast<std::size_t>(m) * n, 0.);
    std::vector<double> x(n), work;
    for (Index i = 0; i < m; ++i)
      {
        std::fill(x.begin(), x.end(), 0.);
        for (Index p = ht.column_start[i]; p < ht.column_start[i + 1]; ++p)
          x[ht.row_index[p]] = ht.values[p];
        // L y = h over every supernode, one right-hand side, with the solver's own kernel
        // for one (the fastest this peer can have).
        for (Index s = 0; s < ns; ++s)
          {
            const Index  nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
            const Index *rows = symbolic.row_index.data() + symbolic.row_start[s];
            forward_supernode_gathered(symbolic, values.data(), s, x.data(), work);
            for (Index q = nc; q < nr; ++q)
              x[rows[q]] += work[q];
          }
        for (Index r = 0; r < n; ++r)
          y_transposed[i + static_cast<std::size_t>(r) * m] = x[r];
      }
    // The dense product over all n rows.
    std::vector<double> w(static_cast<std::size_t>(m) * m, 0.);
    blas::syrk_lower(static_cast<int>(m), static_cast<int>(n), 1., y_transposed.data(), static_cast<int>(m), 0.,
                     w.data(), static_cast<int>(m));
    symmetrize(w, m);
    return w;
  }
} // namespace warpchol::cholesky
