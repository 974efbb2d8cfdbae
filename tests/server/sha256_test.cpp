// Known-answer tests for server/sha256 (FIPS 180-2 appendix B and the NIST example values).
#include "server/sha256.hpp"

#include <string>

#include <gtest/gtest.h>

namespace brisance::server {
namespace {

TEST(Sha256, KnownAnswers) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, RawDigestMatchesHex) {
  const auto digest = sha256("abc");
  EXPECT_EQ(digest[0], 0xba);
  EXPECT_EQ(digest[31], 0xad);
}

TEST(Sha256, ConstantTimeEqual) {
  EXPECT_TRUE(constant_time_equal("same key", "same key"));
  EXPECT_FALSE(constant_time_equal("same key", "same kez"));
  EXPECT_FALSE(constant_time_equal("short", "shorter"));
  EXPECT_TRUE(constant_time_equal("", ""));
}

}  // namespace
}  // namespace brisance::server
