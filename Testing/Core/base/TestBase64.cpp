// SPDX-License-Identifier: BSD-3-Clause
// base64 (base/Base64.h): RFC 4648's test vectors, random bytes against Boost.Archive's
// decoder (an implementation we did not write), and every kind of bad input with its message.
#include "base/Base64.h"

#include <boost/archive/iterators/binary_from_base64.hpp>
#include <boost/archive/iterators/transform_width.hpp>

#include <gtest/gtest.h>

#include <random>
#include <string>

using namespace morphnode;

namespace
{
/// Boost.Archive's dataflow iterators (no padding: strip it first).
std::string BoostDecode(std::string text)
{
  using namespace boost::archive::iterators;
  while (!text.empty() && text.back() == '=')
  {
    text.pop_back();
  }
  using Iterator = transform_width<binary_from_base64<std::string::const_iterator>, 8, 6>;
  std::string out(Iterator(text.cbegin()), Iterator(text.cend()));
  out.resize(text.size() * 6 / 8);
  return out;
}

std::string ErrorOf(const std::string& text)
{
  try
  {
    base64::Decode(text, "'x'");
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return "(no error)";
}
} // namespace

TEST(Base64, Rfc4648TestVectors)
{
  const std::pair<const char*, const char*> vectors[] = { { "", "" }, { "f", "Zg==" },
    { "fo", "Zm8=" }, { "foo", "Zm9v" }, { "foob", "Zm9vYg==" }, { "fooba", "Zm9vYmE=" },
    { "foobar", "Zm9vYmFy" } };
  for (const auto& [bytes, text] : vectors)
  {
    EXPECT_EQ(base64::Encode(bytes), text);
    EXPECT_EQ(base64::Decode(text), bytes);
  }
  // Padding may be left out; whitespace (line-wrapped output) is skipped.
  EXPECT_EQ(base64::Decode("Zm9vYg"), "foob");
  EXPECT_EQ(base64::Decode("Zm9v\r\nYmE=\n"), "fooba");
}

TEST(Base64, RandomBytesAgreeWithBoost)
{
  std::mt19937 random(25);
  for (int n = 0; n < 300; ++n)
  {
    std::string bytes(static_cast<size_t>(n), '\0');
    for (char& c : bytes)
    {
      c = static_cast<char>(random() & 0xff);
    }
    const std::string text = base64::Encode(bytes);
    EXPECT_EQ(text.size(), (bytes.size() + 2) / 3 * 4);
    EXPECT_EQ(base64::Decode(text), bytes) << n;
    EXPECT_EQ(BoostDecode(text), bytes) << n;
  }
}

TEST(Base64, BadInputSaysWhereAndWhy)
{
  EXPECT_EQ(ErrorOf("Zm9v*mFy"), "'x' is not valid base64: '*' at character 4");
  EXPECT_EQ(ErrorOf("Zm9v-_"), "'x' is not valid base64: '-' at character 4"); // base64url
  EXPECT_EQ(ErrorOf(std::string("Zm\0v", 4)), "'x' is not valid base64: byte 0 at character 2");
  EXPECT_NE(ErrorOf("Zm9vY").find("one character too many or too few"), std::string::npos);
  EXPECT_NE(ErrorOf("Zg=a").find("'=' before the end at character 2"), std::string::npos);
  EXPECT_NE(ErrorOf("Zg===").find("more than two '=' at character 4"), std::string::npos);
  EXPECT_NE(ErrorOf("Zm9v=").find("1 '=' do not complete"), std::string::npos);
  EXPECT_NE(ErrorOf("Zm8==").find("2 '=' do not complete"), std::string::npos);
  EXPECT_NE(ErrorOf("Zh==").find("bits set beyond the data"), std::string::npos); // 'h' != 'g'
}
