// The secrets of the service: capture ids and tokens from the operating system's random source
// (128 bits or more, so ids cannot be enumerated and tokens cannot be guessed), tokens stored only
// as their SHA-256, and compared in constant time so a response's timing tells nothing about how
// much of a guess was right.
#pragma once
#include <string>

namespace lorgnette::service {

// `bytes` random bytes as lower-case hex (2 * bytes characters). Throws when the random source fails.
std::string random_hex(int bytes);

inline std::string new_capture_id() { return random_hex(16); }     // 128 bits
inline std::string new_capture_token() { return random_hex(32); }  // 256 bits

// Whether `id` has the shape new_capture_id makes (32 lower-case hex digits): anything else, such
// as "../x", never reaches the store or the file system.
bool valid_capture_id(const std::string& id);

std::string sha256_hex(const std::string& text);

// Whether sha256_hex(token) equals `expected_hash`, in time independent of where they differ.
bool token_matches(const std::string& token, const std::string& expected_hash);

}  // namespace lorgnette::service
