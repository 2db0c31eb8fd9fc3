// Mutual authentication of a connector and the coordinator with a shared secret
// (docs/coordinator.md, "Authentication"): each side proves it holds the secret with an
// HMAC-SHA256 (OpenSSL's libcrypto) over both sides' random nonces and the handshake's frames so
// far, without sending it; then every
// message of the connection carries a tag under a key derived from the secret and both nonces, so
// an attacker on the path who relayed the handshake cannot change, add, drop, repeat or reorder
// what follows. Nothing is encrypted (docs/security.md).
#ifndef SITLNET_COORDINATOR_AUTHENTICATION_H_
#define SITLNET_COORDINATOR_AUTHENTICATION_H_

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

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

// The keys that tag the messages after the handshake, one per direction:
// HMAC-SHA256(secret, "sitlnet session <direction>" || 0 || coordinator's nonce || connector's
// nonce). Fresh nonces make them new for every connection, so a message of another connection
// never verifies; two directions, so a message cannot be sent back to its sender.
struct SessionKeys {
  std::string coordinator_to_connector;
  std::string connector_to_coordinator;
};
SessionKeys DeriveSessionKeys(const std::string& secret, const std::string& coordinator_nonce,
                              const std::string& connector_nonce);

inline constexpr size_t kMessageTagBytes = 32;

// A running SHA-256 of the handshake's frames, exactly as they crossed (the transcript): the
// proofs and the session keys cover it, so a relay that changes the Hello (its scenario hash,
// role, initial poses) or the Challenge makes both ends' proofs disagree.
class TranscriptHash {
 public:
  TranscriptHash();
  ~TranscriptHash();
  TranscriptHash(const TranscriptHash&) = delete;
  TranscriptHash& operator=(const TranscriptHash&) = delete;
  void Add(std::string_view frame);
  // SHA-256 of the frames added so far (32 bytes); more may be added after.
  std::string Digest() const;

 private:
  struct Sha256;  // OpenSSL's digest state (authentication.cc).
  std::unique_ptr<Sha256> sha_;
};

// Tags the messages of one direction: HMAC-SHA256(key, sequence number as 8 bytes little-endian
// || the message's frame). The sequence numbers count the direction's messages from 0, so a
// message dropped, repeated or moved by someone on the path shifts them and stops verifying.
class MessageTagger {
 public:
  explicit MessageTagger(const std::string& key);
  ~MessageTagger();
  MessageTagger(const MessageTagger&) = delete;
  MessageTagger& operator=(const MessageTagger&) = delete;
  // The tag of the next message (`frame`), kMessageTagBytes written to `tag`; counts it.
  void TagNext(std::string_view frame, unsigned char* tag);
  // Messages tagged so far: the next one's sequence number.
  uint64_t count() const { return count_; }

 private:
  struct Mac;  // OpenSSL's HMAC state, keyed once (authentication.cc).
  std::unique_ptr<Mac> mac_;
  uint64_t count_ = 0;
};

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_AUTHENTICATION_H_
