#include "physics_mujoco/test/json_client.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>

#include "physics_mujoco/test/test_scenarios.h"

namespace sitlnet::physics::testing {

std::string ServoPacket16(uint16_t frame_rate, uint32_t frame_count, uint16_t pwm_all) {
  std::string bytes(40, '\0');
  auto put16 = [&](int at, uint16_t v) {
    bytes[at] = static_cast<char>(v & 0xff);
    bytes[at + 1] = static_cast<char>(v >> 8);
  };
  put16(0, 18458);
  put16(2, frame_rate);
  for (int i = 0; i < 4; ++i) bytes[4 + i] = static_cast<char>((frame_count >> (8 * i)) & 0xff);
  for (int ch = 0; ch < 16; ++ch) put16(8 + 2 * ch, ch < 4 ? pwm_all : 1500);
  return bytes;
}

std::vector<double> Field(const std::string& json, const std::string& key) {
  const size_t at = json.find("\"" + key + "\":");
  if (at == std::string::npos) return {};
  const char* p = json.c_str() + at + key.size() + 3;
  std::vector<double> values;
  if (*p == '[') ++p;
  for (;;) {
    char* end = nullptr;
    values.push_back(std::strtod(p, &end));
    if (*end != ',' || values.size() == 4 || end[1] == '"') break;
    p = end + 1;
  }
  return values;
}

JsonClient::JsonClient(const char* from, const char* to)
    : fd_(socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0)) {
  sockaddr_in local{};
  local.sin_family = AF_INET;
  inet_pton(AF_INET, from, &local.sin_addr);
  EXPECT_EQ(bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local), 0);
  server_.sin_family = AF_INET;
  server_.sin_port = htons(TestJsonPort());
  inet_pton(AF_INET, to, &server_.sin_addr);
}

JsonClient::~JsonClient() { close(fd_); }

void JsonClient::Send(const std::string& bytes) {
  sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&server_),
         sizeof server_);
}

std::string JsonClient::Receive(int timeout_ms) {
  if (!WaitReadable(fd_, timeout_ms)) return "";
  char buffer[2048];
  const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
  return n > 0 ? std::string(buffer, n) : "";
}

}  // namespace sitlnet::physics::testing
