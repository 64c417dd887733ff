#include <warpchol/cholesky/statistics_fields.h>

namespace warpchol::cholesky
{
  namespace
  {
    using Statistics = SparseCholesky::Statistics;

    bool always(const Statistics &)
    {
      return true;
    }

    /** Whether the last refactorize() weighed an update against recomputing. */
    bool weighed(const Statistics &statistics)
    {
      return statistics.predicted_update_seconds >= 0;
    }
  } // namespace

  const std::vector<StatisticsField> &statistics_fields()
  {
    // Each a line: name, log column, meaning, value, whether set. Integers widened to long
    // long and flags kept as bool, so that Python sees int and bool.
    static const std::vector<StatisticsField> fields{
      {"n", nullptr, "rows and columns of A",
       [](const Statistics &s) -> StatisticValue { return static_cast<long long>(s.n); }, always},
      {"nnz_a", nullptr, "stored entries of A's lower triangle",
       [](const Statistics &s) -> StatisticValue { return static_cast<long long>(s.nnz_a); }, always},
      {"nnz_l", nullptr, "entries of L, diagonal included",
       [](const Statistics &s) -> StatisticValue { return static_cast<long long>(s.nnz_l); }, always},
      {"fill", nullptr, "nnz_l / nnz_a", [](const Statistics &s) -> StatisticValue { return s.fill(); }, always},
      {"flops", nullptr, "flops of a full factorization by the chosen method (supernodes' padding included)",
       [](const Statistics &s) -> StatisticValue { return s.flops; }, always},
      {"exact_flops", nullptr, "flops of a factorization without padding (CHOLMOD's count)",
       [](const Statistics &s) -> StatisticValue { return s.exact_flops; }, always},
      {"n_supernodes", nullptr, "supernodes (supernodal method; 0 otherwise)",
       [](const Statistics &s) -> StatisticValue { return static_cast<long long>(s.n_supernodes); }, always},
      {"columns_recomputed", nullptr, "columns of L the last call computed",
       [](const Statistics &s) -> StatisticValue { return static_cast<long long>(s.columns_recomputed); }, always},
      {"supernodes_recomputed", nullptr, "supernodes the last call computed, wholly or in part",
       [](const Statistics &s) -> StatisticValue { return static_cast<long long>(s.supernodes_recomputed); },
       always},
      {"flops_recomputed", nullptr, "flops the last call spent",
       [](const Statistics &s) -> StatisticValue { return s.flops_recomputed; }, always},
      {"n_factorizations", nullptr, "factorize() calls and full factorizations",
       [](const Statistics &s) -> StatisticValue { return static_cast<long long>(s.n_factorizations); }, always},
      {"n_refactorizations", nullptr, "refactorize() calls",
       [](const Statistics &s) -> StatisticValue { return static_cast<long long>(s.n_refactorizations); }, always},
      {"factor_bytes", nullptr, "bytes the numeric factor takes once factorized",
       [](const Statistics &s) -> StatisticValue { return static_cast<long long>(s.factor_bytes); }, always},
      {"method", "factor_method", "how the last call brought the factor up to date: none, update, partial or full",
       [](const Statistics &s) -> StatisticValue { return to_string(s.method); }, always},
      {"update_rank", "update_rank", "the rank of the change the last refactorize() weighed as an update",
       [](const Statistics &s) -> StatisticValue { return static_cast<long long>(s.update_rank); }, weighed},
      {"update_flops", nullptr, "the flops of that update (-1: none weighed)",
       [](const Statistics &s) -> StatisticValue { return s.update_flops; }, weighed},
      {"partial_flops", nullptr, "the flops of the partial refactorization it was weighed against (-1: none)",
       [](const Statistics &s) -> StatisticValue { return s.partial_flops; }, weighed},
      {"predicted_update_seconds", "t_predicted_update", "the predicted seconds of that update (-1: none weighed)",
       [](const Statistics &s) -> StatisticValue { return s.predicted_update_seconds; }, weighed},
      {"predicted_partial_seconds", "t_predicted_partial",
       "the predicted seconds of the partial refactorization (-1: none weighed)",
       [](const Statistics &s) -> StatisticValue { return s.predicted_partial_seconds; }, weighed},
      {"predicted_full_seconds", "t_predicted_full", "the predicted seconds of a full factorization (-1: none weighed)",
       [](const Statistics &s) -> StatisticValue { return s.predicted_full_seconds; }, weighed},
      {"update_fell_back", nullptr, "whether a downdate's pivot stopped the last update (it recomputed instead)",
       [](const Statistics &s) -> StatisticValue { return s.update_fell_back; }, always},
      {"n_updates", nullptr, "updates and downdates done",
       [](const Statistics &s) -> StatisticValue { return static_cast<long long>(s.n_updates); }, always}};
    return fields;
  }
} // namespace warpchol::cholesky
