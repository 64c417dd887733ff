#include <warpchol/base/atomic_file.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/input_file.h>
#include <warpchol/sparse/conversions.h>
#include <warpchol/sparse/matrix_market.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <tuple>
#include <unistd.h>

namespace warpchol::sparse
{
  namespace
  {
    std::string lowercase(std::string text)
    {
      std::transform(text.begin(), text.end(), text.begin(),
                     [](unsigned char c) { return std::tolower(c); });
      return text;
    }

    /** Error prefix "FILE:LINE: ". */
    std::string at(const std::string &name, const long line)
    {
      return name + ":" + std::to_string(line) + ": ";
    }

    /** True if @p line holds nothing but blanks. */
    bool is_blank(const std::string &line)
    {
      return std::all_of(line.begin(), line.end(),
                         [](unsigned char c) { return std::isspace(c) != 0; });
    }

    struct Triplet
    {
      Index  row;
      Index  column;
      double value;
    };

    /** The shortest entry line, "1 1 1" and its newline. */
    constexpr double min_bytes_per_entry = 6;

    /** The bytes left in @p stream from where it stands; -1 if it cannot seek. */
    double bytes_left(std::istream &stream)
    {
      // The size line was the file's last, without a newline: getline stopped at the end,
      // and tellg() would fail on the end-of-file state.
      if (stream.eof())
        return 0;
      const auto here = stream.tellg();
      if (here < 0 || !stream.seekg(0, std::ios::end))
        {
          stream.clear();
          return -1;
        }
      const auto end = stream.tellg();
      stream.seekg(here);
      return end < 0 ? -1 : static_cast<double>(end - here);
    }

    /** The physical memory of the machine in bytes; -1 if unknown. */
    double physical_memory()
    {
      const long pages     = ::sysconf(_SC_PHYS_PAGES);
      const long page_size = ::sysconf(_SC_PAGE_SIZE);
      return pages > 0 && page_size > 0 ? static_cast<double>(pages) * page_size : -1;
    }

    std::string gigabytes(const double bytes)
    {
      return format_number(bytes / 1e9, 3) + " GB";
    }

    /**
     * A header is read before anything is allocated for it: the entries it announces must
     * fit in what is left of the file, and the matrix in the machine's memory, so that a
     * broken or hostile header is one line, not std::bad_alloc or a machine swapping.
     */
    void check_size_line(std::istream &stream, const std::string &where, const Index n_cols,
                         const Index n_entries)
    {
      const double left = bytes_left(stream);
      if (left >= 0 && static_cast<double>(n_entries) > std::floor((left + 1) / min_bytes_per_entry))
        throw InputError(where + "the size line announces " + std::to_string(n_entries) +
                         " entries, but the " + format_number(left, 15) +
                         " bytes after it hold at most " +
                         format_number(std::floor((left + 1) / min_bytes_per_entry), 15) +
                         " (an entry line takes at least 6 bytes)");
      // The triplets, then the CSC matrix: column starts, and a row index and value per entry.
      const double needed = static_cast<double>(n_entries) * (sizeof(Triplet) + sizeof(Index) + sizeof(double)) +
                            (static_cast<double>(n_cols) + 1) * sizeof(Index);
      const double memory = physical_memory();
      if (memory > 0 && needed > memory)
        throw InputError(where + "the size line announces " + std::to_string(n_cols) +
                         " columns and " + std::to_string(n_entries) + " entries: reading them needs " +
                         gigabytes(needed) + ", more than the " + gigabytes(memory) +
                         " of memory of this machine");
    }
  } // namespace

  CSCMatrix read_matrix_market(const std::string &filename)
  {
    std::ifstream stream = open_input_file(filename, "matrix file");
    return read_matrix_market(stream, filename);
  }

  namespace
  {
    /** Where the reader is: the stream, its name in messages, the last line read and its number. */
    struct MatrixMarketReader
    {
      std::istream      &stream;
      const std::string &name;
      std::string        line;
      long               line_number = 0;

      bool next_line()
      {
        if (!std::getline(stream, line))
          return false;
        ++line_number;
        return true;
      }

      bool is_comment_or_blank() const
      {
        return line.empty() || line[0] == '%' || is_blank(line);
      }

      [[noreturn]] void fail(const std::string &why) const
      {
        throw InputError(at(name, line_number) + why);
      }

