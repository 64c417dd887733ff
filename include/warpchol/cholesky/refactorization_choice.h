#pragma once

#include <warpchol/base/binary_io.h>
#include <warpchol/base/named_values.h>

#include <array>
#include <string>

/**
 * @file
 * The choice, per change of A, between updating the factor and recomputing its columns
 * (SparseCholesky::refactorize()): what each costs, predicted from flops and rates
 * calibrated on what was measured.
 */
namespace warpchol::cholesky
{
  /** How a refactorize() brought the factor up to date. */
  enum class RefactorizationMethod
  {
    /** Nothing to do, or the changes were only loaded (Refresh::none). */
    none,
    /** An update and downdate of the factor by the change in low-rank form (cholesky/modify). */
    update,
    /** Partial refactorization: the columns on the changes' elimination-tree paths recomputed. */
    partial,
    /** Every column computed anew. */
    full
  };

  /** "none", "update", "partial", "full". */
  std::string to_string(RefactorizationMethod method);

  /** What refactorize() may choose from (SparseCholesky::Settings::change_method). */
  enum class ChangeMethod
  {
    /** The cheapest by predicted seconds, its rates calibrated on measured times. */
    automatic,
    /**
     * The cheapest by predicted seconds at fixed rates (no measurement): the same choice
     * whatever the machine's load, so the same bits from run to run.
     */
    by_flops,
    /** Never update: recompute the columns (partial refactorization). */
    recompute,
    /** Update whenever the change allows it (supernodal method, an exact factor). */
    update
  };

  /** The names of the ways (base/named_values.h): "auto", "flops", "recompute", "update". */
  inline constexpr NameTable<ChangeMethod, 4> change_method_names{{{ChangeMethod::automatic, "auto"},
                                                                   {ChangeMethod::by_flops, "flops"},
                                                                   {ChangeMethod::recompute, "recompute"},
                                                                   {ChangeMethod::update, "update"}}};

  /** "auto", "flops", "recompute", "update". */
  std::string to_string(ChangeMethod method);
  /** The inverse of to_string(); throws InputError naming the valid ones. */
  ChangeMethod parse_change_method(const std::string &name);

  /**
   * Seconds of each method: flops / rate, with a rate per method. An update's rate also
   * depends on its rank k: it reads and writes each entry of L on its paths once for 4k
   * flops, so at low rank it streams L from memory, and only past a few columns does it
   * reach its kernels' flop rate. Its rate is modelled as r k / (k + update_half_rank),
   * and r is what is learned.
   *
   * Until a method was measured its rate is the factorization's (the first one measured,
   * the set-up's) times a prior: 1 for a recomputation; for an update, what its kernels
   * reach on the update's SIMD target against a factorization (simd::Family::update: with
   * 32 vector registers of 8 doubles they carry 16 columns of C per entry of L and keep
   * pace with it; narrower targets carry fewer). Measured rates follow the run as
   * exponential moving averages. With fixed_rates (ChangeMethod::by_flops) nothing is ever
   * measured: the predictions are fixed multiples of the flops, the update's half a
   * factorization's rate at any rank and on any target, so that the choice is the same on
   * every machine.
   *
   * The one learner of the solver's rates: SparseCholesky feeds it every factorization,
   * refactorization and update it times (SparseCholesky::cost_model()), and a caller that
   * foresees what a factorization costs (WCC's StepCostModel) reads it there rather than
   * timing the same factorizations again, as a CHOLMOD user reads cholmod_common's
   * statistics instead of keeping a second count.
   */
  class RefactorizationCostModel
  {
  public:
    explicit RefactorizationCostModel(bool fixed_rates = false);

    /**
     * The predicted seconds of @p method spending @p flops; @p rank: an update's columns of
     * C (ignored for the other methods).
     */
    double predicted_seconds(RefactorizationMethod method, double flops, unsigned int rank = 1) const;

    /** @p method spent @p flops in @p seconds (@p rank as in predicted_seconds()). */
    void record(RefactorizationMethod method, double flops, double seconds, unsigned int rank = 1);

    /**
     * Whether the rate of a factorization (full or partial) is known: measured, or fixed
     * (fixed_rates). Before that, predicted_seconds() reads the default rate, a guess.
     */
    bool knows_factorization_rate() const;

    void save(BinaryWriter &writer) const;
    void load(BinaryReader &reader);

  private:
    /** A factorization's flop rate before any was measured. */
    static constexpr double default_rate = 2e10;
    /** With fixed rates, the update's rate against a factorization's, whatever the target and rank. */
    static constexpr double fixed_update_rate_ratio = 0.5;
    /** The rank at which an update reaches half its kernels' rate. */
    static constexpr double update_half_rank = 2.5;
    /**
     * Work below this many flops is not timed: its fixed costs (calls, allocation, loading
     * the values) would make the rate look lower than large factorizations reach. Per
     * method, partial refactorizations (mostly small) do not pull down the full one's rate.
     */
    static constexpr double least_timed_flops = 1e5;
    /** The share of an update's rate at @p rank of its kernels' rate. */
    static double rank_efficiency(unsigned int rank);
    /** An update's kernels' rate before one was measured, against a factorization's. */
    static double update_rate_prior();
    /** The share of @p method's rate it reaches at @p rank: rank_efficiency() for an update, unless the rates are fixed. */
    double efficiency(RefactorizationMethod method, unsigned int rank) const;
    bool                  fixed_rates;
    /** Flops per second of update (its kernels' rate r; set by the constructor), partial, full; whether each was measured. */
    std::array<double, 3> rates    = {{0., default_rate, default_rate}};
    std::array<bool, 3>   measured = {{false, false, false}};
  };
} // namespace warpchol::cholesky
