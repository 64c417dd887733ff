#include <warpchol/base/atomic_file.h>
#include <warpchol/base/exceptions.h>

#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <signal.h>
#include <streambuf>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace warpchol
{
  namespace
  {
    /** strerror(@p error) as part of a sentence: "no space left on device". */
    std::string reason(const int error)
    {
      std::string text = std::strerror(error);
      if (!text.empty())
        text[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(text[0])));
      return text;
    }

    /**
     * A stream buffer over a file descriptor that checks every write(2) and the close(2),
     * and keeps the first error (errno) with the bytes written up to it. After an error it
     * drops what it is given but goes on counting it, and the stream stays good: the
     * caller reports the error once the writer is done.
     */
    class CheckedFileBuffer : public std::streambuf
    {
    public:
      explicit CheckedFileBuffer(const int descriptor)
        : descriptor(descriptor)
        , buffer(1 << 16)
      {
        setp(buffer.data(), buffer.data() + buffer.size());
      }

      ~CheckedFileBuffer() override
      {
        if (descriptor >= 0)
          ::close(descriptor);
      }

      /** Write what is buffered and close the file; false if any write or the close failed. */
      bool close()
      {
        sync();
        if (::close(descriptor) != 0 && error == 0)
          error = errno;
        descriptor = -1;
        return error == 0;
      }

      /** The first error (errno), 0 if none. */
      int error = 0;
      /** Bytes given to the buffer (flushed so far) and bytes that reached the file. */
      std::uintmax_t bytes_given   = 0;
      std::uintmax_t bytes_written = 0;

    protected:
      int_type overflow(const int_type c) override
      {
        write_buffered();
        if (!traits_type::eq_int_type(c, traits_type::eof()))
          {
            *pptr() = traits_type::to_char_type(c);
            pbump(1);
          }
        return traits_type::not_eof(c);
      }

      int sync() override
      {
        write_buffered();
        return 0;
      }

    private:
      void write_buffered()
      {
        const char       *data = pbase();
        const std::size_t size = pptr() - pbase();
        bytes_given += size;
        for (std::size_t done = 0; error == 0 && done < size;)
          {
            const ssize_t written = ::write(descriptor, data + done, size - done);
            if (written < 0 && errno == EINTR)
              continue;
            if (written <= 0)
              error = written < 0 ? errno : EIO;
            else
              {
                done += written;
                bytes_written += written;
              }
          }
        setp(buffer.data(), buffer.data() + buffer.size());
      }

      int               descriptor;
      std::vector<char> buffer;
    };

    /**
     * Open @p path with @p flags, call @p write on it and close it, checking every write;
     * messages name @p filename (the file the user knows of, not its temporary).
     */
    void write_checked(const std::string &path, const std::string &filename, const int flags,
                       const std::function<void(std::ostream &)> &write)
    {
      const int descriptor = ::open(path.c_str(), flags | O_CLOEXEC, 0666);
      if (descriptor < 0)
        {
          const int error = errno;
          throw OutputError(filename + ": cannot open for writing: " + reason(error));
        }
      CheckedFileBuffer buffer(descriptor);
      std::ostream      stream(&buffer);
      const auto        failure = [&]() {
        return OutputError(filename + ": " + reason(buffer.error) + " (wrote " +
                           std::to_string(buffer.bytes_written) + " of " +
                           std::to_string(buffer.bytes_given) + " bytes)");
      };
      try
        {
          write(stream);
        }
      catch (...)
        {
          // A writer that gave up because of the failed write: report the write.
          if (buffer.error != 0)
            throw failure();
          throw;
        }
      stream.flush();
      if (!buffer.close())
        throw failure();
      if (!stream)
        throw OutputError(filename + ": the writer's stream failed");
    }

    /** What write_file_atomically() puts between a file's name and its writer's process id. */
    constexpr const char *temporary_marker = ".tmp.";

    /** The writer's process id of temporary @p name, 0 if it is not a temporary's name. */
    pid_t writer_of(const std::string &name)
    {
      const auto marker = name.rfind(temporary_marker);
      if (marker == std::string::npos || marker == 0)
        return 0;
      const std::string digits = name.substr(marker + std::strlen(temporary_marker));
      if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos)
        return 0;
      return static_cast<pid_t>(std::stol(digits));
    }
  } // namespace

  std::size_t remove_stale_temporaries(const std::string &directory)
  {
    std::size_t     removed = 0;
    std::error_code error;
    for (const auto &entry : std::filesystem::directory_iterator(directory, error))
      {
        const pid_t writer = writer_of(entry.path().filename().string());
        // kill(pid, 0) sends nothing: ESRCH says that no such process runs. A process id
        // taken again since keeps its temporary, which is the safe side.
        std::error_code not_a_file;
        if (writer > 0 && ::kill(writer, 0) != 0 && errno == ESRCH && entry.is_regular_file(not_a_file) &&
            std::filesystem::remove(entry.path(), not_a_file))
          ++removed;
      }
    return removed;
  }

  void write_file_atomically(const std::string                        &filename,
                             const std::function<void(std::ostream &)> &write)
  {
    struct stat status;
    if (::stat(filename.c_str(), &status) == 0 && !S_ISREG(status.st_mode))
      {
        if (S_ISDIR(status.st_mode))
          throw OutputError(filename + ": is a directory, cannot write a file there");
        write_checked(filename, filename, O_WRONLY, write);
        return;
      }
    // The process id keeps two concurrent writers of the same file apart, and tells a
    // temporary whose writer was killed (remove_stale_temporaries()).
    const std::string temporary = filename + temporary_marker + std::to_string(::getpid());
    try
      {
        write_checked(temporary, filename, O_WRONLY | O_CREAT | O_TRUNC, write);
      }
    catch (...)
      {
        std::remove(temporary.c_str());
        throw;
      }
    if (std::rename(temporary.c_str(), filename.c_str()) != 0)
      {
        const int error = errno;
        std::remove(temporary.c_str());
        throw OutputError(filename + ": cannot rename the temporary file into place: " + reason(error));
      }
  }
} // namespace warpchol
