#include <warpchol/base/exceptions.h>
#include <warpchol/cholesky/supernodal_symbolic.h>
#include <warpchol/cholesky/symbolic.h>
#include <warpchol/sparse/conversions.h>

#include <algorithm>
#include <numeric>

namespace warpchol::cholesky
{
  Index SupernodalSymbolic::n_supernodes() const
  {
    return static_cast<Index>(first_column.size()) - 1;
  }

  Index SupernodalSymbolic::n_columns(const Index s) const
  {
    return first_column[s + 1] - first_column[s];
  }

  Index SupernodalSymbolic::n_rows(const Index s) const
  {
    return row_start[s + 1] - row_start[s];
  }

  Index SupernodalSymbolic::update_first_row(const Index k, const Index s, const Index q) const
  {
    const Index begin = update_row_begin[k], end = update_row_end[k];
    if (q == 0)
      return begin;
    return std::lower_bound(row_index.begin() + begin, row_index.begin() + end, first_column[s] + q) -
           row_index.begin();
  }

  namespace
  {
    /** dsyrk of a rows1 x rows1 triangle plus dgemm of rows2 - rows1 rows, inner size width. */
    double update_flops(const Index width, const Index rows1, const Index rows2)
    {
      const double w = static_cast<double>(width), r1 = static_cast<double>(rows1),
                   r2 = static_cast<double>(rows2);
      return w * r1 * (r1 + 1) + 2. * w * r1 * (r2 - r1);
    }
  } // namespace

  double SupernodalSymbolic::flops_from(const Index s, const Index q) const
  {
    const Index nc = n_columns(s), nr = n_rows(s);
    double      flops = 0;
    for (Index k = update_start[s]; k < update_start[s + 1]; ++k)
      {
        const Index d = update_source[k], p1 = update_first_row(k, s, q), p2 = update_row_end[k];
        if (p1 < p2)
          flops += update_flops(n_columns(d), p2 - p1, row_start[d + 1] - p1);
      }
    if (q > 0)
      flops += update_flops(q, nc - q, nr - q);
    const double c = static_cast<double>(nc - q);
    return flops + c * c * c / 3. + static_cast<double>(nr - nc) * c * c; // dpotrf + dtrsm
  }

  Index SupernodalSymbolic::n_stored_values() const
  {
    return value_start.back();
  }

  Index SupernodalSymbolic::nnz_l() const
  {
    return std::accumulate(column_counts.begin(), column_counts.end(), Index(0));
  }

  namespace
  {
    /**
     * Group the fundamental supernodes (chains j -> j+1 where j is the only child of j+1
     * and column j+1 has one entry less than column j) into relaxed supernodes, CHOLMOD's
     * way: from the last one down, merge a supernode into the group of its parent when
     * that group starts right after it and the merged block is small or has few zeros.
     * Returns the first column of each final supernode (and n at the end).
     */
    std::vector<Index> relaxed_supernodes(const std::vector<Index>    &parent,
                                          const std::vector<Index>    &counts,
                                          const SupernodeRelaxation   &relaxation)
    {
      const Index        n = static_cast<Index>(parent.size());
      std::vector<Index> n_children(n, 0);
      for (Index j = 0; j < n; ++j)
        if (parent[j] != -1)
          ++n_children[parent[j]];

      std::vector<Index> fundamental_first;
      for (Index j = 0; j < n; ++j)
        if (!(j > 0 && parent[j - 1] == j && counts[j - 1] == counts[j] + 1 && n_children[j] == 1))
          fundamental_first.push_back(j);
      const Index nf = static_cast<Index>(fundamental_first.size());
      fundamental_first.push_back(n);
      if (!relaxation.enabled)
        return fundamental_first;

      std::vector<Index> fundamental_of(n);
      for (Index f = 0; f < nf; ++f)
        for (Index j = fundamental_first[f]; j < fundamental_first[f + 1]; ++j)
          fundamental_of[j] = f;

      // Per group (indexed by its first fundamental supernode): columns, rows (its own
      // columns included) and explicit zeros of its dense lower-trapezoidal block.
      std::vector<Index>  columns(nf), rows(nf), group_start(nf);
      std::vector<double> zeros(nf, 0.);
      for (Index f = 0; f < nf; ++f)
        {
          columns[f]     = fundamental_first[f + 1] - fundamental_first[f];
          rows[f]        = counts[fundamental_first[f]];
          group_start[f] = f;
        }
      auto group_of = [&](Index f) {
        while (group_start[f] != f)
          f = group_start[f] = group_start[group_start[f]];
        return f;
      };
      for (Index f = nf - 2; f >= 0; --f)
        {
          const Index last_column = fundamental_first[f + 1] - 1;
          if (parent[last_column] == -1 || group_of(fundamental_of[parent[last_column]]) != f + 1)
            continue;
          const Index g = f + 1;
          // The child's rows below its columns lie in the parent group's rows: the merged
          // block has the child's columns on top of the parent group's rows.
          const double merged_columns = static_cast<double>(columns[f] + columns[g]);
          const double merged_rows    = static_cast<double>(columns[f] + rows[g]);
          const double new_zeros      = static_cast<double>(columns[f]) *
                                   static_cast<double>(columns[f] + rows[g] - rows[f]);
          const double total_zeros = zeros[f] + zeros[g] + new_zeros;
          const double total_size  = merged_columns * (merged_columns + 1) / 2 +
                                    merged_columns * (merged_rows - merged_columns);
          const double z = total_zeros / total_size;
          const auto   c = static_cast<Index>(merged_columns);
          const bool merge = new_zeros == 0 || c <= relaxation.nrelax[0] ||
                             (c <= relaxation.nrelax[1] && z < relaxation.zrelax[0]) ||
                             (c <= relaxation.nrelax[2] && z < relaxation.zrelax[1]) ||
                             z < relaxation.zrelax[2];
          if (!merge)
            continue;
          rows[f]        = columns[f] + rows[g];
          columns[f]     = c;
          zeros[f]       = total_zeros;
          group_start[g] = f;
        }
      std::vector<Index> first;
      for (Index f = 0; f < nf; ++f)
        if (group_of(f) == f)
          first.push_back(fundamental_first[f]);
      first.push_back(n);
      return first;
    }

