#include <warpchol/base/exceptions.h>
#include <warpchol/cholesky/symbolic.h>
#include <warpchol/sparse/conversions.h>

#include <algorithm>

namespace warpchol::cholesky
{
  Index SymbolicFactorization::nnz_l() const
  {
    return column_start.empty() ? 0 : column_start.back();
  }

  std::vector<Index> elimination_tree(const sparse::CSCMatrix &lower)
  {
    // Liu's algorithm needs the entries of row k left of the diagonal: the upper triangle
    // by columns, i.e. the transpose of the lower triangle.
    const Index              n = lower.n_cols;
    const sparse::CSCMatrix upper = sparse::upper_triangle(lower);
    std::vector<Index> parent(n, -1), ancestor(n, -1);
    for (Index k = 0; k < n; ++k)
      for (Index p = upper.column_start[k]; p < upper.column_start[k + 1]; ++p)
        {
          // Climb from i to the root of its current subtree, compressing the path to k.
          for (Index i = upper.row_index[p]; i != -1 && i < k;)
            {
              const Index next = ancestor[i];
              ancestor[i]      = k;
              if (next == -1)
                parent[i] = k;
              i = next;
            }
        }
    return parent;
  }

  std::vector<Index> postorder_tree(const std::vector<Index> &parent)
  {
    const Index n = static_cast<Index>(parent.size());
    // Children lists, built in reverse so that each list comes out increasing.
    std::vector<Index> first_child(n, -1), next_sibling(n, -1);
    for (Index j = n - 1; j >= 0; --j)
      if (parent[j] != -1)
        {
          next_sibling[j]        = first_child[parent[j]];
          first_child[parent[j]] = j;
        }
    std::vector<Index> order;
    order.reserve(n);
    std::vector<Index> stack;
    for (Index root = 0; root < n; ++root)
      {
        if (parent[root] != -1)
          continue;
        // Depth-first: a node is emitted after all its children.
        stack.push_back(root);
        while (!stack.empty())
          {
            const Index node  = stack.back();
            const Index child = first_child[node];
            if (child == -1)
              {
                stack.pop_back();
                order.push_back(node);
              }
            else
              {
                first_child[node] = next_sibling[child]; // consume the child
                stack.push_back(child);
              }
          }
      }
    return order;
  }

  std::vector<Index> column_counts(const sparse::CSCMatrix &lower, const std::vector<Index> &parent,
                                   const std::vector<Index> &postorder)
  {
    const Index n = lower.n_cols;
    // count[j] starts as delta[j], the correction at j; summing deltas up the tree gives
    // the number of row subtrees that contain j, i.e. the entries of column j of L.
    std::vector<Index> count(n), first(n, -1), max_first(n, -1), previous_leaf(n, -1), ancestor(n);
    // first[j]: postorder index of the first descendant of j; leaves start with delta 1.
    for (Index k = 0; k < n; ++k)
      {
        Index j  = postorder[k];
        count[j] = first[j] == -1 ? 1 : 0;
        for (; j != -1 && first[j] == -1; j = parent[j])
          first[j] = k;
      }
    for (Index i = 0; i < n; ++i)
      ancestor[i] = i;
    for (Index k = 0; k < n; ++k)
      {
        const Index j = postorder[k];
        if (parent[j] != -1)
          --count[parent[j]]; // j is not a root
        // Each A(i,j) with i > j: is j a leaf of the row subtree of i?
        for (Index p = lower.column_start[j]; p < lower.column_start[j + 1]; ++p)
          {
            const Index i = lower.row_index[p];
            if (i <= j || first[j] <= max_first[i])
              continue; // j is not a (new) leaf of row subtree i
            max_first[i]              = first[j];
            const Index previous      = previous_leaf[i];
            previous_leaf[i]          = j;
            ++count[j]; // A(i,j) belongs to the skeleton matrix
            if (previous == -1)
              continue; // first leaf of row subtree i
            // Subsequent leaf: the overlap starts at the least common ancestor q of
            // previous and j, found by union-find with path compression.
            Index q = previous;
            while (q != ancestor[q])
              q = ancestor[q];
            for (Index s = previous; s != q;)
              {
                const Index next = ancestor[s];
                ancestor[s]      = q;
                s                = next;
              }
            --count[q];
          }
        if (parent[j] != -1)
          ancestor[j] = parent[j];
      }
    // Sum the deltas up the tree (parents come after their children).
    for (Index j = 0; j < n; ++j)
      if (parent[j] != -1)
        count[parent[j]] += count[j];
    return count;
  }

