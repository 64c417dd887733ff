#include <warpchol/base/format.h>

#include <algorithm>
#include <cstdio>

namespace warpchol
{
  std::string format_number(const double value, const int digits)
  {
    char buffer[64];
    std::snprintf(buffer, sizeof(buffer), "%.*g", digits, value);
    return buffer;
  }

  namespace
  {
    bool is_printable(const unsigned char c)
    {
      return c >= 0x20 && c < 0x7f;
    }

    /** The byte @p c as it appears in a message: itself, or \xNN. */
    std::string printable_byte(const unsigned char c)
    {
      if (is_printable(c))
        return std::string(1, static_cast<char>(c));
      char buffer[8];
      std::snprintf(buffer, sizeof(buffer), "\\x%02X", c);
      return buffer;
    }

    /** The length of the valid UTF-8 sequence at @p text[i] (0 if it is not one). */
    std::size_t utf8_sequence_length(const std::string_view text, const std::size_t i)
    {
      const auto        lead   = static_cast<unsigned char>(text[i]);
      const std::size_t length = lead >= 0xF0 && lead <= 0xF4 ? 4 :
                                 lead >= 0xE0                  ? 3 :
                                 lead >= 0xC2 && lead <= 0xDF  ? 2 :
                                                                 0;
      if (length == 0 || i + length > text.size())
        return 0;
      for (std::size_t k = 1; k < length; ++k)
        if ((static_cast<unsigned char>(text[i + k]) & 0xC0) != 0x80)
          return 0;
      return length;
    }
  } // namespace

  std::string printable(const std::string_view text)
  {
    std::string result;
    result.reserve(text.size());
    for (const char c : text)
      result += printable_byte(static_cast<unsigned char>(c));
    return result;
  }

  std::string excerpt(const std::string_view text, const std::size_t max_characters)
  {
    const std::string ellipsis = "...";
    std::string       result;
    for (std::size_t i = 0; i < text.size(); ++i)
      {
        const std::string next = printable_byte(static_cast<unsigned char>(text[i]));
        // Room for the ellipsis unless this is the last byte.
        const std::size_t room = i + 1 == text.size() ? max_characters :
                                                        max_characters - std::min(max_characters, ellipsis.size());
        if (result.size() + next.size() > room)
          return result + ellipsis;
        result += next;
      }
    return result;
  }

  bool looks_binary(const std::string_view text)
  {
    std::size_t suspicious = 0;
    for (std::size_t i = 0; i < text.size(); ++i)
      {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c == 0)
          return true;
        if (c >= 0x80)
          {
            const std::size_t length = utf8_sequence_length(text, i);
            if (length == 0)
              ++suspicious;
            else
              i += length - 1;
          }
        else if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v') ||
                 c == 0x7f)
          ++suspicious;
      }
    return 10 * suspicious > text.size();
  }

  std::string quote(const std::string_view text, const std::size_t max_characters)
  {
    return "'" + excerpt(text, max_characters) + "'" + (looks_binary(text) ? " (binary data)" : "");
  }

  std::string alternatives(const std::vector<std::string> &names)
  {
    std::string list;
    for (std::size_t k = 0; k < names.size(); ++k)
      list += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + names[k];
    return list;
  }
} // namespace warpchol
