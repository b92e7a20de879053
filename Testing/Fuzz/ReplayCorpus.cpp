// SPDX-License-Identifier: BSD-3-Clause
// Replays a fuzz corpus without libFuzzer: feeds every file under the given folders (or
// the given files) to LLVMFuzzerTestOneInput. A crash or an escaped exception fails the test.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace
{
void Replay(const std::filesystem::path& file, size_t& count)
{
  std::ifstream in(file, std::ios::binary);
  const std::vector<char> bytes(
    (std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  ++count;
}
} // namespace

int main(int argc, char** argv)
{
  if (argc < 2)
  {
    std::fprintf(stderr, "usage: %s <corpus folder or file>...\n", argv[0]);
    return 2;
  }
  size_t count = 0;
  for (int i = 1; i < argc; ++i)
  {
    const std::filesystem::path path(argv[i]);
    if (std::filesystem::is_directory(path))
    {
      for (const auto& entry : std::filesystem::recursive_directory_iterator(path))
      {
        if (entry.is_regular_file())
        {
          Replay(entry.path(), count);
        }
      }
    }
    else if (std::filesystem::is_regular_file(path))
    {
      Replay(path, count);
    }
    else
    {
      std::fprintf(stderr, "no such corpus: %s\n", argv[i]);
      return 2;
    }
  }
  if (count == 0)
  {
    std::fprintf(stderr, "the corpus is empty\n");
    return 1;
  }
  std::printf("replayed %zu inputs\n", count);
  return 0;
}
