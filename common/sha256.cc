// SHA-256 of a file with OpenSSL's libcrypto (Debian's libssl-dev), the library the coordinator
// already links for its HMAC: no hash code of our own to get wrong.
#include <fcntl.h>
#include <openssl/evp.h>
#include <unistd.h>

#include <cerrno>
#include <memory>
#include <vector>

#include "common/common.h"

namespace sitlnet {

std::string Sha256HexOfFile(const std::string& path) {
  const UniqueFd fd(open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (!fd.valid()) throw Error(SystemErrorMessage("hash \"" + path + "\"", errno));
  const std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> context(EVP_MD_CTX_new(),
                                                                       &EVP_MD_CTX_free);
  SITLNET_DEMAND(context != nullptr);
  SITLNET_DEMAND(EVP_DigestInit_ex(context.get(), EVP_sha256(), nullptr) == 1);
  std::vector<unsigned char> block(1 << 20);
  while (true) {
    const ssize_t n = read(fd.get(), block.data(), block.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw Error(SystemErrorMessage("read \"" + path + "\" to hash it", errno));
    if (n == 0) break;
    SITLNET_DEMAND(EVP_DigestUpdate(context.get(), block.data(), static_cast<size_t>(n)) == 1);
  }
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  SITLNET_DEMAND(EVP_DigestFinal_ex(context.get(), digest, &length) == 1);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) {
    hex += kHex[digest[i] >> 4];
    hex += kHex[digest[i] & 0x0f];
  }
  return hex;
}

}  // namespace sitlnet
