// ArduPilot's side of the JSON SITL backend for tests, written from ArduPilot's protocol
// description (libraries/SITL/examples/JSON/readme.md): servo packets out, JSON replies in,
// over UDP on loopback.
#ifndef SITLNET_PHYSICS_MUJOCO_TEST_JSON_CLIENT_H_
#define SITLNET_PHYSICS_MUJOCO_TEST_JSON_CLIENT_H_

#include <netinet/in.h>

#include <cstdint>
#include <string>
#include <vector>

namespace sitlnet::physics::testing {

// What arducopter --model JSON:<address> would send: 40 bytes little-endian, the first four
// channels at `pwm_all`, the others at 1500.
std::string ServoPacket16(uint16_t frame_rate, uint32_t frame_count, uint16_t pwm_all);

// Numbers after "key": in the JSON text (ArduPilot matches keys as substrings too); empty when
// the key is missing.
std::vector<double> Field(const std::string& json, const std::string& key);

class JsonClient {
 public:
  // From robot `from`'s ctl0 address to its server's (`to`; robot i's are 127.77.0.(4i+2) and
  // 127.77.0.(4i+1)), on TestJsonPort().
  explicit JsonClient(const char* from, const char* to = "127.77.0.1");
  ~JsonClient();
  JsonClient(const JsonClient&) = delete;
  JsonClient& operator=(const JsonClient&) = delete;

  void Send(const std::string& bytes);
  // One reply, or "" after `timeout_ms`.
  std::string Receive(int timeout_ms = 2000);
  int fd() const { return fd_; }

 private:
  int fd_;
  sockaddr_in server_{};
};

}  // namespace sitlnet::physics::testing

#endif  // SITLNET_PHYSICS_MUJOCO_TEST_JSON_CLIENT_H_
