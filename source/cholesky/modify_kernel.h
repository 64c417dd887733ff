#pragma once

/**
 * @file
 * The kernel of the rank-k update and downdate (modify.cc): the reflectors of one chunk of
 * columns of C made and applied on one supernode, compiled once per SIMD target
 * (modify_kernel.cc) and dispatched to the update family's target (simd::Family::update).
 */

#include <warpchol/base/types.h>

namespace warpchol::cholesky
{
  /** The most columns of C a chunk holds on any target (each target's: chunk_columns_here()). */
  constexpr Index chunk_columns = 16;
  /**
   * The most rows a reflector is applied to at a time on any target (one vector of
   * doubles): the zero rows that pad W and the room of the last, partial group of rows.
   */
  constexpr Index lanes = 8;

  /** One chunk of columns of C on one supernode: what the kernel reads and changes. */
  struct SupernodeChunk
  {
    /** The supernode's values of L, column by column (nr rows, nc columns). */
    double *l = nullptr;
    Index   nr = 0, nc = 0;
    /** Its rows of the chunk's columns of W, column by column (ldw >= nr + lanes: zero rows pad the last group). */
    double *w   = nullptr;
    Index   ldw = 0;
    /** The chunk's signs: +1 for an update, -1 for a downdate. */
    const double *sign = nullptr;
    /** Room for the reflectors, (nc (2 chunk_columns + 2) + 1) lanes doubles. */
    double *reflectors = nullptr;
    /** Room for the last, partial group of rows: nc lanes doubles. */
    double *tail = nullptr;
    /** The supernode's first local column that changes. */
    Index q = 0;
    /** A pivot whose square falls to this share of the square it held before the downdates fails (NotPositiveDefinite). */
    double tolerance = 0;
    /** The supernode's first column of the matrix: the column a failure names. */
    Index first_column = 0;
    /** Whether the rows below the diagonal block are split over threads. */
    bool threaded = false;
  };

  /**
   * Make and apply the reflectors of @p n_columns (1 to chunk_columns_here()) columns of C
   * to the supernode of @p chunk (ChunkKernel), on the update family's SIMD target.
   */
  void run_chunk(Index n_columns, const SupernodeChunk &chunk);

  /** The most columns of C a chunk holds on the update family's target. */
  Index chunk_columns_here();
} // namespace warpchol::cholesky
