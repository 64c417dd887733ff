/**
 * @file
 * read_legacy_vtk(): our own parser of legacy VTK unstructured grids (ASCII and BINARY,
 * cell lists of versions before 5 and the OFFSETS/CONNECTIVITY arrays of version 5.1).
 * VTK's vtkUnstructuredGridReader crashed on malformed files (fuzz_vtk); this parser
 * checks every count against the bytes left in the file before it allocates, and every
 * point id against the points read, and reports any problem as one line naming the file
 * and the line (ASCII) or the section (BINARY).
 */

#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/input_file.h>
#include <warpchol/mesh/mesh_readers.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string_view>

namespace warpchol::fem
{
  namespace
  {
    constexpr long long vtk_tetra = 10;

    /** VTK cell types of dimension < 3, skipped like Gmsh's lines and triangles. */
    bool is_lower_dimensional(const long long type)
    {
      switch (type)
        {
          case 1:  // VTK_VERTEX
          case 2:  // VTK_POLY_VERTEX
          case 3:  // VTK_LINE
          case 4:  // VTK_POLY_LINE
          case 5:  // VTK_TRIANGLE
          case 6:  // VTK_TRIANGLE_STRIP
          case 7:  // VTK_POLYGON
          case 8:  // VTK_PIXEL
          case 9:  // VTK_QUAD
          case 21: // VTK_QUADRATIC_EDGE
          case 22: // VTK_QUADRATIC_TRIANGLE
          case 23: // VTK_QUADRATIC_QUAD
            return true;
          default:
            return false;
        }
    }

