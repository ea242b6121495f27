// SHA-256 (FIPS 180-4) through OpenSSL's EVP interface; link with -lcrypto (OpenSSL::Crypto).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace hb {

// Incremental SHA-256. update() any number of times, then hexDigest() once; the object cannot be
// updated after hexDigest().
class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;

  void update(const void* data, size_t size);  // data may be null when size is 0
  std::string hexDigest();                     // 64 lowercase hex digits

 private:
  void* ctx_;  // EVP_MD_CTX*, kept opaque so that this header does not pull in OpenSSL
  bool finished_ = false;
};

// One-shot SHA-256 of a byte string, as 64 lowercase hex digits.
std::string sha256Hex(const void* data, size_t size);

}  // namespace hb