    /** supernode_of, supernode_parent and first_descendant, from first_column and the column tree @p parent. */
    void link_supernodes(SupernodalSymbolic &symbolic, const std::vector<Index> &parent)
    {
      const Index n  = symbolic.n;
      const Index ns = symbolic.n_supernodes();
      symbolic.supernode_of.resize(n);
      for (Index s = 0; s < ns; ++s)
        for (Index j = symbolic.first_column[s]; j < symbolic.first_column[s + 1]; ++j)
          symbolic.supernode_of[j] = s;
      symbolic.supernode_parent.assign(ns, -1);
      symbolic.first_descendant.resize(ns);
      std::iota(symbolic.first_descendant.begin(), symbolic.first_descendant.end(), Index(0));
      for (Index s = 0; s < ns; ++s)
        {
          const Index above = parent[symbolic.first_column[s + 1] - 1];
          if (above != -1)
            {
              const Index p                = symbolic.supernode_of[above];
              symbolic.supernode_parent[s] = p;
              symbolic.first_descendant[p] = std::min(symbolic.first_descendant[p], symbolic.first_descendant[s]);
            }
        }
    }

    /**
     * row_start, row_index and value_start. Row i lies below supernode s iff s is on the
     * supernodal tree path from the supernode of some k < i with C(i,k) != 0 up to (not
     * including) the supernode of i. Rows are visited in increasing order, so each
     * supernode's rows come out sorted.
     */
    void find_row_structure(SupernodalSymbolic &symbolic, const sparse::CSCMatrix &lower)
    {
      const Index             n     = symbolic.n;
      const Index             ns    = symbolic.n_supernodes();
      const sparse::CSCMatrix upper = sparse::upper_triangle(lower);
      auto                    walk_rows = [&](auto &&add_row) {
        std::vector<Index> mark(ns, -1);
        for (Index i = 0; i < n; ++i)
          {
            const Index top = symbolic.supernode_of[i];
            for (Index p = upper.column_start[i]; p < upper.column_start[i + 1]; ++p)
              for (Index s = symbolic.supernode_of[upper.row_index[p]]; s != top && mark[s] != i;
                   s       = symbolic.supernode_parent[s])
                {
                  mark[s] = i;
                  add_row(s, i);
                }
          }
      };
      symbolic.row_start.assign(ns + 1, 0);
      for (Index s = 0; s < ns; ++s)
        symbolic.row_start[s + 1] = symbolic.n_columns(s);
      walk_rows([&](const Index s, Index) { ++symbolic.row_start[s + 1]; });
      std::partial_sum(symbolic.row_start.begin(), symbolic.row_start.end(), symbolic.row_start.begin());
      symbolic.row_index.resize(symbolic.row_start[ns]);
      std::vector<Index> next_row(ns);
      for (Index s = 0; s < ns; ++s)
        {
          next_row[s] = symbolic.row_start[s];
          for (Index j = symbolic.first_column[s]; j < symbolic.first_column[s + 1]; ++j)
            symbolic.row_index[next_row[s]++] = j;
        }
      walk_rows([&](const Index s, const Index i) { symbolic.row_index[next_row[s]++] = i; });

      symbolic.value_start.assign(ns + 1, 0);
      for (Index s = 0; s < ns; ++s)
        symbolic.value_start[s + 1] = symbolic.value_start[s] + symbolic.n_rows(s) * symbolic.n_columns(s);
    }