    std::string upper(std::string_view text)
    {
      std::string result(text);
      std::transform(result.begin(), result.end(), result.begin(),
                     [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
      return result;
    }

    bool is_space(const char c)
    {
      return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
    }

    /** The first word of @p text (empty if it holds none). */
    std::string_view first_word(std::string_view text)
    {
      std::size_t begin = 0;
      while (begin < text.size() && is_space(text[begin]))
        ++begin;
      std::size_t end = begin;
      while (end < text.size() && !is_space(text[end]))
        ++end;
      return text.substr(begin, end - begin);
    }

    /** The type of a data array as the legacy format names it ("float", "vtktypeint64"). */
    struct ValueType
    {
      enum Kind
      {
        signed_integer,
        unsigned_integer,
        floating,
        bit,
        string
      };
      Kind        kind  = floating;
      std::size_t bytes = 0; ///< in BINARY files (bits: packed, 8 a byte)
    };

    bool value_type(std::string_view name, ValueType &type)
    {
      using K = ValueType::Kind;
      struct Entry
      {
        const char *name;
        K           kind;
        std::size_t bytes;
      };
      static const Entry table[] = {
        {"bit", K::bit, 1},
        {"char", K::signed_integer, 1},
        {"signed_char", K::signed_integer, 1},
        {"unsigned_char", K::unsigned_integer, 1},
        {"short", K::signed_integer, 2},
        {"unsigned_short", K::unsigned_integer, 2},
        {"int", K::signed_integer, 4},
        {"unsigned_int", K::unsigned_integer, 4},
        {"long", K::signed_integer, 8},
        {"unsigned_long", K::unsigned_integer, 8},
        {"long_long", K::signed_integer, 8},
        {"unsigned_long_long", K::unsigned_integer, 8},
        {"vtkidtype", K::signed_integer, 4}, // written as 32-bit ints before version 5
        {"vtktypeint8", K::signed_integer, 1},
        {"vtktypeuint8", K::unsigned_integer, 1},
        {"vtktypeint16", K::signed_integer, 2},
        {"vtktypeuint16", K::unsigned_integer, 2},
        {"vtktypeint32", K::signed_integer, 4},
        {"vtktypeuint32", K::unsigned_integer, 4},
        {"vtktypeint64", K::signed_integer, 8},
        {"vtktypeuint64", K::unsigned_integer, 8},
        {"float", K::floating, 4},
        {"double", K::floating, 8},
        {"vtktypefloat32", K::floating, 4},
        {"vtktypefloat64", K::floating, 8},
        {"string", K::string, 0},
        {"utf8_string", K::string, 0},
      };
      std::string lower(name);
      std::transform(lower.begin(), lower.end(), lower.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      for (const Entry &entry : table)
        if (lower == entry.name)
          {
            type.kind  = entry.kind;
            type.bytes = entry.bytes;
            return true;
          }
      return false;
    }

    /** A big-endian value of @p bytes bytes (at most 8). */
    std::uint64_t load_big_endian(const char *at, const std::size_t bytes)
    {
      std::uint64_t value = 0;
      for (std::size_t b = 0; b < bytes; ++b)
        value = (value << 8) | static_cast<unsigned char>(at[b]);
      return value;
    }

    std::int64_t sign_extend(std::uint64_t bits, const std::size_t bytes)
    {
      if (bytes < 8 && ((bits >> (8 * bytes - 1)) & 1) != 0)
        bits |= ~std::uint64_t(0) << (8 * bytes);
      return static_cast<std::int64_t>(bits);
    }

    /** Cells as offsets into a connectivity list (the version 5 layout; older files too). */
    struct Cells
    {
      std::vector<long long> offsets; ///< n_cells + 1 entries, from 0
      std::vector<long long> connectivity;
    };

    class Parser
    {
    public:
      Parser(const std::string &filename, std::string data)
        : filename(filename)
        , data(std::move(data))
      {}

      TetrahedralMesh parse();

    private:
      const std::string &filename;
      const std::string  data;
      std::size_t        position    = 0;
      std::size_t        token_start = 0;
      bool               binary      = false;
      int                version     = 0;
      std::string        section     = "header";
      bool               past_binary_data = false; ///< line numbers mean nothing after

      /**
       * "FILE:LINE" in an ASCII file; in a BINARY one, whose line numbers mean nothing past
       * its first data, "FILE" (the messages name the section) or "FILE: byte N" between
       * sections.
       */
      std::string where() const
      {
        const std::size_t at = std::min(token_start, data.size());
        if (binary && past_binary_data)
          return section == "header" ? filename + ": byte " + std::to_string(at) : filename;
        return filename + ":" + std::to_string(1 + std::count(data.begin(), data.begin() + at, '\n'));
      }

      [[noreturn]] void fail(const std::string &message) const
      {
        throw InputError(where() + ": " + message);
      }

      std::size_t bytes_left() const
      {
        return data.size() - position;
      }

      void skip_space()
      {
        while (position < data.size() && is_space(data[position]))
          ++position;
      }

      /** The next word (empty at the end of the file). */
      std::string_view next_token()
      {
        skip_space();
        token_start = position;
        while (position < data.size() && !is_space(data[position]))
          ++position;
        return std::string_view(data).substr(token_start, position - token_start);
      }

      std::string_view peek_token()
      {
        const std::size_t saved = position, saved_start = token_start;
        const auto        token = next_token();
        position                = saved;
        token_start             = saved_start;
        return token;
      }

      /** The rest of the current line, without its end; the position after its newline. */
      std::string_view rest_of_line()
      {
        token_start       = position;
        std::size_t end   = data.find('\n', position);
        if (end == std::string::npos)
          end = data.size();
        std::string_view line = std::string_view(data).substr(position, end - position);
        position              = std::min(end + 1, data.size());
        if (!line.empty() && line.back() == '\r')
          line.remove_suffix(1);
        return line;
      }

      /**
       * The end of a keyword line: in a BINARY file, its data start right after the
       * newline, so nothing but blanks may come before it.
       */
      void end_keyword_line()
      {
        while (position < data.size() && (data[position] == ' ' || data[position] == '\t' || data[position] == '\r'))
          ++position;
        if (position < data.size() && data[position] == '\n')
          ++position;
        else if (binary && position < data.size())
          {
            token_start = position;
            fail("expected the end of the " + section + " line, found " +
                 quote(std::string_view(data).substr(position, 40)));
          }
        past_binary_data = past_binary_data || (binary && section != "header");
      }

      /** The next word as a count (a non-negative integer); @p what names it. */
      unsigned long long count(const std::string &what)
      {
        const auto token = next_token();
        if (token.empty())
          fail(section + ": the file ends before its " + what);
        unsigned long long value = 0;
        const auto [end, error]  = std::from_chars(token.data(), token.data() + token.size(), value);
        if (error != std::errc() || end != token.data() + token.size())
          fail(section + ": " + what + " " + quote(token) + " is not a non-negative integer");
        return value;
      }

      ValueType type_of(const std::string &what)
      {
        const auto token = next_token();
        ValueType  type;
        if (token.empty())
          fail(section + ": the file ends before the type of its " + what);
        if (!value_type(token, type))
          fail(section + ": unknown data type " + quote(token) + " of its " + what);
        return type;
      }

      /**
       * Refuse @p n values of @p type (the @p what of the current section) that cannot fit
       * in what is left of the file: before anything is allocated for them.
       */
      void check_fits(const unsigned long long n, const ValueType &type, const std::string &what)
      {
        const std::size_t left = bytes_left();
        bool              fits;
        if (!binary)
          fits = n <= left / 2 + 1; // a character and a separator each
        else if (type.kind == ValueType::bit)
          fits = n / 8 + (n % 8 != 0) <= left;
        else if (type.kind == ValueType::string)
          fits = n <= left; // a NUL or a newline each, at least
        else
          fits = n <= left / type.bytes;
        if (!fits)
          fail(section + ": " + std::to_string(n) + " " + what + " cannot fit in the " + std::to_string(left) +
               " bytes left in the file");
      }

      [[noreturn]] void fail_truncated(const unsigned long long read, const unsigned long long n,
                                       const std::string &what)
      {
        // The line of the last word read, not the end of the file after it.
        while (token_start > 0 && is_space(data[token_start - 1]))
          --token_start;
        fail(section + ": the file ends after " + std::to_string(read) + " of the " + std::to_string(n) + " " + what);
      }

      /** @p n values of @p type, as numbers (the types of POINTS). */
      std::vector<double> read_reals(const unsigned long long n, const ValueType &type, const std::string &what)
      {
        if (type.kind == ValueType::bit || type.kind == ValueType::string)
          fail(section + ": its " + what + " must be numbers");
        check_fits(n, type, what);
        std::vector<double> values(n);
        for (unsigned long long i = 0; i < n; ++i)
          {
            if (binary)
              {
                const std::uint64_t bits = load_big_endian(data.data() + position, type.bytes);
                position += type.bytes;
                if (type.kind == ValueType::floating && type.bytes == 4)
                  {
                    const auto narrow = static_cast<std::uint32_t>(bits);
                    float      value;
                    std::memcpy(&value, &narrow, 4);
                    values[i] = value;
                  }
                else if (type.kind == ValueType::floating)
                  std::memcpy(&values[i], &bits, 8);
                else if (type.kind == ValueType::signed_integer)
                  values[i] = static_cast<double>(sign_extend(bits, type.bytes));
                else
                  values[i] = static_cast<double>(bits);
                if (!std::isfinite(values[i]))
                  fail(section + ": value " + std::to_string(i) + " of its " + what + " is not a finite number");
              }
            else
              {
                const auto token = next_token();
                if (token.empty())
                  fail_truncated(i, n, what);
                const std::string text(token);
                char             *end = nullptr;
                values[i]             = std::strtod(text.c_str(), &end);
                if (end != text.c_str() + text.size() || !std::isfinite(values[i]))
                  fail(section + ": " + quote(token) + " is not a finite number");
              }
          }
        return values;
      }

      /** @p n values of integer @p type (cell lists, offsets, cell types). */
      std::vector<long long> read_integers(const unsigned long long n, const ValueType &type, const std::string &what)
      {
        if (type.kind != ValueType::signed_integer && type.kind != ValueType::unsigned_integer)
          fail(section + ": its " + what + " must be integers");
        check_fits(n, type, what);
        std::vector<long long> values(n);
        for (unsigned long long i = 0; i < n; ++i)
          {
            if (binary)
              {
                const std::uint64_t bits = load_big_endian(data.data() + position, type.bytes);
                position += type.bytes;
                if (type.kind == ValueType::signed_integer)
                  values[i] = sign_extend(bits, type.bytes);
                else
                  values[i] = bits > static_cast<std::uint64_t>(std::numeric_limits<long long>::max()) ?
                                std::numeric_limits<long long>::max() :
                                static_cast<long long>(bits);
              }
            else
              {
                const auto token = next_token();
                if (token.empty())
                  fail_truncated(i, n, what);
                const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), values[i]);
                if (error != std::errc() || end != token.data() + token.size())
                  fail(section + ": " + quote(token) + " is not an integer");
              }
          }
        return values;
      }

      /** Skip @p n values of @p type (FIELD data). */
      void skip_values(const unsigned long long n, const ValueType &type, const std::string &what)
      {
        check_fits(n, type, what);
        if (binary)
          {
            if (type.kind == ValueType::string)
              fail(section + ": binary string arrays are not supported");
            position += type.kind == ValueType::bit ? n / 8 + (n % 8 != 0) : n * type.bytes;
            return;
          }
        for (unsigned long long i = 0; i < n; ++i)
          if ((type.kind == ValueType::string ? (skip_space(), rest_of_line()) : next_token()).empty())
            fail_truncated(i, n, what);
      }

      /** Version 5: the METADATA block that may follow an array, up to a blank line. */
      void skip_metadata()
      {
        if (version < 5 || upper(peek_token()) != "METADATA")
          return;
        next_token();
        rest_of_line();
        while (position < data.size())
          {
            const auto line = rest_of_line();
            if (std::all_of(line.begin(), line.end(), is_space))
              break;
          }
      }

      void read_header();
      void skip_field();
      std::vector<double> read_points();
      Cells               read_cells();
      std::vector<long long> read_cell_types();
    };

    void Parser::read_header()
    {
      skip_space();
      const auto header = rest_of_line();
      if (upper(header.substr(0, 14)) != "# VTK DATAFILE")
        fail("not a legacy VTK file: expected '# vtk DataFile Version', found " + quote(header));
      const std::string header_upper = upper(header);
      const auto        at           = header_upper.find("VERSION");
      if (at != std::string::npos)
        {
          std::size_t digits = at + 7;
          while (digits < header.size() && header[digits] == ' ')
            ++digits;
          std::from_chars(header.data() + digits, header.data() + header.size(), version);
        }
      rest_of_line(); // the title
      const auto        format_line = rest_of_line();
      const std::string format      = upper(first_word(format_line));
      if (format == "BINARY")
        binary = true;
      else if (format != "ASCII")
        fail("expected ASCII or BINARY, found " + quote(format_line));
      const auto dataset = next_token();
      if (upper(dataset) != "DATASET")
        fail("expected DATASET UNSTRUCTURED_GRID, found " + quote(dataset));
      const auto type = next_token();
      if (upper(type) != "UNSTRUCTURED_GRID")
        fail("not a legacy VTK file holding an UNSTRUCTURED_GRID (DATASET " + quote(type) + ")");
      end_keyword_line();
    }

    void Parser::skip_field()
    {
      section = "FIELD";
      next_token(); // its name
      const unsigned long long n_arrays = count("number of arrays");
      end_keyword_line();
      for (unsigned long long a = 0; a < n_arrays; ++a)
        {
          const auto name = next_token();
          if (name.empty())
            fail("FIELD: the file ends after " + std::to_string(a) + " of the " + std::to_string(n_arrays) + " arrays");
          if (upper(name) == "NULL_ARRAY")
            continue;
          const unsigned long long n_components = count("number of components");
          const unsigned long long n_tuples     = count("number of tuples");
          const ValueType          type         = type_of("array " + quote(name));
          end_keyword_line();
          if (n_components != 0 && n_tuples > std::numeric_limits<unsigned long long>::max() / n_components)
            fail("FIELD: " + std::to_string(n_components) + " x " + std::to_string(n_tuples) + " values are too many");
          skip_values(n_components * n_tuples, type, "values of array " + quote(name));
          skip_metadata();
        }
    }

    std::vector<double> Parser::read_points()
    {
      section                        = "POINTS";
      const unsigned long long n     = count("number of points");
      const ValueType          type  = type_of("coordinates");
      end_keyword_line();
      if (n > std::numeric_limits<unsigned int>::max() || n > std::numeric_limits<unsigned long long>::max() / 3)
        fail("POINTS: " + std::to_string(n) + " points are too many");
      auto coordinates = read_reals(3 * n, type, "coordinates");
      skip_metadata();
      return coordinates;
    }

    Cells Parser::read_cells()
    {
      section                       = "CELLS";
      const unsigned long long n    = count("number of cells");
      const unsigned long long size = count("size");
      end_keyword_line();
      Cells cells;
      if (upper(peek_token()) == "OFFSETS")
        {
          // Version 5.1: "CELLS n_offsets n_connectivity", then the two arrays.
          next_token();
          const ValueType offset_type = type_of("offsets");
          end_keyword_line();
          cells.offsets = read_integers(n, offset_type, "offsets");
          skip_metadata();
          const auto keyword = next_token();
          if (upper(keyword) != "CONNECTIVITY")
            fail("expected CONNECTIVITY after the offsets, found " + quote(keyword));
          const ValueType connectivity_type = type_of("connectivity");
          end_keyword_line();
          cells.connectivity = read_integers(size, connectivity_type, "connectivity entries");
          skip_metadata();
          if (cells.offsets.empty())
            cells.offsets.push_back(0);
          if (cells.offsets.front() != 0)
            throw InputError(filename + ": CELLS: the first offset is " + std::to_string(cells.offsets.front()) +
                             ", not 0");
          for (std::size_t c = 1; c < cells.offsets.size(); ++c)
            if (cells.offsets[c] < cells.offsets[c - 1])
              throw InputError(filename + ": CELLS: offset " + std::to_string(c) + " (" +
                               std::to_string(cells.offsets[c]) + ") is less than the one before it (" +
                               std::to_string(cells.offsets[c - 1]) + ")");
          if (static_cast<unsigned long long>(cells.offsets.back()) != size)
            throw InputError(filename + ": CELLS: the last offset is " + std::to_string(cells.offsets.back()) +
                             ", not the " + std::to_string(size) + " connectivity entries");
          return cells;
        }

      // Before version 5: "CELLS n size", then n lists "k id_1 ... id_k". VTK reads an ASCII
      // file's lists as they come, whatever size says (files with a wrong size exist): so
      // does this parser; a BINARY file's lists must take size integers exactly.
      const ValueType int32{ValueType::signed_integer, 4};
      if (binary && n > size)
        fail("CELLS " + std::to_string(n) + " " + std::to_string(size) + ": " + std::to_string(n) +
             " cells cannot fit in " + std::to_string(size) + " integers");
      check_fits(n, int32, "cells");
      cells.offsets.reserve(n + 1);
      cells.offsets.push_back(0);
      std::vector<long long> lists;
      if (binary)
        lists = read_integers(size, int32, "integers");
      std::size_t at = 0;
      for (unsigned long long c = 0; c < n; ++c)
        {
          if (binary)
            {
              if (at == lists.size())
                throw InputError(filename + ": CELLS: its " + std::to_string(size) + " integers end after " +
                                 std::to_string(c) + " of the " + std::to_string(n) + " cells");
              const long long k = lists[at++];
              if (k < 0 || static_cast<unsigned long long>(k) > size - at)
                throw InputError(filename + ": CELLS: cell " + std::to_string(c) + " claims " + std::to_string(k) +
                                 " points, but only " + std::to_string(size - at) + " of the " +
                                 std::to_string(size) + " integers are left");
              cells.connectivity.insert(cells.connectivity.end(), lists.begin() + at, lists.begin() + at + k);
              at += k;
            }
          else
            {
              const long long k = read_integers(1, int32, "point counts").front();
              if (k < 0)
                fail("CELLS: cell " + std::to_string(c) + " claims " + std::to_string(k) + " points");
              const auto ids = read_integers(static_cast<unsigned long long>(k), int32, "point ids");
              cells.connectivity.insert(cells.connectivity.end(), ids.begin(), ids.end());
            }
          cells.offsets.push_back(static_cast<long long>(cells.connectivity.size()));
        }
      if (binary && at != size)
        throw InputError(filename + ": CELLS " + std::to_string(n) + " " + std::to_string(size) + ": the " +
                         std::to_string(n) + " cell lists take " + std::to_string(at) + " integers, not " +
                         std::to_string(size));
      skip_metadata();
      return cells;
    }

    std::vector<long long> Parser::read_cell_types()
    {
      section                    = "CELL_TYPES";
      const unsigned long long n = count("number of cells");
      end_keyword_line();
      auto types = read_integers(n, ValueType{ValueType::signed_integer, 4}, "cell types");
      skip_metadata();
      return types;
    }

    TetrahedralMesh Parser::parse()
    {
      read_header();
      std::vector<double>    coordinates;
      Cells                  cells;
      std::vector<long long> types;
      bool                   have_points = false, have_cells = false, have_types = false;
      while (true)
        {
          section            = "header";
          const auto keyword = upper(next_token());
          if (keyword.empty() || keyword == "POINT_DATA" || keyword == "CELL_DATA")
            break;
          if (keyword == "FIELD")
            skip_field();
          else if (keyword == "METADATA" && version >= 5)
            {
              position = token_start;
              skip_metadata();
            }
          else if (keyword == "POINTS" || keyword == "CELLS" || keyword == "CELL_TYPES")
            {
              bool &have = keyword == "POINTS" ? have_points : keyword == "CELLS" ? have_cells : have_types;
              if (have)
                fail("a second " + keyword + " section");
              have = true;
              if (keyword == "POINTS")
                coordinates = read_points();
              else if (keyword == "CELLS")
                cells = read_cells();
              else
                types = read_cell_types();
            }
          else
            fail("unknown keyword " + quote(data.substr(token_start, position - token_start)) +
                 " (expected FIELD, POINTS, CELLS, CELL_TYPES, POINT_DATA or CELL_DATA)");
        }
      for (const auto &[have, name] : {std::pair<bool, const char *>{have_points, "POINTS"},
                                       {have_cells, "CELLS"},
                                       {have_types, "CELL_TYPES"}})
        if (!have)
          throw InputError(filename + ": the file has no " + name + " section");
      if (coordinates.empty())
        throw InputError(filename + ": the file holds no point");
      const std::size_t n_cells = cells.offsets.size() - 1;
      if (types.size() != n_cells)
        throw InputError(filename + ": CELL_TYPES lists " + std::to_string(types.size()) + " cell types for " +
                         std::to_string(n_cells) + " cells");

      TetrahedralMesh mesh;
      mesh.name           = filename;
      const auto n_points = static_cast<long long>(coordinates.size() / 3);
      mesh.vertices.resize(n_points);
      for (long long p = 0; p < n_points; ++p)
        for (unsigned int d = 0; d < 3; ++d)
          mesh.vertices[p][d] = coordinates[3 * p + d];

      for (std::size_t c = 0; c < n_cells; ++c)
        {
          const std::string location = filename + ": cell " + std::to_string(c);
          const long long  *points   = cells.connectivity.data() + cells.offsets[c];
          const long long   n        = cells.offsets[c + 1] - cells.offsets[c];
          for (long long a = 0; a < n; ++a)
            if (points[a] < 0 || points[a] >= n_points)
              throw InputError(location + " refers to point " + std::to_string(points[a]) +
                               ", which is not defined (the file has " + std::to_string(n_points) + " points)");
          if (is_lower_dimensional(types[c]))
            continue;
          if (types[c] != vtk_tetra)
            throw InputError(location + " has VTK cell type " + std::to_string(types[c]) +
                             ": the only volume cell supported is the linear tetrahedron (10)");
          if (n != 4)
            throw InputError(location + " is a tetrahedron with " + std::to_string(n) + " points instead of 4");
          mesh.tetrahedra.push_back({{static_cast<unsigned int>(points[0]), static_cast<unsigned int>(points[1]),
                                      static_cast<unsigned int>(points[2]), static_cast<unsigned int>(points[3])}});
          mesh.locations.push_back(location);
        }
      if (mesh.tetrahedra.empty())
        throw InputError(filename + ": the file holds no tetrahedron (VTK cell type 10)");
      return mesh;
    }
  } // namespace

  TetrahedralMesh read_legacy_vtk(const std::string &filename)
  {
    std::ifstream input = open_input_file(filename, "mesh file");
    std::string   data((std::istreambuf_iterator<char>(input)), std::istreambuf_iterator<char>());
    if (input.bad())
      throw InputError(filename + ": cannot read the mesh file");
    return Parser(filename, std::move(data)).parse();
  }
} // namespace warpchol::fem
