#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <type_traits>
#include <vector>

/**
 * @file
 * The binary form of a checkpoint: plain values and arrays of them, in the machine's own
 * byte order, with named sections that a reader checks, so that a file of another kind, of
 * another version or cut short is refused in one line instead of read as garbage.
 */
namespace warpchol
{
  /**
   * Whether @p T can be written as its bytes: no pointer inside, one block of storage
   * (Eigen's fixed-size matrices are standard layout, though not trivially copyable).
   */
  template <typename T>
  constexpr bool is_plain_data_v =
    std::is_standard_layout_v<T> && !std::is_pointer_v<T> && std::is_copy_assignable_v<T>;

  /** Writes values, arrays and section names to a binary stream. */
  class BinaryWriter
  {
  public:
    explicit BinaryWriter(std::ostream &out);

    /** Mark the start of section @p name: a reader expects it there (expect_section()). */
    void section(const std::string &name);

    template <typename T>
    void write(const T &value)
    {
      static_assert(is_plain_data_v<T>, "only plain data is written as bytes");
      write_bytes(&value, sizeof(T));
    }

    template <typename T>
    void write(const std::vector<T> &values)
    {
      static_assert(is_plain_data_v<T>, "only plain data is written as bytes");
      write(static_cast<std::uint64_t>(values.size()));
      write_bytes(values.data(), values.size() * sizeof(T));
    }

    void write(const std::string &text);
    void write(const std::vector<std::string> &texts);
    void write(const std::vector<bool> &flags);

    /**
     * archive & value: write @p value. With BinaryReader::operator&, a type lists its
     * checkpointed members once, in a serialize(Archive &) for both directions (as deal.II
     * and boost do); write_object() and read_object() call it.
     */
    template <typename T>
    BinaryWriter &operator&(const T &value)
    {
      write(value);
      return *this;
    }

  private:
    void          write_bytes(const void *data, std::size_t bytes);
    std::ostream &out;
  };

  /**
   * Reads what a BinaryWriter wrote. Every size is checked against the bytes left in the
   * file before anything is allocated; a file cut short, of another kind or with another
   * layout throws InputError naming the file and the section being read.
   */
  class BinaryReader
  {
  public:
    /** @p filename names the file in messages; @p size is its length in bytes. */
    BinaryReader(std::istream &in, const std::string &filename, std::uint64_t size);

    /** Throws InputError unless section @p name starts here. */
    void expect_section(const std::string &name);

    template <typename T>
    void read(T &value)
    {
      static_assert(is_plain_data_v<T>, "only plain data is read as bytes");
      read_bytes(&value, sizeof(T));
    }

    template <typename T>
    void read(std::vector<T> &values)
    {
      static_assert(is_plain_data_v<T>, "only plain data is read as bytes");
      const std::uint64_t n = read_count(sizeof(T));
      values.resize(n);
      read_bytes(values.data(), n * sizeof(T));
    }

    void read(std::string &text);
    void read(std::vector<std::string> &texts);
    void read(std::vector<bool> &flags);

    /** archive & value: read @p value (see BinaryWriter::operator&). */
    template <typename T>
    BinaryReader &operator&(T &value)
    {
      read(value);
      return *this;
    }

    /** The value read, for a plain type. */
    template <typename T>
    T get()
    {
      T value{};
      read(value);
      return value;
    }

    /** Throw InputError "FILE: checkpoint section S: @p message". */
    [[noreturn]] void fail(const std::string &message) const;

    const std::string &filename() const;

  private:
    void read_bytes(void *data, std::size_t bytes);
    /** A count of items of @p item_bytes each, checked against what is left of the file. */
    std::uint64_t read_count(std::size_t item_bytes);

    std::istream &in;
    std::string   file;
    std::uint64_t bytes_left;
    std::string   current_section;
  };

  /** Write @p object's checkpointed members: its serialize(Archive &), which only reads them here. */
  template <typename T>
  void write_object(BinaryWriter &writer, const T &object)
  {
    const_cast<T &>(object).serialize(writer);
  }

  /** Read what write_object() wrote into @p object. */
  template <typename T>
  void read_object(BinaryReader &reader, T &object)
  {
    object.serialize(reader);
  }
} // namespace warpchol
