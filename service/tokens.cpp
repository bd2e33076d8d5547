// Random ids and tokens, hashing and constant-time comparison (tokens.h), with OpenSSL's libcrypto.
#include "service/tokens.h"

#include <openssl/crypto.h>
#include <openssl/rand.h>
#include <openssl/sha.h>

#include <stdexcept>
#include <vector>

namespace lorgnette::service {
namespace {

std::string hex(const unsigned char* data, size_t n) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  out.reserve(2 * n);
  for (size_t i = 0; i < n; ++i) out += digits[data[i] >> 4], out += digits[data[i] & 15];
  return out;
}

}  // namespace

std::string random_hex(int bytes) {
  std::vector<unsigned char> buf(static_cast<size_t>(bytes));
  if (RAND_bytes(buf.data(), bytes) != 1) throw std::runtime_error("the random source failed");
  return hex(buf.data(), buf.size());
}

bool valid_capture_id(const std::string& id) {
  if (id.size() != 32) return false;
  for (char c : id)
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  return true;
}

std::string sha256_hex(const std::string& text) {
  unsigned char digest[SHA256_DIGEST_LENGTH];
  SHA256(reinterpret_cast<const unsigned char*>(text.data()), text.size(), digest);
  return hex(digest, sizeof digest);
}

bool token_matches(const std::string& token, const std::string& expected_hash) {
  const std::string got = sha256_hex(token);  // fixed length, whatever the token's length
  if (expected_hash.size() != got.size()) return false;
  return CRYPTO_memcmp(got.data(), expected_hash.data(), got.size()) == 0;
}

}  // namespace lorgnette::service
