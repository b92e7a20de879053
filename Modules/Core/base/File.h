// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file File.h
/// @brief The one place where the core and the programs open files they did not make:
/// reading checks a file's kind and size before a byte is read, writing goes through a
/// file beside the target that replaces it only when every byte is on disk.
///
/// Reading (ReadFile, CheckInputFile): the path is resolved (symbolic links followed);
/// only a regular file is read; a FIFO, a device (`/dev/zero`), a socket or a directory is
/// an InputError naming it, and so is a file larger than the caller's limit, decided from
/// its size before any memory is taken. Opening never blocks (a FIFO named `x.glb` is
/// refused, not waited for).
///
/// Writing (SafeOutput, WriteFileSafely): the bytes go to a new file in the target's folder
/// (`<name>.XXXXXX.part`); every write, flush and close is checked; the finished file is
/// renamed onto the target only when the target is a regular file or does not exist. A
/// symbolic link, a device, a FIFO or a directory at the target is refused before anything
/// is written (never replaced, never written through). A failure (a full disk: ENOSPC,
/// EFBIG) removes the new file and leaves the target as it was.
///
/// POSIX (open, fstat, lstat, mkstemps, rename): std::filesystem has no way to open
/// without following a FIFO's blocking or to tell a failed close, and iostreams lose errno.

