#pragma once

#include <warpchol/sparse/csc_matrix.h>

#include <istream>
#include <string>

/**
 * @file
 * Matrix Market coordinate files (https://math.nist.gov/MatrixMarket/formats.html).
 */
namespace warpchol::sparse
{
  /**
   * Read a real or integer coordinate Matrix Market file. A "symmetric" file gives a
   * matrix with lower storage (entries given above the diagonal are mirrored into the
   * lower triangle), a "general" one full storage. Repeated entries are summed.
   * Throws InputError "FILE:LINE: what is wrong" on a malformed file.
   */
  CSCMatrix read_matrix_market(const std::string &filename);

  /** The same from a stream; @p name stands for the file in error messages. */
  CSCMatrix read_matrix_market(std::istream &stream, const std::string &name);

  /**
   * Read the Matrix Market file of a matrix to factor (the solver's benchmarks): as
   * read_matrix_market(), and an empty matrix, a non-square one and a "general" one whose
   * pattern or values are not symmetric (symmetric_pair()) are refused with InputError
   * naming the file and the entry as the file numbers it, from 1.
   */
  CSCMatrix read_symmetric_matrix_market(const std::string &filename);

  /**
   * Write @p matrix as a real coordinate Matrix Market file, "symmetric" for lower
   * storage and "general" otherwise, with 17 significant digits (values round-trip).
   * The file is written under a temporary name and renamed into place.
   */
  void write_matrix_market(const CSCMatrix &matrix, const std::string &filename);
} // namespace warpchol::sparse
