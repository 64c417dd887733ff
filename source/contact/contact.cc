#include <warpchol/contact/contact.h>

namespace warpchol::fem
{
  Vector3 point_value(const Contact &contact, const std::vector<Vector3> &field)
  {
    Vector3 value = Vector3::Zero();
    for (unsigned int k = 0; k < contact.n_vertices; ++k)
      value += contact.weights[k] * field[contact.vertex_of(k)];
    return value;
  }

  std::uint64_t contact_key(const Contact &contact)
  {
    // A point in a triangle is keyed by its first vertex with the top bit set.
    return (static_cast<std::uint64_t>(contact.vertex) << 32) | contact.obstacle |
           (contact.n_vertices > 1 ? std::uint64_t(1) << 31 : 0);
  }

  void write_contact_keys(BinaryWriter &writer, const std::vector<Contact> &contacts)
  {
    std::vector<unsigned int> vertices, obstacles, counts;
    for (const Contact &contact : contacts)
      {
        vertices.push_back(contact.vertex);
        obstacles.push_back(contact.obstacle);
        counts.push_back(contact.n_vertices);
      }
    writer.write(vertices);
    writer.write(obstacles);
    writer.write(counts);
  }

  std::vector<Contact> read_contact_keys(BinaryReader &reader, const std::size_t n_obstacles,
                                         const std::string &what)
  {
    std::vector<unsigned int> vertices, obstacles, counts;
    reader.read(vertices);
    reader.read(obstacles);
    reader.read(counts);
    if (obstacles.size() != vertices.size() || counts.size() != vertices.size())
      reader.fail("holds " + std::to_string(vertices.size()) + " " + what + "s with " +
                  std::to_string(obstacles.size()) + " obstacles");
    std::vector<Contact> contacts(vertices.size());
    for (std::size_t j = 0; j < vertices.size(); ++j)
      {
        if (obstacles[j] >= n_obstacles)
          reader.fail("a " + what + " names obstacle " + std::to_string(obstacles[j] + 1) + " of " +
                      std::to_string(n_obstacles));
        contacts[j].vertex     = vertices[j];
        contacts[j].obstacle   = obstacles[j];
        contacts[j].n_vertices = counts[j];
      }
    return contacts;
  }
} // namespace warpchol::fem
