// Mutual authentication of a connector and the coordinator with a shared secret
// (docs/coordinator.md, "Authentication"): each side proves it holds the secret with an
// HMAC-SHA256 (OpenSSL's libcrypto) over both sides' random nonces, without sending it. It
// authenticates the ends of a connection when it opens; it does not encrypt or protect the
// messages that follow from an attacker on the path (docs/security.md).
#ifndef SITLNET_COORDINATOR_AUTHENTICATION_H_
#define SITLNET_COORDINATOR_AUTHENTICATION_H_

#include <string>

namespace sitlnet::coordinator {

inline constexpr size_t kNonceBytes = 32;
inline constexpr size_t kMinSecretBytes = 16;
inline constexpr size_t kMaxSecretBytes = 4096;

// The secret in `path`: its bytes, 16 to 4096 of them. Throws Error naming the file if it
// cannot be read, is not a regular file, has another owner than this process's user (or, under
// sudo, the user who ran sudo), or can be read or written by its group or others (like ssh with
// a private key).
std::string LoadSecretFile(const std::string& path);

// kNonceBytes from the kernel's random source (getrandom).
std::string RandomNonce();

// HMAC-SHA256(secret, label || 0 || first || second): 32 bytes.
std::string ProofOf(const std::string& secret, const std::string& label, const std::string& first,
                    const std::string& second);

// Constant-time equality of two proofs.
bool SameProof(const std::string& a, const std::string& b);

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_AUTHENTICATION_H_