  SymbolicFactorization analyze_left_looking(const sparse::CSCMatrix &lower)
  {
    if (lower.storage != sparse::Storage::lower || lower.n_rows != lower.n_cols)
      throw MatrixError("symbolic analysis needs a square matrix with lower storage");
    const Index           n = lower.n_cols;
    SymbolicFactorization symbolic;
    symbolic.n = n;
    symbolic.parent.assign(n, -1);
    symbolic.column_counts.assign(n, 1);

    // The upper part of column k of C is row k of its lower triangle.
    const sparse::CSCMatrix upper = sparse::upper_triangle(lower);

    // 1. Row structure and parents. Walking from each i with C(i,k) != 0 (i < k) up the
    //    tree built so far visits exactly the columns of row k of L; a node without a
    //    parent yet gets k as its parent. mark[] stops the walk at nodes already listed.
    std::vector<Index> mark(n, -1);
    symbolic.row_start.assign(n + 1, 0);
    for (Index k = 0; k < n; ++k)
      {
        mark[k]                = k;
        const Index row_begin = static_cast<Index>(symbolic.row_column.size());
        for (Index p = upper.column_start[k]; p < upper.column_start[k + 1]; ++p)
          for (Index i = upper.row_index[p]; i < k && mark[i] != k; i = symbolic.parent[i])
            {
              symbolic.row_column.push_back(i);
              mark[i] = k;
              ++symbolic.column_counts[i];
              if (symbolic.parent[i] == -1)
                symbolic.parent[i] = k;
            }
        std::sort(symbolic.row_column.begin() + row_begin, symbolic.row_column.end());
        symbolic.row_start[k + 1] = static_cast<Index>(symbolic.row_column.size());
      }

    // 2. Column structure: column k of L is the lower part of column k of C merged with
    //    the columns of the children of k (their rows below k).
    symbolic.column_start.assign(n + 1, 0);
    for (Index j = 0; j < n; ++j)
      symbolic.column_start[j + 1] = symbolic.column_start[j] + symbolic.column_counts[j];
    symbolic.row_index.resize(symbolic.column_start[n]);
    std::vector<Index> first_child(n, -1), next_sibling(n, -1);
    for (Index j = n - 1; j >= 0; --j)
      if (symbolic.parent[j] != -1)
        {
          next_sibling[j]                 = first_child[symbolic.parent[j]];
          first_child[symbolic.parent[j]] = j;
        }
    std::fill(mark.begin(), mark.end(), -1);
    for (Index k = 0; k < n; ++k)
      {
        Index *const column = symbolic.row_index.data() + symbolic.column_start[k];
        Index        length = 0;
        column[length++]    = k;
        mark[k]             = k;
        for (Index p = lower.column_start[k]; p < lower.column_start[k + 1]; ++p)
          if (const Index i = lower.row_index[p]; mark[i] != k)
            {
              mark[i]          = k;
              column[length++] = i;
            }
        for (Index child = first_child[k]; child != -1; child = next_sibling[child])
          for (Index p = symbolic.column_start[child] + 1; p < symbolic.column_start[child + 1];
               ++p)
            if (const Index i = symbolic.row_index[p]; mark[i] != k)
              {
                mark[i]          = k;
                column[length++] = i;
              }
        if (length != symbolic.column_counts[k])
          throw Error("symbolic analysis: row and column structures disagree on column " +
                      std::to_string(k));
        std::sort(column + 1, column + length);
      }

    // 3. Position of each row-structure entry L(i,j) in the column storage: columns are
    //    sorted, so scanning rows in increasing order meets the entries of column j in
    //    storage order.
    symbolic.row_entry.resize(symbolic.row_column.size());
    std::vector<Index> next_in_column(symbolic.column_start.begin(), symbolic.column_start.end() - 1);
    for (Index i = 0; i < n; ++i)
      for (Index p = symbolic.row_start[i]; p < symbolic.row_start[i + 1]; ++p)
        symbolic.row_entry[p] = ++next_in_column[symbolic.row_column[p]];

    symbolic.postorder = postorder_tree(symbolic.parent);
    symbolic.flops     = 0;
    for (const Index count : symbolic.column_counts)
      symbolic.flops += static_cast<double>(count) * static_cast<double>(count);
    return symbolic;
  }
} // namespace warpchol::cholesky