      /** The banner %%MatrixMarket matrix coordinate FIELD SYMMETRY: whether it says symmetric. */
      bool read_banner()
      {
        if (!next_line())
          throw InputError(at(name, 1) + "empty file, expected a %%MatrixMarket banner");
        std::istringstream banner(line);
        std::string        tag, object, format, field, symmetry;
        banner >> tag >> object >> format >> field >> symmetry;
        if (tag != "%%MatrixMarket")
          fail("expected '%%MatrixMarket' banner, found " + quote(line));
        object   = lowercase(object);
        format   = lowercase(format);
        field    = lowercase(field);
        symmetry = lowercase(symmetry);
        if (object != "matrix")
          fail("object " + quote(object) + " is not supported (only 'matrix')");
        if (format != "coordinate")
          fail("format " + quote(format) + " is not supported (only 'coordinate')");
        if (field != "real" && field != "integer" && field != "double")
          fail("field " + quote(field) + " is not supported (only 'real' or 'integer')");
        if (symmetry != "general" && symmetry != "symmetric")
          fail("symmetry " + quote(symmetry) + " is not supported (only 'general' or 'symmetric')");
        stream.clear();
        return symmetry == "symmetric";
      }

      /** The size line ROWS COLUMNS ENTRIES, after comments and blank lines. */
      void read_size_line(const bool symmetric, Index &n_rows, Index &n_cols, Index &n_entries)
      {
        n_rows = n_cols = n_entries = -1;
        while (next_line())
          {
            if (is_comment_or_blank())
              continue;
            std::istringstream size_line(line);
            std::string        rest;
            if (!(size_line >> n_rows >> n_cols >> n_entries) || (size_line >> rest) || n_rows < 0 || n_cols < 0 ||
                n_entries < 0)
              fail("expected 'ROWS COLUMNS ENTRIES' (three non-negative integers)");
            break;
          }
        if (n_rows < 0)
          fail("missing size line");
        if (symmetric && n_rows != n_cols)
          fail("a symmetric matrix must be square, got " + std::to_string(n_rows) + "x" + std::to_string(n_cols));
        check_size_line(stream, at(name, line_number), n_cols, n_entries);
      }

      /** The @p n_entries entries (0-based; a symmetric matrix's mirrored into the lower triangle), then nothing but comments. */
      std::vector<Triplet> read_entries(const bool symmetric, const Index n_rows, const Index n_cols,
                                        const Index n_entries)
      {
        std::vector<Triplet> triplets;
        triplets.reserve(n_entries);
        while (static_cast<Index>(triplets.size()) < n_entries && next_line())
          {
            if (is_comment_or_blank())
              continue;
            std::istringstream entry(line);
            Index              i = 0, j = 0;
            std::string        value_text, rest;
            if (!(entry >> i >> j >> value_text) || (entry >> rest))
              fail("expected 'ROW COLUMN VALUE', found " + quote(line));
            if (i < 1 || i > n_rows || j < 1 || j > n_cols)
              fail("entry (" + std::to_string(i) + "," + std::to_string(j) + ") outside the " +
                   std::to_string(n_rows) + "x" + std::to_string(n_cols) + " matrix");
            char        *end   = nullptr;
            const double value = std::strtod(value_text.c_str(), &end);
            if (end == value_text.c_str() || *end != '\0')
              fail("value " + quote(value_text) + " is not a number");
            if (!std::isfinite(value))
              fail("value " + quote(value_text) + " is not finite");
            --i;
            --j;
            if (symmetric && i < j)
              std::swap(i, j); // mirror an upper entry into the lower triangle
            triplets.push_back({i, j, value});
          }
        if (static_cast<Index>(triplets.size()) < n_entries)
          fail("file ends after " + std::to_string(triplets.size()) + " of " + std::to_string(n_entries) +
               " entries");
        while (next_line())
          if (!is_comment_or_blank())
            fail("more entries than the " + std::to_string(n_entries) + " announced");
        return triplets;
      }
    };

