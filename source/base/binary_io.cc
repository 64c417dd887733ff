#include <warpchol/base/binary_io.h>
#include <warpchol/base/exceptions.h>

namespace warpchol
{
  BinaryWriter::BinaryWriter(std::ostream &out)
    : out(out)
  {}

  void BinaryWriter::write_bytes(const void *data, const std::size_t bytes)
  {
    out.write(static_cast<const char *>(data), static_cast<std::streamsize>(bytes));
  }

  void BinaryWriter::section(const std::string &name)
  {
    write(name);
  }

  void BinaryWriter::write(const std::string &text)
  {
    write(static_cast<std::uint64_t>(text.size()));
    write_bytes(text.data(), text.size());
  }

  void BinaryWriter::write(const std::vector<std::string> &texts)
  {
    write(static_cast<std::uint64_t>(texts.size()));
    for (const auto &text : texts)
      write(text);
  }

  void BinaryWriter::write(const std::vector<bool> &flags)
  {
    write(std::vector<unsigned char>(flags.begin(), flags.end()));
  }

  BinaryReader::BinaryReader(std::istream &in, const std::string &filename, const std::uint64_t size)
    : in(in)
    , file(filename)
    , bytes_left(size)
    , current_section("header")
  {}

  void BinaryReader::fail(const std::string &message) const
  {
    throw InputError(file + ": checkpoint section '" + current_section + "': " + message);
  }

  const std::string &BinaryReader::filename() const
  {
    return file;
  }

  void BinaryReader::read_bytes(void *data, const std::size_t bytes)
  {
    if (bytes > bytes_left)
      fail("the file ends early (cut short or not a checkpoint)");
    in.read(static_cast<char *>(data), static_cast<std::streamsize>(bytes));
    if (!in)
      fail("cannot be read");
    bytes_left -= bytes;
  }

  std::uint64_t BinaryReader::read_count(const std::size_t item_bytes)
  {
    const auto n = get<std::uint64_t>();
    // Checked before allocating: a corrupt count must not ask for terabytes.
    if (item_bytes > 0 && n > bytes_left / item_bytes)
      fail("holds " + std::to_string(n) + " items, more than the " + std::to_string(bytes_left) +
           " bytes left in the file: cut short or corrupt");
    return n;
  }

  void BinaryReader::expect_section(const std::string &name)
  {
    std::string found;
    // A section name is short: a long count means the layout differs.
    const auto n = get<std::uint64_t>();
    if (n > 64 || n > bytes_left)
      fail("expected section '" + name + "' next (another version or not a checkpoint)");
    found.resize(n);
    read_bytes(found.data(), n);
    if (found != name)
      fail("expected section '" + name + "' next, found '" + found + "' (another version)");
    current_section = name;
  }

  void BinaryReader::read(std::string &text)
  {
    const auto n = read_count(1);
    text.resize(n);
    read_bytes(text.data(), n);
  }

  void BinaryReader::read(std::vector<std::string> &texts)
  {
    // Each string takes at least its 8-byte length.
    const auto n = read_count(sizeof(std::uint64_t));
    texts.resize(n);
    for (auto &text : texts)
      read(text);
  }

  void BinaryReader::read(std::vector<bool> &flags)
  {
    std::vector<unsigned char> bytes;
    read(bytes);
    flags.assign(bytes.begin(), bytes.end());
  }
} // namespace warpchol
