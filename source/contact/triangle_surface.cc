#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/contact/triangle_surface.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace warpchol::fem
{
  namespace
  {
    /** Fails with "FILE:LINE: why", or "FILE: why" for line 0. */
    [[noreturn]] void fail(const std::string &file_name, const int line, const std::string &why)
    {
      throw InputError(file_name + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + why);
    }

    /** Three finite coordinates from @p words starting at @p first. */
    Vector3 read_point(const std::vector<std::string> &words, const std::size_t first, const std::string &file_name,
                       const int line)
    {
      if (words.size() < first + 3)
        fail(file_name, line, "expected three coordinates");
      Vector3 point;
      for (int c = 0; c < 3; ++c)
        {
          const std::string &word = words[first + c];
          char              *end  = nullptr;
          point[c]                = std::strtod(word.c_str(), &end);
          if (end == word.c_str() || *end != '\0' || !std::isfinite(point[c]))
            fail(file_name, line, "coordinate " + quote(word) + " is not a finite number");
        }
      return point;
    }

    /**
     * A count from the file (of points, polygons, corners): digits only and below 2^31, so
     * that the count times three and plus one stay in range; a larger count cannot be met
     * by the lines that follow anyway.
     */
    long read_count(const std::string &word, const std::string &what, const std::string &file_name, const int line)
    {
      const bool digits = !word.empty() && word.size() <= 10 &&
                          word.find_first_not_of("0123456789") == std::string::npos;
      const long count = digits ? std::strtol(word.c_str(), nullptr, 10) : -1;
      if (count < 0 || count > std::numeric_limits<int>::max())
        fail(file_name, line, what + " " + quote(word) + " is not a count");
      return count;
    }

    std::vector<std::string> split(const std::string &text)
    {
      std::istringstream       stream(text);
      std::vector<std::string> words;
      for (std::string word; stream >> word;)
        words.push_back(word);
      return words;
    }

    TriangleSurface read_binary_stl(const std::string &bytes, const std::string &file_name)
    {
      TriangleSurface surface;
      std::uint32_t   count = 0;
      std::memcpy(&count, bytes.data() + 80, 4);
      for (std::uint32_t t = 0; t < count; ++t)
        {
          const char *record = bytes.data() + 84 + 50 * static_cast<std::size_t>(t);
          std::array<unsigned int, 3> triangle{};
          for (int corner = 0; corner < 3; ++corner)
            {
              float xyz[3];
              std::memcpy(xyz, record + 12 + 12 * corner, 12);
              const Vector3 point(xyz[0], xyz[1], xyz[2]);
              if (!point.allFinite())
                fail(file_name, 0, "triangle " + std::to_string(t + 1) + " has a coordinate that is not finite");
              triangle[corner] = static_cast<unsigned int>(surface.points.size());
              surface.points.push_back(point);
            }
          surface.triangles.push_back(triangle);
        }
      return surface;
    }

    TriangleSurface read_ascii_stl(std::istream &in, const std::string &file_name)
    {
      TriangleSurface surface;
      int             line_number = 0, corners = 0;
      for (std::string line; std::getline(in, line);)
        {
          ++line_number;
          const std::vector<std::string> words = split(line);
          if (words.empty() || words[0] != "vertex")
            continue;
          surface.points.push_back(read_point(words, 1, file_name, line_number));
          if (++corners == 3)
            {
              const auto last = static_cast<unsigned int>(surface.points.size());
              surface.triangles.push_back({{last - 3, last - 2, last - 1}});
              corners = 0;
            }
        }
      if (corners != 0)
        fail(file_name, line_number, "the file ends inside a facet");
      return surface;
    }

    /** An index of a face (1-based, or negative: from the end), "a", "a/b" or "a/b/c". */
    unsigned int face_index(const std::string &word, const std::size_t n_points, const std::string &file_name,
                            const int line)
    {
      char      *end   = nullptr;
      const long index = std::strtol(word.c_str(), &end, 10);
      if (end == word.c_str() || (*end != '\0' && *end != '/'))
        fail(file_name, line, "face index " + quote(word) + " is not an integer");
      const long zero_based = index > 0 ? index - 1 : static_cast<long>(n_points) + index;
      if (index == 0 || zero_based < 0 || zero_based >= static_cast<long>(n_points))
        fail(file_name, line, "face index " + word + " refers to no vertex (" + std::to_string(n_points) + " so far)");
      return static_cast<unsigned int>(zero_based);
    }

    TriangleSurface read_obj(std::istream &in, const std::string &file_name)
    {
      TriangleSurface surface;
      int             line_number = 0;
      for (std::string line; std::getline(in, line);)
        {
          ++line_number;
          const std::vector<std::string> words = split(line);
          if (words.empty() || words[0][0] == '#')
            continue;
          if (words[0] == "v")
            surface.points.push_back(read_point(words, 1, file_name, line_number));
          else if (words[0] == "f")
            {
              if (words.size() < 4)
                fail(file_name, line_number, "a face needs at least three vertices");
              std::vector<unsigned int> corners;
              for (std::size_t k = 1; k < words.size(); ++k)
                corners.push_back(face_index(words[k], surface.points.size(), file_name, line_number));
              for (std::size_t k = 1; k + 1 < corners.size(); ++k)
                surface.triangles.push_back({{corners[0], corners[k], corners[k + 1]}});
            }
          else if (words[0] != "vn" && words[0] != "vt" && words[0] != "o" && words[0] != "g" && words[0] != "s" &&
                   words[0] != "usemtl" && words[0] != "mtllib" && words[0] != "l")
            fail(file_name, line_number, "not an OBJ line: " + quote(line));
        }
      return surface;
    }

    TriangleSurface read_legacy_vtk(std::istream &in, const std::string &file_name)
    {
      TriangleSurface surface;
      int             line_number = 0;
      std::string     line;
      const auto      next_words  = [&]() {
        while (std::getline(in, line))
          {
            ++line_number;
            std::vector<std::string> words = split(line);
            if (!words.empty())
              return words;
          }
        fail(file_name, line_number, "the file ends early");
      };
      std::getline(in, line); // "# vtk DataFile Version x"
      std::getline(in, line); // the title
      line_number = 2;
      if (next_words()[0] != "ASCII")
        fail(file_name, line_number, "only ASCII legacy VTK files are read");
      const std::vector<std::string> dataset = next_words();
      if (dataset.size() < 2 || dataset[1] != "POLYDATA")
        fail(file_name, line_number, "expected DATASET POLYDATA");
      for (;;)
        {
          if (!std::getline(in, line))
            break;
          ++line_number;
          const std::vector<std::string> words = split(line);
          if (words.empty())
            continue;
          if (words[0] == "POINTS" && words.size() >= 2)
            {
              const long n = read_count(words[1], "POINTS: the number of points", file_name, line_number);
              std::vector<std::string> values;
              while (static_cast<long>(values.size()) < 3 * n)
                {
                  const int                      at    = line_number + 1;
                  const std::vector<std::string> more  = next_words();
                  values.insert(values.end(), more.begin(), more.end());
                  for (std::size_t k = values.size() - more.size(); k + 2 < values.size() && k % 3 == 0; k += 3)
                    surface.points.push_back(read_point(values, k, file_name, at));
                }
              if (static_cast<long>(surface.points.size()) != n)
                fail(file_name, line_number, "POINTS: the coordinates do not come in threes per line");
            }
          else if (words[0] == "POLYGONS" && words.size() >= 2)
            {
              const long n = read_count(words[1], "POLYGONS: the number of polygons", file_name, line_number);
              for (long k = 0; k < n; ++k)
                {
                  const std::vector<std::string> polygon = next_words();
                  const long count = read_count(polygon[0], "the number of corners", file_name, line_number);
                  if (count < 3 || static_cast<long>(polygon.size()) != count + 1)
                    fail(file_name, line_number, "a polygon of " + polygon[0] + " points over " +
                                                   std::to_string(polygon.size() - 1) + " indices");
                  std::vector<unsigned int> corners;
                  for (long c = 1; c <= count; ++c)
                    {
                      char         *end   = nullptr;
                      const long    index = std::strtol(polygon[c].c_str(), &end, 10);
                      if (*end != '\0' || index < 0 || index >= static_cast<long>(surface.points.size()))
                        fail(file_name, line_number, "point index " + quote(polygon[c]) + " refers to no point");
                      corners.push_back(static_cast<unsigned int>(index));
                    }
                  for (std::size_t c = 1; c + 1 < corners.size(); ++c)
                    surface.triangles.push_back({{corners[0], corners[c], corners[c + 1]}});
                }
            }
        }
      return surface;
    }
  } // namespace

  TriangleSurface read_triangle_surface(const std::string &file_name)
  {
    std::ifstream file(file_name, std::ios::binary);
    if (!file)
      fail(file_name, 0, "cannot be read");
    std::ostringstream buffer;
    buffer << file.rdbuf();
    const std::string bytes = buffer.str();
    if (bytes.empty())
      fail(file_name, 0, "is empty");

    TriangleSurface surface;
    std::uint32_t   count = 0;
    if (bytes.size() >= 84)
      std::memcpy(&count, bytes.data() + 80, 4);
    std::istringstream text(bytes);
    if (bytes.size() >= 84 && bytes.size() == 84 + 50 * static_cast<std::size_t>(count))
      surface = read_binary_stl(bytes, file_name);
    else if (bytes.compare(0, 5, "solid") == 0)
      surface = read_ascii_stl(text, file_name);
    else if (bytes.compare(0, 14, "# vtk DataFile") == 0)
      surface = read_legacy_vtk(text, file_name);
    else
      surface = read_obj(text, file_name);

    if (surface.triangles.empty())
      fail(file_name, 0, "holds no triangle");
    bool some_area = false;
    for (const auto &t : surface.triangles)
      some_area = some_area || (surface.points[t[1]] - surface.points[t[0]])
                                   .cross(surface.points[t[2]] - surface.points[t[0]])
                                   .norm() > 0;
    if (!some_area)
      fail(file_name, 0, "holds triangles of zero area only");
    return surface;
  }
} // namespace warpchol::fem
