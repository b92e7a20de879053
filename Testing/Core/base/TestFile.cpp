// SPDX-License-Identifier: BSD-3-Clause
// Checked file access (base/File.h): reading refuses what is not a regular file and what
// is larger than the limit before reading a byte; writing never replaces a link, a device,
// a FIFO or a directory, and a full disk (EFBIG from RLIMIT_FSIZE in a child process: no
// privileges, no device node) leaves the old file as it was and no partial file.
#include "base/Error.h"
#include "base/File.h"
#include "base/Text.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace morphnode;
namespace fs = std::filesystem;

namespace
{
/// A fresh folder under the build's temporary directory, removed afterwards.
struct Folder
{
  fs::path Path;
  Folder()
  {
    char pattern[] = "/tmp/morphnode-file-XXXXXX";
    Path = ::mkdtemp(pattern);
  }
  ~Folder()
  {
    std::error_code ec;
    fs::remove_all(Path, ec);
  }
  std::string operator/(const std::string& name) const { return (Path / name).string(); }
};

void Put(const std::string& path, const std::string& text)
{
  std::ofstream(path, std::ios::binary) << text;
}

std::string Get(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string ErrorOf(const std::function<void()>& f)
{
  try
  {
    f();
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return "(no error)";
}

size_t PartFiles(const Folder& f)
{
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(f.Path))
  {
    n += e.path().extension() == ".part" ? 1 : 0;
  }
  return n;
}
} // namespace

TEST(File, ReadsRegularFilesAndLinksToThem)
{
  Folder f;
  Put(f / "a.txt", "hello");
  fs::create_symlink(f / "a.txt", f / "link.txt");
  EXPECT_EQ(text::ReadFile(f / "a.txt"), "hello");
  EXPECT_EQ(text::ReadFile(f / "link.txt"), "hello"); // links are resolved
  EXPECT_EQ(file::CheckInputFile(f / "a.txt"), 5u);
}

TEST(File, RefusesWhatIsNotARegularFileBeforeReading)
{
  Folder f;
  ASSERT_EQ(::mkfifo((f / "x.glb").c_str(), 0600), 0);
  // A FIFO with no writer: opening must not block, the kind is refused.
  EXPECT_NE(ErrorOf([&] { text::ReadFile(f / "x.glb", "glTF file"); }).find("is a FIFO"),
    std::string::npos);
  EXPECT_NE(ErrorOf([&] { text::ReadFile(f.Path.string(), "script"); }).find("is a directory"),
    std::string::npos);
  // A link to /dev/zero (read-only use of the device: its kind is refused before a read).
  fs::create_symlink("/dev/zero", f / "face.glb");
  const std::string zero = ErrorOf([&] { text::ReadFile(f / "face.glb", "face"); });
  EXPECT_NE(zero.find("face '"), std::string::npos) << zero;
  EXPECT_NE(zero.find("is a device"), std::string::npos) << zero;
  EXPECT_NE(
    ErrorOf([&] { text::ReadFile(f / "missing"); }).find("cannot be opened"), std::string::npos);
}

TEST(File, RefusesFilesLargerThanTheLimitFromTheirSize)
{
  Folder f;
  // A 5 GiB sparse file: no disk space, no memory; refused from its size alone.
  {
    std::ofstream(f / "big.glb");
  }
  fs::resize_file(f / "big.glb", uint64_t(5) << 30);
  const std::string e = ErrorOf([&] { text::ReadFile(f / "big.glb", "face"); });
  EXPECT_NE(e.find("has 5368709120 bytes; the limit is"), std::string::npos) << e;
  Put(f / "small.txt", "12345");
  EXPECT_NE(ErrorOf([&] { text::ReadFile(f / "small.txt", "text", 4); }).find("the limit is 4"),
    std::string::npos);
  EXPECT_EQ(text::ReadFile(f / "small.txt", "text", 5), "12345");
}

TEST(File, WritesReplaceOnlyRegularFilesOrNewPaths)
{
  Folder f;
  file::WriteFileSafely(f / "new.csv", "a\n");
  EXPECT_EQ(Get(f / "new.csv"), "a\n");
  file::WriteFileSafely(f / "new.csv", "b\n");
  EXPECT_EQ(Get(f / "new.csv"), "b\n");
  // A link at the target: refused, the link and what it points to unchanged.
  Put(f / "victim", "keep");
  fs::create_symlink(f / "victim", f / "out.glb");
  const std::string link = ErrorOf([&] { file::WriteFileSafely(f / "out.glb", "x", "--gltf"); });
  EXPECT_NE(link.find("is a symbolic link"), std::string::npos) << link;
  EXPECT_TRUE(fs::is_symlink(f / "out.glb"));
  EXPECT_EQ(Get(f / "victim"), "keep");
  // A directory, a FIFO: refused, left alone.
  fs::create_directory(f / "dir");
  EXPECT_NE(ErrorOf([&] { file::WriteFileSafely(f / "dir", "x"); }).find("is a directory"),
    std::string::npos);
  ASSERT_EQ(::mkfifo((f / "fifo").c_str(), 0600), 0);
  EXPECT_NE(
    ErrorOf([&] { file::WriteFileSafely(f / "fifo", "x"); }).find("is a FIFO"), std::string::npos);
  EXPECT_TRUE(fs::is_fifo(f / "fifo"));
  // Not committed (an error on the way): nothing left, the old file as it was.
  {
    file::SafeOutput out(f / "new.csv");
    out.Write("partial");
  }
  EXPECT_EQ(Get(f / "new.csv"), "b\n");
  EXPECT_EQ(PartFiles(f), 0u);
}

TEST(File, AFullDiskLeavesTheOldFileAndNoPartialFile)
{
  Folder f;
  Put(f / "old.csv", "old contents\n");
  const std::string big(64 * 1024, 'x');
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0)
  {
    // The child's file size limit: 4 KiB; writes beyond it fail with EFBIG (not a signal).
    std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit limit = { 4096, 4096 };
    ::setrlimit(RLIMIT_FSIZE, &limit);
    int code = 10;
    try
    {
      file::WriteFileSafely(f / "old.csv", big, "--out");
    }
    catch (const InputError& e)
    {
      const std::string m = e.what();
      code =
        m.find("File too large") != std::string::npos && m.find("'") != std::string::npos ? 0 : 11;
    }
    ::_exit(code);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0)
    << "10: the write did not fail, 11: the message does not say EFBIG";
  EXPECT_EQ(Get(f / "old.csv"), "old contents\n");
  EXPECT_EQ(PartFiles(f), 0u);
}

TEST(InputError, MessagesAreValidUtf8)
{
  // A quoted token with a broken sequence (issue 29: such a message never reached Python).
  const InputError e(std::string("bad token 'a\xff\xfe"
                                 "b' and \xc3\xa9 kept"));
  const std::string m = e.what();
  EXPECT_EQ(m,
    "bad token 'a\xef\xbf\xbd\xef\xbf\xbd"
    "b' and \xc3\xa9 kept");
  EXPECT_EQ(std::string(InputError("plain").what()), "plain");
}