#include "base/Error.h"

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace morphnode
{
namespace file
{
/// Default largest file a reader takes whole (text formats: scripts, rigs, tables, tracks).
constexpr uint64_t DefaultMaxReadBytes = uint64_t(256) << 20;

namespace detail
{
inline std::string Kind(mode_t mode)
{
  if (S_ISDIR(mode))
  {
    return "a directory";
  }
  if (S_ISFIFO(mode))
  {
    return "a FIFO";
  }
  if (S_ISCHR(mode) || S_ISBLK(mode))
  {
    return "a device";
  }
  if (S_ISSOCK(mode))
  {
    return "a socket";
  }
  if (S_ISLNK(mode))
  {
    return "a symbolic link";
  }
  return "not a regular file";
}

inline std::string Errno(int e)
{
  return e == EFBIG || e == ENOSPC
    ? std::string(std::strerror(e)) + ": the disk or the file size limit is full"
    : std::string(std::strerror(e));
}

inline std::string Name(const std::string& what, const std::string& path)
{
  return what + " '" + path + "'";
}

/// Opens for reading without blocking and checks kind and size. Returns the descriptor.
inline int OpenChecked(
  const std::string& path, const std::string& what, uint64_t maxBytes, uint64_t& size)
{
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0)
  {
    throw InputError(Name(what, path) + " cannot be opened (" + Errno(errno) + ")");
  }
  struct stat st;
  if (::fstat(fd, &st) != 0)
  {
    const int e = errno;
    ::close(fd);
    throw InputError(Name(what, path) + " cannot be read (" + Errno(e) + ")");
  }
  if (!S_ISREG(st.st_mode))
  {
    ::close(fd);
    throw InputError(
      Name(what, path) + " is " + Kind(st.st_mode) + "; only regular files are read");
  }
  size = static_cast<uint64_t>(st.st_size);
  if (size > maxBytes)
  {
    ::close(fd);
    throw InputError(Name(what, path) + " has " + std::to_string(size) + " bytes; the limit is " +
      std::to_string(maxBytes));
  }
  return fd;
}
} // namespace detail

/// The size of a regular file `path` (links resolved), checked against maxBytes; InputError
/// for a missing file, another kind of file or a larger one. For readers that open the file
/// themselves (libsndfile, VTK readers): call it first.
inline uint64_t CheckInputFile(const std::string& path, const std::string& what = "file",
  uint64_t maxBytes = DefaultMaxReadBytes)
{
  uint64_t size = 0;
  ::close(detail::OpenChecked(path, what, maxBytes, size));
  return size;
}

/// The whole regular file as bytes, after CheckInputFile's checks.
inline std::string ReadFile(const std::string& path, const std::string& what = "file",
  uint64_t maxBytes = DefaultMaxReadBytes)
{
  uint64_t size = 0;
  const int fd = detail::OpenChecked(path, what, maxBytes, size);
  std::string bytes;
  try
  {
    bytes.resize(static_cast<size_t>(size));
  }
  catch (const std::bad_alloc&)
  {
    ::close(fd);
    throw InputError(
      detail::Name(what, path) + " (" + std::to_string(size) + " bytes) does not fit in memory");
  }
  size_t done = 0;
  while (done < bytes.size())
  {
    const ssize_t n = ::read(fd, &bytes[done], bytes.size() - done);
    if (n < 0 && errno == EINTR)
    {
      continue;
    }
    if (n < 0)
    {
      const int e = errno;
      ::close(fd);
      throw InputError(detail::Name(what, path) + " cannot be read (" + detail::Errno(e) + ")");
    }
    if (n == 0)
    {
      break; // shrank while read: what is there
    }
    done += static_cast<size_t>(n);
  }
  ::close(fd);
  bytes.resize(done);
  return bytes;
}

/// InputError unless `path` may be replaced by a writer: it does not exist or is a regular
/// file (not a symbolic link, device, FIFO, socket or directory). Not following links:
/// `--out link` must not write through the link onto something else.
inline void CheckOutputPath(const std::string& path, const std::string& what = "output")
{
  if (path.empty())
  {
    throw InputError(what + ": no file name");
  }
  struct stat st;
  if (::lstat(path.c_str(), &st) != 0)
  {
    if (errno == ENOENT)
    {
      return;
    }
    throw InputError(
      detail::Name(what, path) + " cannot be checked (" + detail::Errno(errno) + ")");
  }
  if (!S_ISREG(st.st_mode))
  {
    throw InputError(detail::Name(what, path) + " is " + detail::Kind(st.st_mode) +
      "; only a regular file or a new path is replaced");
  }
}

/// A file being written beside its target. Write() or write to GetTemporaryPath() with
/// another writer (VTK, libsndfile), then Commit(): checked close, then rename onto the
/// target. Destroyed without Commit() (an error, an exception): the new file is removed,
/// the target untouched.
class SafeOutput
{
public:
  SafeOutput(const std::string& path, const std::string& what = "output")
    : Path(path)
    , What(what)
  {
    CheckOutputPath(path, what);
    std::string pattern = path + ".XXXXXX.part";
    this->Fd = ::mkstemps(&pattern[0], 5);
    if (this->Fd < 0)
    {
      throw InputError(
        detail::Name(what, path) + " cannot be written (" + detail::Errno(errno) + ")");
    }
    ::fcntl(this->Fd, F_SETFD, FD_CLOEXEC);
    // mkstemps makes 0600; a finished file gets the usual mode (umask applies).
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::fchmod(this->Fd, 0666 & ~mask);
    this->Temporary = pattern;
  }
  ~SafeOutput() { this->Discard(); }
  SafeOutput(const SafeOutput&) = delete;
  SafeOutput& operator=(const SafeOutput&) = delete;

  const std::string& GetTemporaryPath() const { return this->Temporary; }
  const std::string& GetPath() const { return this->Path; }

  /// Appends bytes; InputError on any failed write (the full disk's ENOSPC or EFBIG).
  void Write(std::string_view bytes)
  {
    size_t done = 0;
    while (done < bytes.size())
    {
      const ssize_t n = ::write(this->Fd, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR)
      {
        continue;
      }
      if (n <= 0)
      {
        this->Fail(n < 0 ? errno : EIO);
      }
      done += static_cast<size_t>(n);
    }
  }

  /// Checked close and rename onto the target (checked again: it may have changed).
  void Commit()
  {
    if (this->Fd >= 0)
    {
      const int fd = this->Fd;
      this->Fd = -1;
      if (::fsync(fd) != 0 && errno != EINVAL)
      {
        const int e = errno;
        ::close(fd);
        this->Fail(e);
      }
      if (::close(fd) != 0)
      {
        this->Fail(errno);
      }
    }
    if (this->Temporary.empty())
    {
      throw InputError(detail::Name(this->What, this->Path) + ": already written or discarded");
    }
    struct stat st;
    if (::stat(this->Temporary.c_str(), &st) != 0)
    {
      this->Fail(errno);
    }
    CheckOutputPath(this->Path, this->What);
    if (std::rename(this->Temporary.c_str(), this->Path.c_str()) != 0)
    {
      this->Fail(errno);
    }
    this->Temporary.clear();
  }

  /// Removes the new file (the target stays as it was).
  void Discard()
  {
    if (this->Fd >= 0)
    {
      ::close(this->Fd);
      this->Fd = -1;
    }
    if (!this->Temporary.empty())
    {
      ::unlink(this->Temporary.c_str());
      this->Temporary.clear();
    }
  }

private:
  [[noreturn]] void Fail(int e)
  {
    this->Discard();
    throw InputError(detail::Name(this->What, this->Path) + " cannot be written (" +
      detail::Errno(e) + "); the old file, if any, is unchanged");
  }

  std::string Path;
  std::string What;
  std::string Temporary;
  int Fd = -1;
};

/// Writes `bytes` to `path` through a SafeOutput.
inline void WriteFileSafely(
  const std::string& path, std::string_view bytes, const std::string& what = "output")
{
  SafeOutput out(path, what);
  out.Write(bytes);
  out.Commit();
}
} // namespace file
} // namespace morphnode