    /**
     * The updates: the rows of d below its columns, grouped by the supernode they belong to.
     * Listing them by increasing d fixes the order in which updates are summed, so the
     * result does not depend on scheduling.
     */
    void list_updates(SupernodalSymbolic &symbolic)
    {
      const Index ns = symbolic.n_supernodes();
      symbolic.update_start.assign(ns + 1, 0);
      for (int pass = 0; pass < 2; ++pass)
        {
          std::vector<Index> next_update(symbolic.update_start.begin(), symbolic.update_start.end() - 1);
          for (Index d = 0; d < ns; ++d)
            {
              const Index end = symbolic.row_start[d + 1];
              for (Index p = symbolic.row_start[d] + symbolic.n_columns(d); p < end;)
                {
                  const Index s     = symbolic.supernode_of[symbolic.row_index[p]];
                  const Index begin = p;
                  while (p < end && symbolic.row_index[p] < symbolic.first_column[s + 1])
                    ++p;
                  if (pass == 0)
                    ++symbolic.update_start[s + 1];
                  else
                    {
                      const Index k                = next_update[s]++;
                      symbolic.update_source[k]    = d;
                      symbolic.update_row_begin[k] = begin;
                      symbolic.update_row_end[k]   = p;
                    }
                }
            }
          if (pass == 0)
            {
              std::partial_sum(symbolic.update_start.begin(), symbolic.update_start.end(),
                               symbolic.update_start.begin());
              symbolic.update_source.resize(symbolic.update_start[ns]);
              symbolic.update_row_begin.resize(symbolic.update_start[ns]);
              symbolic.update_row_end.resize(symbolic.update_start[ns]);
            }
        }
    }

    /** Flops, counted the way the numeric phase spends them, and the workspace it needs. */
    void count_flops(SupernodalSymbolic &symbolic)
    {
      const Index ns = symbolic.n_supernodes();
      symbolic.supernode_flops.assign(ns, 0.);
      for (Index s = 0; s < ns; ++s)
        {
          symbolic.supernode_flops[s] = symbolic.flops_from(s, 0);
          symbolic.flops += symbolic.supernode_flops[s];
          for (Index k = symbolic.update_start[s]; k < symbolic.update_start[s + 1]; ++k)
            symbolic.max_update_size =
              std::max(symbolic.max_update_size, (symbolic.update_row_end[k] - symbolic.update_row_begin[k]) *
                                                   (symbolic.row_start[symbolic.update_source[k] + 1] -
                                                    symbolic.update_row_begin[k]));
        }
      for (const Index count : symbolic.column_counts)
        symbolic.exact_flops += static_cast<double>(count) * static_cast<double>(count);
    }
  } // namespace

  SupernodalSymbolic analyze_supernodal(const sparse::CSCMatrix   &lower,
                                        const std::vector<Index>  &parent,
                                        const SupernodeRelaxation &relaxation)
  {
    const Index n = lower.n_cols;
    for (Index j = 0; j < n; ++j)
      if (parent[j] != -1 && parent[j] <= j)
        throw Error("supernodal analysis needs a postordered elimination tree");
    SupernodalSymbolic symbolic;
    symbolic.n      = n;
    symbolic.parent = parent;
    std::vector<Index> identity(n);
    std::iota(identity.begin(), identity.end(), Index(0));
    symbolic.column_counts = column_counts(lower, parent, identity);
    symbolic.first_column  = relaxed_supernodes(parent, symbolic.column_counts, relaxation);
    link_supernodes(symbolic, parent);
    find_row_structure(symbolic, lower);
    list_updates(symbolic);
    count_flops(symbolic);
    return symbolic;
  }
} // namespace warpchol::cholesky