    /** The CSC matrix of @p triplets, sorted by (column, row), repeated entries summed. */
    CSCMatrix from_triplets(std::vector<Triplet> &triplets, const Index n_rows, const Index n_cols,
                            const Storage storage)
    {
      std::sort(triplets.begin(), triplets.end(), [](const Triplet &a, const Triplet &b) {
        return std::tie(a.column, a.row) < std::tie(b.column, b.row);
      });
      CSCMatrix matrix = CSCMatrix::zero(n_rows, n_cols, storage);
      for (std::size_t t = 0; t < triplets.size(); ++t)
        {
          const Triplet &entry = triplets[t];
          if (t > 0 && entry.column == triplets[t - 1].column && entry.row == triplets[t - 1].row)
            {
              matrix.values.back() += entry.value;
              continue;
            }
          matrix.row_index.push_back(entry.row);
          matrix.values.push_back(entry.value);
          ++matrix.column_start[entry.column + 1];
        }
      for (Index j = 0; j < n_cols; ++j)
        matrix.column_start[j + 1] += matrix.column_start[j];
      return matrix;
    }
  } // namespace

  CSCMatrix read_matrix_market(std::istream &stream, const std::string &name)
  {
    MatrixMarketReader reader{stream, name, {}, 0};
    const bool         symmetric = reader.read_banner();
    Index              n_rows, n_cols, n_entries;
    reader.read_size_line(symmetric, n_rows, n_cols, n_entries);
    std::vector<Triplet> triplets = reader.read_entries(symmetric, n_rows, n_cols, n_entries);
    return from_triplets(triplets, n_rows, n_cols, symmetric ? Storage::lower : Storage::full);
  }

  CSCMatrix read_symmetric_matrix_market(const std::string &filename)
  {
    CSCMatrix         matrix = read_matrix_market(filename);
    const std::string size   = std::to_string(matrix.n_rows) + "x" + std::to_string(matrix.n_cols);
    if (matrix.n_rows == 0 || matrix.n_cols == 0)
      throw InputError(filename + ": the matrix is empty (" + size + "): nothing to factor");
    if (matrix.n_rows != matrix.n_cols)
      throw InputError(filename + ": a matrix to factor must be square, got " + size);
    if (matrix.storage == Storage::lower)
      return matrix;

    // A "general" file: every entry (i,j) needs its twin (j,i), of the same value. Column j
    // of the transpose lists row j of A: both are sorted, and walked side by side.
    const CSCMatrix transposed = transpose(matrix);
    const auto      entry      = [](const Index i, const Index j) {
      return "(" + std::to_string(i + 1) + "," + std::to_string(j + 1) + ")";
    };
    const auto not_symmetric = [&](const std::string &what) {
      return InputError(filename + ": " + what + ": a matrix to factor must be symmetric");
    };
    for (Index j = 0; j < matrix.n_cols; ++j)
      {
        Index       k = matrix.column_start[j], t = transposed.column_start[j];
        const Index k_end = matrix.column_start[j + 1], t_end = transposed.column_start[j + 1];
        while (k < k_end || t < t_end)
          {
            const Index i = k < k_end ? matrix.row_index[k] : matrix.n_rows;
            const Index i_twin = t < t_end ? transposed.row_index[t] : matrix.n_rows;
            if (i < i_twin)
              throw not_symmetric("entry " + entry(i, j) + " is stored but " + entry(j, i) + " is not");
            if (i_twin < i)
              throw not_symmetric("entry " + entry(j, i_twin) + " is stored but " + entry(i_twin, j) + " is not");
            if (!symmetric_pair(matrix.values[k], transposed.values[t], matrix(i, i), matrix(j, j)))
              throw not_symmetric("A" + entry(i, j) + " = " + format_number(matrix.values[k]) + " but A" +
                                  entry(j, i) + " = " + format_number(transposed.values[t]));
            ++k;
            ++t;
          }
      }
    return matrix;
  }

  void write_matrix_market(const CSCMatrix &matrix, const std::string &filename)
  {
    write_file_atomically(filename, [&](std::ostream &out) {
      out << "%%MatrixMarket matrix coordinate real "
          << (matrix.storage == Storage::lower ? "symmetric" : "general") << "\n"
          << matrix.n_rows << ' ' << matrix.n_cols << ' ' << matrix.n_nonzeros() << "\n";
      char buffer[64];
      for (Index j = 0; j < matrix.n_cols; ++j)
        for (Index k = matrix.column_start[j]; k < matrix.column_start[j + 1]; ++k)
          {
            std::snprintf(buffer, sizeof(buffer), "%.17g", matrix.values[k]);
            out << matrix.row_index[k] + 1 << ' ' << j + 1 << ' ' << buffer << '\n';
          }
    });
  }
} // namespace warpchol::sparse
