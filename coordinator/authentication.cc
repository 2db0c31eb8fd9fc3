#include "coordinator/authentication.h"

#include <fcntl.h>
#include <openssl/core_names.h>
#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>
#include <openssl/params.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "common/common.h"

namespace sitlnet::coordinator {

std::string LoadSecretFile(const std::string& path) {
  const std::string who = "secret file " + path;
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) throw Error(SystemErrorMessage(who, errno));
  struct stat info {};
  std::string secret;
  std::string problem;
  if (fstat(fd, &info) != 0) {
    problem = SystemErrorMessage(who, errno);
  } else if (!S_ISREG(info.st_mode)) {
    problem = who + ": not a regular file";
  } else if (!IsInvokingUser(info.st_uid)) {
    problem =
        who + ": owned by uid " + std::to_string(info.st_uid) + ", not by the user running sitlnet";
  } else if ((info.st_mode & 077) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", info.st_mode & 07777);
    problem = who + ": mode " + mode + " lets others read or write it (chmod 600 " + path + ")";
  } else {
    char buffer[kMaxSecretBytes + 1];
    ssize_t n;
    while ((n = read(fd, buffer, sizeof buffer)) > 0 && secret.size() <= kMaxSecretBytes) {
      secret.append(buffer, static_cast<size_t>(n));
    }
    if (n < 0) problem = SystemErrorMessage(who, errno);
  }
  close(fd);
  if (problem.empty() && (secret.size() < kMinSecretBytes || secret.size() > kMaxSecretBytes)) {
    problem = who + ": " + std::to_string(secret.size()) + " bytes, expected " +
              std::to_string(kMinSecretBytes) + " to " + std::to_string(kMaxSecretBytes) +
              " (make one: head -c 32 /dev/urandom > " + path + "; chmod 600 " + path + ")";
  }
  if (!problem.empty()) throw Error(problem);
  return secret;
}

std::string RandomNonce() {
  std::string nonce(kNonceBytes, '\0');
  size_t filled = 0;
  while (filled < nonce.size()) {
    const ssize_t n = getrandom(nonce.data() + filled, nonce.size() - filled, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw Error(SystemErrorMessage("getrandom", errno));
    filled += static_cast<size_t>(n);
  }
  return nonce;
}

std::string ProofOf(const std::string& secret, const std::string& label, const std::string& first,
                    const std::string& second) {
  std::string message = label;
  message.push_back('\0');
  message += first;
  message += second;
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  SITLNET_DEMAND(HMAC(EVP_sha256(), secret.data(), static_cast<int>(secret.size()),
                      reinterpret_cast<const unsigned char*>(message.data()), message.size(),
                      digest, &length) != nullptr);
  return std::string(reinterpret_cast<const char*>(digest), length);
}

bool SameProof(const std::string& a, const std::string& b) {
  return a.size() == b.size() && CRYPTO_memcmp(a.data(), b.data(), a.size()) == 0;
}

struct TranscriptHash::Sha256 {
  EVP_MD_CTX* context = EVP_MD_CTX_new();
  ~Sha256() { EVP_MD_CTX_free(context); }
};

TranscriptHash::TranscriptHash() : sha_(std::make_unique<Sha256>()) {
  SITLNET_DEMAND(sha_->context != nullptr);
  SITLNET_DEMAND(EVP_DigestInit_ex(sha_->context, EVP_sha256(), nullptr) == 1);
}

TranscriptHash::~TranscriptHash() = default;

void TranscriptHash::Add(std::string_view frame) {
  SITLNET_DEMAND(EVP_DigestUpdate(sha_->context, frame.data(), frame.size()) == 1);
}

std::string TranscriptHash::Digest() const {
  Sha256 copy;
  SITLNET_DEMAND(copy.context != nullptr && EVP_MD_CTX_copy_ex(copy.context, sha_->context) == 1);
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  SITLNET_DEMAND(EVP_DigestFinal_ex(copy.context, digest, &length) == 1);
  return std::string(reinterpret_cast<const char*>(digest), length);
}

SessionKeys DeriveSessionKeys(const std::string& secret, const std::string& coordinator_nonce,
                              const std::string& connector_nonce) {
  return {ProofOf(secret, "sitlnet session coordinator to connector", coordinator_nonce,
                  connector_nonce),
          ProofOf(secret, "sitlnet session connector to coordinator", coordinator_nonce,
                  connector_nonce)};
}

// The key is set once; each tag re-initializes the state with it (EVP_MAC_init with a null key
// keeps the previous one), which spares a key schedule per message.
struct MessageTagger::Mac {
  EVP_MAC* algorithm = nullptr;
  EVP_MAC_CTX* context = nullptr;
  ~Mac() {
    EVP_MAC_CTX_free(context);
    EVP_MAC_free(algorithm);
  }
};

MessageTagger::MessageTagger(const std::string& key) : mac_(std::make_unique<Mac>()) {
  SITLNET_DEMAND(!key.empty());
  mac_->algorithm = EVP_MAC_fetch(nullptr, "HMAC", nullptr);
  SITLNET_DEMAND(mac_->algorithm != nullptr);
  mac_->context = EVP_MAC_CTX_new(mac_->algorithm);
  SITLNET_DEMAND(mac_->context != nullptr);
  char digest[] = "SHA256";
  const OSSL_PARAM params[] = {OSSL_PARAM_construct_utf8_string(OSSL_MAC_PARAM_DIGEST, digest, 0),
                               OSSL_PARAM_END};
  SITLNET_DEMAND(EVP_MAC_init(mac_->context, reinterpret_cast<const unsigned char*>(key.data()),
                              key.size(), params) == 1);
}

MessageTagger::~MessageTagger() = default;

void MessageTagger::TagNext(std::string_view frame, unsigned char* tag) {
  unsigned char sequence[8];
  for (int i = 0; i < 8; ++i) sequence[i] = static_cast<unsigned char>(count_ >> (8 * i));
  size_t length = 0;
  SITLNET_DEMAND(EVP_MAC_init(mac_->context, nullptr, 0, nullptr) == 1);
  SITLNET_DEMAND(EVP_MAC_update(mac_->context, sequence, sizeof sequence) == 1);
  SITLNET_DEMAND(EVP_MAC_update(mac_->context, reinterpret_cast<const unsigned char*>(frame.data()),
                                frame.size()) == 1);
  SITLNET_DEMAND(EVP_MAC_final(mac_->context, tag, &length, kMessageTagBytes) == 1);
  SITLNET_DEMAND(length == kMessageTagBytes);
  ++count_;
}

}  // namespace sitlnet::coordinator
